// Import through Assimp: STL, glTF/GLB, 3DS, FBX, Collada and the rest of what it reads. Every mesh in
// the file is merged, triangulated and placed by its node transforms; corner UVs are kept.
#pragma once

#include <cstdint>
#include <filesystem>

#include "hapticut/common/result.h"
#include "hapticut/common/text_file.h"
#include "hapticut/mesh/io/obj_format.h"

namespace hapticut::mesh::io {

/// True for extensions Assimp can import here (case-insensitive, with the dot: ".stl").
bool assimpCanImport(const std::filesystem::path& file);

/// The largest file handed to Assimp: 2 GiB, some 40 million triangles of binary STL (the command line
/// takes 20 million).
inline constexpr std::uintmax_t kMaxImportBytes = std::uintmax_t{2} << 30;
/// The most vertices a file's nodes may place its meshes into (a glTF can instance one mesh a million
/// times): as many as that largest binary STL has, 3 to each of its 50-byte triangles.
inline constexpr std::uintmax_t kMaxImportVertices = kMaxImportBytes / 50 * 3;

/// Imports every triangle of the file. Assimp gives each mesh its own vertices (STL even one per
/// corner), so the result is not welded yet: see repair.h.
Result<ImportedMesh, Error> importWithAssimp(const std::filesystem::path& file);

}  // namespace hapticut::mesh::io
