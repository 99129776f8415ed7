// Wavefront OBJ: read (polygons fan-triangulated, per-corner UVs kept) and write, keeping vertex indices.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

#include "hapticut/common/error.h"
#include "hapticut/common/result.h"
#include "hapticut/mesh/io/imported_mesh.h"
#include "hapticut/mesh/surface_mesh.h"

namespace hapticut::mesh::io {

Result<ImportedMesh, Error> parseObj(std::string_view text, const std::filesystem::path& file_for_errors);
std::string formatObj(const SurfaceMesh& mesh);

}  // namespace hapticut::mesh::io
