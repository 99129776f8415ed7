// Whole text files read safely and written atomically, for every loader and writer in the project.
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>

#include "hapticut/common/error.h"
#include "hapticut/common/result.h"

namespace hapticut {

/// Reads a whole file as text; refuses a folder, a file it cannot open, or one larger than max_bytes.
Result<std::string, Error> readTextFile(const std::filesystem::path& file,
                                        std::size_t max_bytes = std::size_t{4} << 30);

/// Writes through a temporary file and a rename, so a failed write never destroys an existing file.
[[nodiscard]] WriteStatus writeTextFileAtomically(const std::filesystem::path& file, const std::string& text);

}  // namespace hapticut
