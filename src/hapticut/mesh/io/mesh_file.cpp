// Loading and saving meshes by file extension.
#include "hapticut/mesh/io/mesh_file.h"

#include <algorithm>
#include <cctype>

#include "hapticut/mesh/io/assimp_import.h"
#include "hapticut/mesh/io/obj_format.h"
#include "hapticut/mesh/io/ply_format.h"
#include "hapticut/mesh/repair.h"

namespace hapticut::mesh::io {

std::optional<MeshFormat> formatFromExtension(const std::filesystem::path& file) {
    std::string ext = file.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (ext == ".txt") return MeshFormat::Thesis;
    if (ext == ".obj") return MeshFormat::Obj;
    if (ext == ".ply") return MeshFormat::Ply;
    return std::nullopt;
}

Result<LoadedMesh, Error> loadMesh(const std::filesystem::path& file) {
    const auto format = formatFromExtension(file);
    if (!format && assimpCanImport(file)) {
        auto imported = importWithAssimp(file);
        if (!imported) return unexpected(imported.error());
        LoadedMesh out;
        out.mesh = std::move(imported->mesh);
        out.warnings = std::move(imported->warnings);
        // Assimp splits vertices per corner (STL always): weld exact duplicates so the surface is connected.
        for (const std::string& note : cleanMesh(out.mesh).notes) out.warnings.push_back({file, 0, note});
        return out;
    }
    if (!format)
        return unexpected(Error{file, 0,
                                "unknown mesh format '" + file.extension().string() +
                                    "': expected .txt (thesis format), .obj, .ply, or a format Assimp imports (.stl, "
                                    ".gltf, .glb, .3ds, .fbx, .dae, ...)"});
    const auto text = readTextFile(file);
    if (!text) return unexpected(text.error());

    LoadedMesh out;
    if (*format == MeshFormat::Thesis) {
        const std::size_t start = text->find_first_not_of(" \t\r\n");
        if (start != std::string::npos && text->compare(start, 9, "threshold") == 0) {
            auto tool = parseTool(*text, file);
            if (!tool) return unexpected(tool.error());
            out.mesh = std::move(tool->mesh);
            out.toolThreshold_N = tool->threshold_N;
            out.warnings = std::move(tool->warnings);
            return out;
        }
        auto model = parseModel(*text, file);
        if (!model) return unexpected(model.error());
        out.mesh = std::move(model->mesh);
        out.physics = model->physics;
        out.warnings = std::move(model->warnings);
        return out;
    }
    auto imported = *format == MeshFormat::Obj ? parseObj(*text, file) : parsePly(*text, file);
    if (!imported) return unexpected(imported.error());
    out.mesh = std::move(imported->mesh);
    out.warnings = std::move(imported->warnings);
    return out;
}

WriteStatus saveMesh(const std::filesystem::path& file, const SurfaceMesh& mesh, const ThesisPhysics& physics) {
    const auto format = formatFromExtension(file);
    if (!format)
        return Error{file, 0, "unknown mesh format '" + file.extension().string() + "': expected .txt, .obj or .ply"};
    switch (*format) {
        case MeshFormat::Thesis: return writeModelFile(file, mesh, physics);
        case MeshFormat::Obj: return writeTextFileAtomically(file, formatObj(mesh));
        case MeshFormat::Ply: return writeTextFileAtomically(file, formatPly(mesh));
    }
    return Error{file, 0, "unreachable"};
}

}  // namespace hapticut::mesh::io
