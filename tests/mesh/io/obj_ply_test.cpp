// OBJ and PLY: round trips that keep vertex identity and per-corner UVs, binary PLY, and errors.
#include <gtest/gtest.h>

#include <bit>
#include <cstring>

#include "hapticut/mesh/io/mesh_file.h"
#include "hapticut/mesh/io/obj_format.h"
#include "hapticut/mesh/io/ply_format.h"
#include "hapticut/mesh/procedural/heart.h"
#include "test_support.h"

namespace hapticut::mesh::io {
namespace {

void expectSameSurface(const SurfaceMesh& a, const SurfaceMesh& b) {
    EXPECT_EQ(a.positions, b.positions);
    EXPECT_EQ(a.faces, b.faces);
    EXPECT_EQ(a.uvs, b.uvs);
    EXPECT_EQ(edgesOfFaces(a.faces), edgesOfFaces(b.faces));
}

TEST(ObjFormat, RoundTripKeepsVerticesFacesAndSeamUvs) {
    SurfaceMesh heart = procedural::makeHeart({});
    // Two coincident vertices, as an opened cut has, must stay two vertices.
    heart.positions.push_back(heart.positions[heart.faces[0][0]]);
    heart.faces[0][0] = static_cast<std::uint32_t>(heart.positions.size() - 1);
    const auto parsed = parseObj(formatObj(heart), "heart.obj");
    ASSERT_TRUE(parsed.has_value()) << parsed.error().toString();
    expectSameSurface(parsed->mesh, heart);
}

TEST(ObjFormat, NamedPartsRoundTripSpacesAndAll) {
    SurfaceMesh heart = procedural::makeHeart({.triangles = 200});
    heart.partNames = {"left ventricle", "atria"};
    heart.faceParts.assign(heart.faces.size(), 0);
    for (std::size_t f = heart.faces.size() / 2; f < heart.faces.size(); ++f) heart.faceParts[f] = 1;
    const auto parsed = parseObj(formatObj(heart), "heart.obj");
    ASSERT_TRUE(parsed.has_value()) << parsed.error().toString();
    expectSameSurface(parsed->mesh, heart);
    EXPECT_EQ(parsed->mesh.partNames, heart.partNames);
    EXPECT_EQ(parsed->mesh.faceParts, heart.faceParts);
    // A group line lists groups: the first names the part. An object's name is the whole line.
    const auto groups =
        parseObj("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\ng wall septum\nf 1 2 3\no right atrium \r\nf 1 2 4\n", "g.obj");
    ASSERT_TRUE(groups.has_value()) << groups.error().toString();
    EXPECT_EQ(groups->mesh.partNames, (std::vector<std::string>{"wall", "right atrium"}));
}

TEST(ObjFormat, ReadsPolygonsNegativeIndicesAndIgnoresOtherStatements) {
    const std::string text =
        "mtllib a.mtl\no quad\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0 1.0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\n"
        "usemtl red\ns off\nf -4/1/1 -3/2/1 -2/3/1 -1/4/1\n";
    const auto parsed = parseObj(text, "quad.obj");
    ASSERT_TRUE(parsed.has_value()) << parsed.error().toString();
    EXPECT_EQ(parsed->mesh.faces.size(), 2u);
    EXPECT_EQ(parsed->mesh.edges.size(), 5u);
    EXPECT_EQ(parsed->mesh.uvs[1][2], Vec2(0, 1));
}

TEST(ObjFormat, ErrorsNameTheLine) {
    auto expectError = [](const std::string& text, int line, const std::string& fragment) {
        test::expectError(parseObj(text, "bad.obj"), line, fragment);
    };
    expectError("v 0 0 0\nv 1 0 0\nf 1 2 3\n", 3, "vertex index 3 is out of range: 2 defined so far");
    expectError("v 0 0 nan\n", 1, "expected a finite number for z");
    expectError("v 0 0\n", 1, "expected 'v <x> <y> <z>'");
    expectError("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n", 4, "at least 3 corners");
    expectError("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 x 3\n", 4, "expected a vertex index");
    expectError("v 0 0 0\n", 0, "no faces found");
    expectError("", 0, "no faces found");
}

TEST(ObjFormat, DropsDegenerateFacesWithAWarning) {
    const auto parsed = parseObj("v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 4\nf 1 1 4\n", "flat.obj");
    ASSERT_TRUE(parsed.has_value());
    EXPECT_EQ(parsed->mesh.faces.size(), 1u);
    ASSERT_EQ(parsed->warnings.size(), 1u);
    EXPECT_NE(parsed->warnings[0].message.find("dropped 2 degenerate"), std::string::npos);
}

TEST(PlyFormat, AsciiRoundTripKeepsVerticesFacesAndUvs) {
    const SurfaceMesh heart = procedural::makeHeart({});
    const auto parsed = parsePly(formatPly(heart), "heart.ply");
    ASSERT_TRUE(parsed.has_value()) << parsed.error().toString();
    expectSameSurface(parsed->mesh, heart);
}

template <class T>
void put(std::string& out, T value, bool big_endian) {
    char b[sizeof(T)];
    std::memcpy(b, &value, sizeof(T));
    if (big_endian == (std::endian::native == std::endian::little)) std::reverse(b, b + sizeof(T));
    out.append(b, sizeof(T));
}

std::string binaryTetra(bool big_endian) {
    const SurfaceMesh t = test::tetrahedron();
    std::string out =
        std::string("ply\nformat ") + (big_endian ? "binary_big_endian" : "binary_little_endian") +
        " 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\nproperty uchar red\n"
        "element face 4\nproperty list uchar int vertex_indices\nend_header\n";
    for (const Vec3& p : t.positions) {
        for (int k = 0; k < 3; ++k) put(out, static_cast<float>(p[k]), big_endian);
        put(out, std::uint8_t{200}, big_endian);
    }
    for (const Face& f : t.faces) {
        put(out, std::uint8_t{3}, big_endian);
        for (std::uint32_t v : f) put(out, static_cast<std::int32_t>(v), big_endian);
    }
    return out;
}

TEST(PlyFormat, ReadsBinaryInBothByteOrders) {
    for (bool big : {false, true}) {
        const auto parsed = parsePly(binaryTetra(big), "tetra.ply");
        ASSERT_TRUE(parsed.has_value()) << parsed.error().toString();
        EXPECT_EQ(parsed->mesh.faces, test::tetrahedron().faces);
        EXPECT_EQ(parsed->mesh.positions, test::tetrahedron().positions);
    }
}

TEST(PlyFormat, ErrorsAreClear) {
    auto expectError = [](const std::string& text, const std::string& fragment) {
        const auto r = parsePly(text, "bad.ply");
        ASSERT_FALSE(r.has_value()) << fragment;
        EXPECT_NE(r.error().message.find(fragment), std::string::npos) << r.error().toString();
    };
    expectError("obj\n", "expected 'ply'");
    expectError("ply\nformat ascii 1.0\nelement vertex 3\n", "no 'end_header'");
    expectError("ply\nformat ascii 1.0\nelement vertex 99999999\nproperty float x\nend_header\n1\n",
                "larger than the file could hold");
    const std::string truncated = binaryTetra(false);
    expectError(truncated.substr(0, truncated.size() - 5), "unexpected end of binary data");
    expectError(
        "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\nelement face "
        "1\n"
        "property list uchar int vertex_indices\nend_header\n0 0 0\n3 0 0 5\n",
        "vertex index 5 is out of range");
    expectError("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nend_header\n0 0\n",
                "needs x, y and z");
    // Found by the fuzzer: a face element without an index list used to index an empty vertex array.
    expectError("ply\nformat ascii 1.0\nelement face 1\nproperty list uchar int vertex_ind\nend_header\n3 0 1 2\n",
                "needs a list property 'vertex_indices'");
}

TEST(MeshFile, LoadsByExtensionAndRefusesUnknownOnes) {
    const test::ScratchDir dir;
    const SurfaceMesh t = test::tetrahedron();
    for (const char* name : {"t.txt", "t.obj", "t.PLY"}) {
        const auto file = dir / name;
        ASSERT_FALSE(saveMesh(file, t, ThesisPhysics{.mass = 1}).has_value());
        const auto loaded = loadMesh(file);
        ASSERT_TRUE(loaded.has_value()) << loaded.error().toString();
        EXPECT_EQ(loaded->mesh.faces, t.faces) << name;
        EXPECT_EQ(loaded->physics.has_value(), std::string(name) == "t.txt");
    }
    const auto unknown = loadMesh(dir / "t.xyzzy");
    ASSERT_FALSE(unknown.has_value());
    EXPECT_NE(unknown.error().message.find("unknown mesh format '.xyzzy'"), std::string::npos);
}

}  // namespace
}  // namespace hapticut::mesh::io
