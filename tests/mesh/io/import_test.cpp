// Import of every supported format (files the test writes itself with Assimp's exporter), repair of
// broken meshes, and clear errors for malformed files.
#include <gtest/gtest.h>

#include <chrono>

#include <assimp/scene.h>
#include <assimp/Exporter.hpp>

#include <filesystem>
#include <fstream>

#include "hapticut/mesh/io/assimp_import.h"
#include "hapticut/mesh/io/mesh_file.h"
#include "hapticut/mesh/mesh_report.h"
#include "hapticut/mesh/procedural/primitives.h"
#include "hapticut/mesh/repair.h"
#include "test_support.h"

namespace hapticut::mesh {
namespace {

namespace fs = std::filesystem;

/// An aiScene the way an exporter expects it: one node per named part under the root, each with its
/// meshes (closed spheres, say), which take the part's name.
struct SceneForExport {
    aiScene scene;
    explicit SceneForExport(const SurfaceMesh& m) : SceneForExport({{"", {m}}}) {}
    explicit SceneForExport(const std::vector<std::pair<std::string, std::vector<SurfaceMesh>>>& parts) {
        scene.mRootNode = new aiNode();
        scene.mMaterials = new aiMaterial* [1] { new aiMaterial() };
        scene.mNumMaterials = 1;
        std::vector<aiMesh*> meshes;
        std::vector<aiNode*> nodes;
        for (const auto& [name, pieces] : parts) {
            auto* node = new aiNode(name);
            node->mParent = scene.mRootNode;
            node->mNumMeshes = static_cast<unsigned>(pieces.size());
            node->mMeshes = new unsigned[pieces.size()];
            for (std::size_t i = 0; i < pieces.size(); ++i) {
                node->mMeshes[i] = static_cast<unsigned>(meshes.size());
                meshes.push_back(toAssimp(pieces[i], name));
            }
            nodes.push_back(node);
        }
        scene.mMeshes = new aiMesh*[meshes.size()];
        std::copy(meshes.begin(), meshes.end(), scene.mMeshes);
        scene.mNumMeshes = static_cast<unsigned>(meshes.size());
        scene.mRootNode->addChildren(static_cast<unsigned>(nodes.size()), nodes.data());
    }

    static aiMesh* toAssimp(const SurfaceMesh& m, const std::string& name) {
        auto* mesh = new aiMesh();
        mesh->mName = aiString(name);
        mesh->mMaterialIndex = 0;
        mesh->mPrimitiveTypes = aiPrimitiveType_TRIANGLE;
        mesh->mNumVertices = static_cast<unsigned>(m.positions.size());
        mesh->mVertices = new aiVector3D[mesh->mNumVertices];
        for (unsigned i = 0; i < mesh->mNumVertices; ++i) {
            const Vec3& p = m.positions[i];
            mesh->mVertices[i] =
                aiVector3D(static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z()));
        }
        mesh->mNumFaces = static_cast<unsigned>(m.faces.size());
        mesh->mFaces = new aiFace[mesh->mNumFaces];
        for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
            mesh->mFaces[f].mNumIndices = 3;
            mesh->mFaces[f].mIndices = new unsigned[3]{m.faces[f][0], m.faces[f][1], m.faces[f][2]};
        }
        return mesh;
    }
};

class Import : public ::testing::Test {
protected:
    test::ScratchDir scratch_;
    const fs::path& dir_ = scratch_.path();
};

TEST_F(Import, EveryFormatGivesTheSameMeshAfterWelding) {
    const SurfaceMesh sphere = procedural::makeSphere(Vec3::Zero(), 0.05, 12, 8);
    SceneForExport source(sphere);
    Assimp::Exporter exporter;
    const struct {
        const char* id;
        const char* ext;
    } formats[] = {{"stl", "stl"},    {"stlb", "stl"}, {"obj", "obj"},     {"ply", "ply"}, {"plyb", "ply"},
                   {"gltf2", "gltf"}, {"glb2", "glb"}, {"collada", "dae"}, {"3ds", "3ds"}, {"fbxa", "fbx"}};
    for (const auto& format : formats) {
        const fs::path file = dir_ / (std::string("sphere-") + format.id + "." + format.ext);
        ASSERT_EQ(exporter.Export(&source.scene, format.id, file.string()), AI_SUCCESS)
            << format.id << ": " << exporter.GetErrorString();
        auto loaded = io::loadMesh(file);
        ASSERT_TRUE(loaded.has_value()) << format.id << ": " << loaded.error().toString();
        // Our own OBJ and PLY readers keep vertices as written; Assimp's exporters may split them.
        cleanMesh(loaded->mesh);
        const MeshReport r = validateMesh(loaded->mesh);
        EXPECT_EQ(r.vertices, sphere.positions.size()) << format.id;
        EXPECT_EQ(r.faces, sphere.faces.size()) << format.id;
        EXPECT_TRUE(r.closed) << format.id;
        EXPECT_TRUE(r.manifold) << format.id;
        EXPECT_EQ(r.components, 1u) << format.id;
        EXPECT_NEAR(r.bboxMax.x(), 0.05, 1e-6) << format.id;
    }
}

// An atlas's organ comes as named meshes, one node each: each is a part, by its name, with its own
// faces; a part of two pieces (a glTF mesh of two primitives, which Assimp names "atria-0" and
// "atria-1") is still one part.
TEST_F(Import, NamedMeshesOfGltfFbxAndColladaAreTheModelsParts) {
    const SurfaceMesh ventricle = procedural::makeSphere(Vec3::Zero(), 0.04, 12, 8);
    const SurfaceMesh left = procedural::makeSphere(Vec3(-0.02, 0.07, 0), 0.015, 8, 6);
    const SurfaceMesh right = procedural::makeSphere(Vec3(0.02, 0.07, 0), 0.015, 8, 6);
    SceneForExport source({{"left ventricle", {ventricle}}, {"atria", {left, right}}});
    Assimp::Exporter exporter;
    for (const auto& [id, ext] : {std::pair{"gltf2", "gltf"}, {"glb2", "glb"}, {"fbxa", "fbx"}, {"collada", "dae"}}) {
        const fs::path file = dir_ / (std::string("heart-") + id + "." + ext);
        ASSERT_EQ(exporter.Export(&source.scene, id, file.string()), AI_SUCCESS)
            << id << ": " << exporter.GetErrorString();
        auto loaded = io::loadMesh(file);
        ASSERT_TRUE(loaded.has_value()) << id << ": " << loaded.error().toString();
        const SurfaceMesh& m = loaded->mesh;
        ASSERT_EQ(m.partNames, (std::vector<std::string>{"left ventricle", "atria"})) << id;
        ASSERT_EQ(m.faceParts.size(), m.faces.size()) << id;
        std::vector<std::size_t> faces(2, 0);
        for (std::size_t f = 0; f < m.faces.size(); ++f) {
            ++faces[m.faceParts[f]];
            // Every face of a part lies on its own spheres.
            const double y =
                (m.positions[m.faces[f][0]] + m.positions[m.faces[f][1]] + m.positions[m.faces[f][2]]).y() / 3;
            EXPECT_EQ(y > 0.045, m.faceParts[f] == 1) << id << " face " << f;
        }
        EXPECT_EQ(faces[0], ventricle.faces.size()) << id;
        EXPECT_EQ(faces[1], left.faces.size() + right.faces.size()) << id;
    }
}

// A node's placement moves its meshes into the scene; a mirroring one leaves their faces outward.
TEST_F(Import, NodesPlaceTheirMeshesAndAMirrorKeepsFacesOutward) {
    SceneForExport source({{"moved", {procedural::makeSphere(Vec3::Zero(), 0.03, 12, 8)}},
                           {"mirrored", {procedural::makeSphere(Vec3(0.05, 0, 0), 0.02, 12, 8)}}});
    aiMatrix4x4::Translation(aiVector3D(0, 0.1f, 0), source.scene.mRootNode->mChildren[0]->mTransformation);
    aiMatrix4x4::Scaling(aiVector3D(-1, 1, 1), source.scene.mRootNode->mChildren[1]->mTransformation);
    Assimp::Exporter exporter;
    const fs::path file = dir_ / "placed.glb";
    ASSERT_EQ(exporter.Export(&source.scene, "glb2", file.string()), AI_SUCCESS) << exporter.GetErrorString();
    auto loaded = io::loadMesh(file);
    ASSERT_TRUE(loaded.has_value()) << loaded.error().toString();
    ASSERT_EQ(loaded->mesh.partNames, (std::vector<std::string>{"moved", "mirrored"}));
    for (std::uint32_t part = 0; part < 2; ++part) {
        SurfaceMesh piece = loaded->mesh;
        keepFaces(piece, [&](std::size_t f) { return piece.faceParts[f] == part; });
        cleanMesh(piece);
        const MeshReport r = validateMesh(piece);
        const Vec3 centre = (r.bboxMin + r.bboxMax) / 2;
        EXPECT_TRUE(centre.isApprox(part == 0 ? Vec3(0, 0.1, 0) : Vec3(-0.05, 0, 0), 1e-5)) << centre.transpose();
        EXPECT_GT(test::signedVolume(piece), 0) << loaded->mesh.partNames[part] << " faces outward";
    }
}

TEST_F(Import, MalformedFilesOfEachFormatGiveClearErrors) {
    for (const char* ext : {"stl", "gltf", "glb", "dae", "3ds", "fbx"}) {
        for (const std::string& content :
             {std::string(), std::string("solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0"),
              std::string("\x01\x02garbage\xff\xfe", 12)}) {
            const fs::path file = dir_ / (std::string("bad.") + ext);
            std::ofstream(file, std::ios::binary) << content;
            const auto loaded = io::loadMesh(file);
            ASSERT_FALSE(loaded.has_value()) << ext << " accepted " << content.size() << " bytes of garbage";
            EXPECT_EQ(loaded.error().file, file);
            EXPECT_FALSE(loaded.error().message.empty());
        }
    }
    const auto missing = io::loadMesh(dir_ / "missing.stl");
    ASSERT_FALSE(missing.has_value());
    EXPECT_NE(missing.error().message.find("no such file"), std::string::npos);
    // A valid glTF whose scene holds no mesh: the importer gives no reason, so we say what is missing.
    std::ofstream(dir_ / "empty.gltf") << R"({"asset":{"version":"2.0"},"scenes":[{"nodes":[]}],"scene":0})";
    const auto empty = io::loadMesh(dir_ / "empty.gltf");
    ASSERT_FALSE(empty.has_value());
    EXPECT_NE(empty.error().message.find("no mesh in the file"), std::string::npos) << empty.error().toString();
}

// A file past the importer's limit is refused by its size before Assimp reads it into memory (a sparse
// file: no disk is used), and so is one past our own readers' limit.
TEST_F(Import, AFileTooLargeToImportIsRefusedByItsSizeBeforeItIsRead) {
    for (const char* name : {"huge.stl", "huge.obj"}) {
        const fs::path file = dir_ / name;
        std::ofstream(file) << "solid huge\n";
        fs::resize_file(file,
                        std::string(name) == "huge.stl" ? io::kMaxImportBytes + 1 : (std::uintmax_t{4} << 30) + 1);
        const auto start = std::chrono::steady_clock::now();
        const auto loaded = io::loadMesh(file);
        ASSERT_FALSE(loaded.has_value());
        EXPECT_EQ(loaded.error().file, file);
        EXPECT_NE(loaded.error().message.find("bytes, more than the"), std::string::npos) << loaded.error().toString();
        EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 5)
            << "refused by its size, not after reading gigabytes";
    }
}

TEST(Repair, WeldsDuplicateVerticesAndDropsDuplicateAndDegenerateFaces) {
    SurfaceMesh m = test::tetrahedron();
    // Every corner its own vertex, as STL stores it, plus a repeated and a degenerate face.
    SurfaceMesh soup;
    for (const Face& f : m.faces) {
        const auto base = static_cast<std::uint32_t>(soup.positions.size());
        for (std::uint32_t v : f) soup.positions.push_back(m.positions[v]);
        soup.faces.push_back({base, base + 1, base + 2});
    }
    soup.faces.push_back(soup.faces[0]);
    soup.faces.push_back({0, 1, 1});
    completeMesh(soup);
    const RepairReport r = cleanMesh(soup);
    EXPECT_EQ(r.weldedVertices, 8u);
    EXPECT_EQ(r.duplicateFaces, 1u);
    EXPECT_EQ(r.degenerateFaces, 1u);
    EXPECT_TRUE(r.generatedUvs);
    const MeshReport after = validateMesh(soup);
    EXPECT_EQ(after.vertices, 4u);
    EXPECT_EQ(after.faces, 4u);
    EXPECT_TRUE(after.closed);
}

// Found by the import fuzzer: an STL whose corners all lie at one point gives a weld tolerance of zero,
// and its cells' numbers ran past the range of an integer. Every vertex far outside the cell grid welds
// with its equals only.
TEST(Repair, WeldsVerticesFarOutsideTheCellGrid) {
    SurfaceMesh point;
    point.positions.assign(6, Vec3(0, 0.05, 0));
    point.faces = {{0, 1, 2}, {3, 4, 5}};
    completeMesh(point);
    const RepairReport r = cleanMesh(point);
    EXPECT_EQ(r.weldedVertices, 5u);
    EXPECT_EQ(r.degenerateFaces, 2u);
    EXPECT_TRUE(point.faces.empty());

    SurfaceMesh far = test::tetrahedron();
    for (Vec3& p : far.positions) p = p * 1e290 + Vec3(-1e300, 1e300, 0);
    far.positions.push_back(far.positions[0]);
    far.faces.push_back({4, 1, 2});
    completeMesh(far);
    EXPECT_EQ(cleanMesh(far, {.weldEpsilon_m = 1e-12}).weldedVertices, 1u) << "only the copy, not its far neighbours";
    EXPECT_EQ(far.positions.size(), 4u);
}

TEST(Repair, OrientsFlippedFacesOutward) {
    SurfaceMesh m = test::tetrahedron();
    std::swap(m.faces[1][1], m.faces[1][2]);
    std::swap(m.faces[3][1], m.faces[3][2]);
    for (Face& f : m.faces) std::swap(f[1], f[2]);  // and everything inside out
    EXPECT_FALSE(validateMesh(m).oriented);
    const RepairReport r = cleanMesh(m, {.repair = true});
    EXPECT_GT(r.flippedFaces, 0u);
    EXPECT_TRUE(validateMesh(m).oriented);
    EXPECT_GT(test::signedVolume(m), 0) << "outward";
}

// A file exported inside out loads outward: every closed piece that agrees within itself but faces
// inward is turned, far from the origin too (a segmentation's body coordinates); an open patch, a piece
// already outward and one that disagrees within itself are left alone, and the parts turned are named.
TEST(Repair, TurnsClosedPiecesThatCameInsideOutOutward) {
    SurfaceMesh m;
    auto part = [&](const SurfaceMesh& piece, const std::string& name, bool insideOut) {
        SurfaceMesh p = piece;
        if (insideOut)
            for (Face& f : p.faces) std::swap(f[1], f[2]);
        const std::size_t first = m.faces.size();
        procedural::appendMesh(m, p);
        m.partNames.push_back(name);
        m.faceParts.resize(m.faces.size(), static_cast<std::uint32_t>(m.partNames.size() - 1));
        return std::pair{first, m.faces.size()};
    };
    const auto ball = part(procedural::makeSphere(Vec3(0.3, 0.2, 0.1), 0.01, 16, 8), "gallbladder", true);
    const auto liver = part(procedural::makeSphere(Vec3(0.35, 0.2, 0.1), 0.02, 24, 12), "liver", false);
    const auto patch = part(procedural::makeGrid(4, 0.01), "sheet", true);
    SurfaceMesh mixed = procedural::makeSphere(Vec3(0.3, 0.3, 0.1), 0.01, 12, 6);
    for (Face& f : mixed.faces) std::swap(f[1], f[2]);
    std::swap(mixed.faces[0][1], mixed.faces[0][2]);  // one face disagrees: --repair's to sort out
    const auto disagreeing = part(mixed, "cyst", false);
    const SurfaceMesh before = m;

    const TurnedOutward turned = turnInsideOutPiecesOutward(m);
    EXPECT_EQ(turned.pieces, 1u);
    EXPECT_EQ(turned.faces, ball.second - ball.first);
    EXPECT_EQ(turned.parts, std::vector<std::string>{"gallbladder"});
    auto volumeOf = [&](std::pair<std::size_t, std::size_t> range) {
        SurfaceMesh piece = m;
        piece.faces.assign(m.faces.begin() + static_cast<long>(range.first),
                           m.faces.begin() + static_cast<long>(range.second));
        return test::signedVolume(piece);
    };
    EXPECT_GT(volumeOf(ball), 0) << "turned outward";
    EXPECT_GT(volumeOf(liver), 0);
    for (auto range : {liver, patch, disagreeing})
        for (std::size_t f = range.first; f < range.second; ++f) EXPECT_EQ(m.faces[f], before.faces[f]) << f;
    ASSERT_EQ(m.normals.size(), m.faces.size());
    EXPECT_GT(m.normals[ball.first].dot(m.positions[m.faces[ball.first][0]] - Vec3(0.3, 0.2, 0.1)), 0)
        << "its normals recomputed, pointing out";
    EXPECT_EQ(turnInsideOutPiecesOutward(m).pieces, 0u) << "nothing left to turn";
}

TEST(Repair, PartsAFinFromTheEdgeItSharesWithAClosedPiece) {
    SurfaceMesh m = test::tetrahedron();
    m.positions.push_back(Vec3(2, 2, -2));
    m.faces.push_back({1, 0, 4});  // a fin on edge (0, 1): three faces share it
    completeMesh(m);
    m.edges = edgesOfFaces(m.faces);
    ASSERT_EQ(validateMesh(m).nonManifoldEdges, 1u);
    const RepairReport r = cleanMesh(m, {.repair = true, .minComponentShare = 0});
    EXPECT_EQ(r.separatedVertices, 2u) << "the fin is a piece of its own, parted at both ends of the edge";
    const MeshReport after = validateMesh(m);
    EXPECT_TRUE(after.manifold);
    EXPECT_EQ(after.faces, 5u);
    EXPECT_EQ(after.boundaryEdges, 3u) << "the tetrahedron stays closed; only the fin is open";
}

TEST(Repair, PartsPiecesTouchingAtAVertex) {
    // Two tetrahedra touching at one corner (a bowtie vertex): after the split, two separate pieces.
    SurfaceMesh m = test::tetrahedron();
    SurfaceMesh other = test::tetrahedron();
    for (Vec3& p : other.positions) p = Vec3(2, 2, 2) - (p - Vec3(1, 1, 1));  // mirrored through vertex 0 at (1, 1, 1)
    procedural::appendMesh(m, other);
    for (Face& f : m.faces)
        for (std::uint32_t& v : f)
            if (v == 4) v = 0;  // share the corner
    completeMesh(m);
    m.edges = edgesOfFaces(m.faces);
    ASSERT_EQ(validateMesh(m).vertices - validateMesh(m).unusedVertices, 7u) << "joined at one shared vertex";
    const RepairReport r = cleanMesh(m, {.repair = true, .minComponentShare = 0});
    EXPECT_EQ(r.separatedVertices, 1u);
    const MeshReport after = validateMesh(m);
    EXPECT_EQ(after.vertices, 8u);
    EXPECT_EQ(after.eulerCharacteristic, 4) << "two spheres";
    EXPECT_TRUE(after.closed);
    EXPECT_TRUE(after.oriented);
}

TEST(Repair, RemovesSmallFragmentsButKeepsTheLargestPiece) {
    // A sphere of 160 faces with a stray 4-face fragment: 2.4% of the faces, below a 5% share.
    SurfaceMesh m = procedural::makeSphere(Vec3::Zero(), 0.05, 10, 9);
    SurfaceMesh fragment = test::tetrahedron();
    for (Vec3& p : fragment.positions) p = 0.001 * p + Vec3(0.2, 0, 0);
    procedural::appendMesh(m, fragment);
    ASSERT_EQ(validateMesh(m).components, 2u);
    const RepairReport r = cleanMesh(m, {.repair = true, .minComponentShare = 0.05});
    EXPECT_EQ(r.removedComponents, 1u);
    EXPECT_EQ(r.removedComponentFaces, 4u);
    const MeshReport after = validateMesh(m);
    EXPECT_EQ(after.components, 1u);
    EXPECT_EQ(after.unusedVertices, 0u);
    EXPECT_TRUE(after.closed);
    // A single piece is never removed, however small the share.
    SurfaceMesh alone = test::tetrahedron();
    EXPECT_EQ(cleanMesh(alone, {.repair = true, .minComponentShare = 0.99}).removedComponents, 0u);
}

TEST(Repair, FitsTheUnitBox) {
    SurfaceMesh m = procedural::makeSphere(Vec3(3, 4, 5), 2.0, 10, 6);
    fitUnitBox(m);
    const MeshReport r = validateMesh(m);
    EXPECT_NEAR((r.bboxMax - r.bboxMin).maxCoeff(), 1.0, 1e-12);
    EXPECT_LT(((r.bboxMax + r.bboxMin) / 2).norm(), 1e-12);
}

}  // namespace
}  // namespace hapticut::mesh
