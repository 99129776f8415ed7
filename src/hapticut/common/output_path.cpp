// Checks that the files a command will write can be written, before it starts.
#include "hapticut/common/output_path.h"

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <string>

namespace hapticut {

namespace {
std::string lower(std::string text) {
    std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return std::tolower(c); });
    return text;
}
}  // namespace

Status checkOutputPath(const std::filesystem::path& file, std::string_view extension) {
    if (file.empty()) return std::nullopt;
    namespace fs = std::filesystem;
    auto fail = [&](const std::string& why) { return Error{file, 0, why}; };
    if (!extension.empty() && lower(file.extension().string()) != lower(std::string(extension)))
        return fail("cannot write it: expected a " + std::string(extension) + " file");
    std::error_code ec;
    if (fs::is_directory(file, ec)) return fail("is a folder, expected a file");
    const fs::path folder = file.parent_path().empty() ? fs::path(".") : file.parent_path();
    if (!fs::exists(folder, ec)) return fail("cannot write it: there is no folder " + folder.string());
    if (!fs::is_directory(folder, ec)) return fail("cannot write it: " + folder.string() + " is not a folder");
    // Written through a temporary file beside the target (AtomicFile), so the folder must take new files.
    if (::access(folder.c_str(), W_OK | X_OK) != 0)
        return fail("cannot write it: the folder " + folder.string() + " is not writable (" + std::strerror(errno) +
                    ")");
    if (fs::exists(file, ec) && ::access(file.c_str(), W_OK) != 0)
        return fail("cannot write it: the file exists and is not writable (" + std::string(std::strerror(errno)) + ")");
    return std::nullopt;
}

Status checkOutputPaths(std::initializer_list<std::filesystem::path> files) {
    for (const std::filesystem::path& f : files)
        if (Status s = checkOutputPath(f)) return s;
    return std::nullopt;
}

}  // namespace hapticut
