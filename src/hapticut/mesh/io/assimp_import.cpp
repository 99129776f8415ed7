// Import through Assimp.
#include "hapticut/mesh/io/assimp_import.h"

#include <assimp/config.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <assimp/Importer.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "hapticut/mesh/io/imported_mesh.h"

namespace hapticut::mesh::io {

bool assimpCanImport(const std::filesystem::path& file) {
    const std::string ext = file.extension().string();
    if (ext.size() < 2) return false;
    Assimp::Importer importer;
    return importer.IsExtensionSupported(ext);
}

namespace {

/// "atria-12" without its "-12"; any other name as it is.
std::string_view withoutNumber(std::string_view name) {
    const std::size_t dash = name.rfind('-');
    if (dash == std::string_view::npos || dash == 0 || dash + 1 == name.size()) return name;
    const std::string_view number = name.substr(dash + 1);
    return std::all_of(number.begin(), number.end(), [](char c) { return c >= '0' && c <= '9'; }) ? name.substr(0, dash)
                                                                                                  : name;
}

/// The part the node's i-th mesh belongs to: the mesh's name, or the node's when it has none. Assimp
/// splits a glTF mesh of several primitives (a material each) into meshes "name-0", "name-1", ..., all
/// in one node: those are one part, "name".
std::string partName(const aiScene& scene, const aiNode& node, unsigned i) {
    const auto meshName = [&](unsigned k) { return std::string_view(scene.mMeshes[node.mMeshes[k]]->mName.C_Str()); };
    const std::string_view own = meshName(i);
    if (own.empty()) return node.mName.C_Str();
    if (node.mNumMeshes < 2) return std::string(own);
    const std::string_view base = withoutNumber(own);
    for (unsigned k = 0; k < node.mNumMeshes; ++k)
        if (node.mMeshes[k] >= scene.mNumMeshes || meshName(k) == base || withoutNumber(meshName(k)) != base)
            return std::string(own);
    return std::string(base);
}

}  // namespace

Result<ImportedMesh, Error> importWithAssimp(const std::filesystem::path& file) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(file, ec)) return unexpected(Error{file, 0, "cannot open: no such file"});
    // Assimp reads the whole file into memory and then builds its scene beside it: a file larger than our
    // own readers take is refused before it starts, with its size, not after minutes of swapping.
    if (const std::uintmax_t bytes = std::filesystem::file_size(file, ec); !ec && bytes > kMaxImportBytes)
        return unexpected(Error{file, 0,
                                "file is " + std::to_string(bytes) + " bytes, more than the " +
                                    std::to_string(kMaxImportBytes) +
                                    " this importer accepts (about 40 million triangles of binary STL)"});
    try {
        Assimp::Importer importer;
        // No vertex joining here: welding is ours, with a tolerance the user controls. Nor Assimp's
        // pre-transform step: it joins the meshes that share a material, and an atlas's chambers and
        // valves often share one, so their names, our parts, would be lost. The node graph is walked here.
        // A Collada file's names are what its author wrote ("left ventricle"), its ids are mangled
        // ("leftWventricle_1"); the names are the parts' names.
        importer.SetPropertyBool(AI_CONFIG_IMPORT_COLLADA_USE_COLLADA_NAMES, true);
        const aiScene* scene = importer.ReadFile(file.string(), aiProcess_Triangulate | aiProcess_SortByPType);
        if (!scene || (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE)) {
            // Assimp flags a scene without geometry as incomplete and gives no reason.
            const char* reason = importer.GetErrorString();
            if (!reason[0] && scene && scene->mNumMeshes == 0)
                return unexpected(Error{file, 0, "no mesh in the file: its scene has no geometry"});
            return unexpected(
                Error{file, 0, std::string("cannot import: ") + (reason[0] ? reason : "the importer gave no reason")});
        }
        ImportedMesh out;
        SurfaceMesh& m = out.mesh;
        std::size_t skippedPrimitives = 0, nonFinite = 0;
        const auto addMesh = [&](const aiMesh* mesh, const aiMatrix4x4& toScene, const std::string& name) {
            const auto base = static_cast<std::uint32_t>(m.positions.size());
            auto named = std::find(m.partNames.begin(), m.partNames.end(), name);
            if (name.empty() || named == m.partNames.end()) named = m.partNames.insert(m.partNames.end(), name);
            const auto part = static_cast<std::uint32_t>(named - m.partNames.begin());
            for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
                const aiVector3D p = toScene * mesh->mVertices[v];
                if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) ++nonFinite;
                m.positions.emplace_back(p.x, p.y, p.z);
            }
            // A mirroring placement turns the faces inside out; their corners are swapped back.
            const bool mirrored = toScene.Determinant() < 0;
            const aiVector3D* uv = mesh->HasTextureCoords(0) ? mesh->mTextureCoords[0] : nullptr;
            for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
                const aiFace& face = mesh->mFaces[f];
                if (face.mNumIndices != 3) {
                    ++skippedPrimitives;  // points and lines carry no surface
                    continue;
                }
                std::array<unsigned, 3> corner{face.mIndices[0], face.mIndices[1], face.mIndices[2]};
                if (mirrored) std::swap(corner[1], corner[2]);
                m.faces.push_back({base + corner[0], base + corner[1], base + corner[2]});
                m.faceParts.push_back(part);
                FaceUvs corners{Vec2::Zero(), Vec2::Zero(), Vec2::Zero()};
                if (uv)
                    for (int k = 0; k < 3; ++k) corners[k] = Vec2(uv[corner[k]].x, uv[corner[k]].y);
                m.uvs.push_back(corners);
            }
        };
        // Every mesh as each node places it, in the file's order, without recursion (a file may nest
        // its nodes as deep as it likes) and with a bound on what instancing can multiply a file into.
        std::vector<std::pair<const aiNode*, aiMatrix4x4>> nodes;
        if (scene->mRootNode) nodes.emplace_back(scene->mRootNode, scene->mRootNode->mTransformation);
        while (!nodes.empty()) {
            const auto [node, toScene] = nodes.back();
            nodes.pop_back();
            for (unsigned i = 0; i < node->mNumMeshes; ++i) {
                if (node->mMeshes[i] >= scene->mNumMeshes) continue;
                const aiMesh* mesh = scene->mMeshes[node->mMeshes[i]];
                if (m.positions.size() + mesh->mNumVertices > kMaxImportVertices)
                    return unexpected(Error{file, 0,
                                            "its nodes place its meshes into more than " +
                                                std::to_string(kMaxImportVertices) +
                                                " vertices, more than this "
                                                "importer accepts"});
                addMesh(mesh, toScene, partName(*scene, *node, i));
            }
            for (unsigned c = node->mNumChildren; c-- > 0;)
                if (node->mChildren[c])
                    nodes.emplace_back(node->mChildren[c], toScene * node->mChildren[c]->mTransformation);
        }
        if (nonFinite > 0)
            return unexpected(Error{file, 0, std::to_string(nonFinite) + " vertex coordinate(s) are NaN or infinite"});
        if (m.faces.empty())
            return unexpected(
                Error{file, 0, "no triangles found (" + std::to_string(scene->mNumMeshes) + " mesh(es) in the file)"});
        if (skippedPrimitives > 0)
            out.warnings.push_back(
                {file, 0, "skipped " + std::to_string(skippedPrimitives) + " point or line primitive(s)"});
        nameParts(m, file.stem().string());
        completeMesh(m);
        return out;
    } catch (const std::exception& e) {
        return unexpected(Error{file, 0, std::string("cannot import: ") + e.what()});
    }
}

}  // namespace hapticut::mesh::io
