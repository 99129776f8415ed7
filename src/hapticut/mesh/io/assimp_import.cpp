// Import through Assimp.
#include "hapticut/mesh/io/assimp_import.h"

#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <assimp/Importer.hpp>

#include <algorithm>
#include <cmath>
#include <string>

#include "hapticut/mesh/io/imported_mesh.h"

namespace hapticut::mesh::io {

bool assimpCanImport(const std::filesystem::path& file) {
    const std::string ext = file.extension().string();
    if (ext.size() < 2) return false;
    Assimp::Importer importer;
    return importer.IsExtensionSupported(ext);
}

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
        // No vertex joining here: welding is ours, with a tolerance the user controls.
        const aiScene* scene = importer.ReadFile(
            file.string(), aiProcess_Triangulate | aiProcess_PreTransformVertices | aiProcess_SortByPType);
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
        for (unsigned mi = 0; mi < scene->mNumMeshes; ++mi) {
            const aiMesh* mesh = scene->mMeshes[mi];
            const auto base = static_cast<std::uint32_t>(m.positions.size());
            // Each named mesh is a part; the pieces of one (a glTF mesh's primitives) share its name.
            const std::string name = mesh->mName.C_Str();
            auto named = std::find(m.partNames.begin(), m.partNames.end(), name);
            if (name.empty() || named == m.partNames.end()) named = m.partNames.insert(m.partNames.end(), name);
            const auto part = static_cast<std::uint32_t>(named - m.partNames.begin());
            for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
                const aiVector3D& p = mesh->mVertices[v];
                if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) ++nonFinite;
                m.positions.emplace_back(p.x, p.y, p.z);
            }
            const aiVector3D* uv = mesh->HasTextureCoords(0) ? mesh->mTextureCoords[0] : nullptr;
            for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
                const aiFace& face = mesh->mFaces[f];
                if (face.mNumIndices != 3) {
                    ++skippedPrimitives;  // points and lines carry no surface
                    continue;
                }
                m.faces.push_back({base + face.mIndices[0], base + face.mIndices[1], base + face.mIndices[2]});
                m.faceParts.push_back(part);
                FaceUvs corners{Vec2::Zero(), Vec2::Zero(), Vec2::Zero()};
                if (uv)
                    for (int k = 0; k < 3; ++k) corners[k] = Vec2(uv[face.mIndices[k]].x, uv[face.mIndices[k]].y);
                m.uvs.push_back(corners);
            }
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
