// Safe whole-file reading and writing.
#include "hapticut/common/text_file.h"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <system_error>

namespace hapticut {

Result<std::string, Error> readTextFile(const std::filesystem::path& file, std::size_t max_bytes) {
    auto fail = [&](std::string message) { return unexpected(Error{file, 0, std::move(message)}); };
    std::error_code ec;
    if (std::filesystem::is_directory(file, ec)) return fail("is a directory, expected a file");
    std::ifstream in(file, std::ios::binary);
    if (!in) return fail(std::string("cannot open: ") + std::strerror(errno));
    in.seekg(0, std::ios::end);
    const auto size = static_cast<std::size_t>(std::max<std::streamoff>(in.tellg(), 0));
    if (size > max_bytes)
        return fail("file is " + std::to_string(size) + " bytes, more than the " + std::to_string(max_bytes) +
                    " this reader accepts");
    in.seekg(0);
    std::string text(size, '\0');
    in.read(text.data(), static_cast<std::streamsize>(size));
    if (static_cast<std::size_t>(in.gcount()) != size) return fail("read failed");
    return text;
}

WriteStatus writeTextFileAtomically(const std::filesystem::path& file, const std::string& text) {
    std::filesystem::path tmp = file;
    tmp += ".tmp-hapticut";
    {
        std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
        if (!out) return Error{file, 0, std::string("cannot write: ") + std::strerror(errno)};
        out.write(text.data(), static_cast<std::streamsize>(text.size()));
        out.flush();
        if (!out) {
            std::error_code ignored;
            std::filesystem::remove(tmp, ignored);
            return Error{file, 0, "write failed (disk full?)"};
        }
    }
    std::error_code ec;
    std::filesystem::rename(tmp, file, ec);
    if (ec) {
        std::filesystem::remove(tmp, ec);
        return Error{file, 0, "cannot replace the file: " + ec.message()};
    }
    return std::nullopt;
}

}  // namespace hapticut
