// Checks, before a long command starts, that the files it will write can be written: a typo in a
// folder or a read-only target found after an hour's run would lose the run's results.
#pragma once

#include <filesystem>
#include <initializer_list>
#include <string_view>

#include "hapticut/common/error.h"

namespace hapticut {

/// An error naming `file` when it cannot be written: its folder missing or not a folder, the folder or
/// an existing file not writable, or a folder in its place. `extension` (".png"), when given, is the
/// ending the file must have (any case). An empty path is no output: fine.
Status checkOutputPath(const std::filesystem::path& file, std::string_view extension = {});

/// The first of `files` that cannot be written, as checkOutputPath says.
Status checkOutputPaths(std::initializer_list<std::filesystem::path> files);

}  // namespace hapticut
