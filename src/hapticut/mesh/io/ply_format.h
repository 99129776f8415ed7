// Stanford PLY: read ASCII and binary (both endians) with optional per-face texcoords; write ASCII.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

#include "hapticut/common/result.h"
#include "hapticut/common/text_file.h"
#include "hapticut/mesh/io/obj_format.h"
#include "hapticut/mesh/surface_mesh.h"

namespace hapticut::mesh::io {

Result<ImportedMesh, Error> parsePly(std::string_view bytes, const std::filesystem::path& file_for_errors);
std::string formatPly(const SurfaceMesh& mesh);

}  // namespace hapticut::mesh::io
