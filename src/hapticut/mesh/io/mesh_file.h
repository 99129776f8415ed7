// Loading and saving meshes by file extension: thesis format (.txt), OBJ, PLY.
#pragma once

#include <filesystem>
#include <optional>
#include <vector>

#include "hapticut/common/result.h"
#include "hapticut/common/text_file.h"
#include "hapticut/mesh/io/thesis_format.h"

namespace hapticut::mesh::io {

enum class MeshFormat { Thesis, Obj, Ply };

struct LoadedMesh {
    SurfaceMesh mesh;
    std::optional<ThesisPhysics> physics;   // present for thesis model files
    std::optional<double> toolThreshold_N;  // present for thesis tool files
    std::vector<Warning> warnings;
};

/// The format an extension names (.txt, .obj, .ply, any case); empty when unknown.
std::optional<MeshFormat> formatFromExtension(const std::filesystem::path& file);

/// Loads a model or tool file; a thesis file starting with `threshold` is read as a tool.
Result<LoadedMesh, Error> loadMesh(const std::filesystem::path& file);

/// Saves in the format the extension names. Thesis model files need `physics`.
[[nodiscard]] WriteStatus saveMesh(const std::filesystem::path& file, const SurfaceMesh& mesh,
                                   const ThesisPhysics& physics);

}  // namespace hapticut::mesh::io
