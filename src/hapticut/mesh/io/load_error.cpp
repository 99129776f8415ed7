// LoadError formatting and safe whole-file reading and writing.
#include "hapticut/mesh/io/load_error.h"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <system_error>

namespace hapticut::mesh::io {

std::string LoadError::toString() const {
    std::string s = file.string();
    if (line > 0) s.append(":").append(std::to_string(line));
    s.append(": ").append(message);
    return s;
}

std::optional<std::string> readTextFile(const std::filesystem::path& file, LoadError& error, std::size_t max_bytes) {
    error = LoadError{file, 0, ""};
    std::error_code ec;
    if (std::filesystem::is_directory(file, ec)) {
        error.message = "is a directory, expected a file";
        return std::nullopt;
    }
    std::ifstream in(file, std::ios::binary);
    if (!in) {
        error.message = std::string("cannot open: ") + std::strerror(errno);
        return std::nullopt;
    }
    in.seekg(0, std::ios::end);
    const auto size = static_cast<std::size_t>(std::max<std::streamoff>(in.tellg(), 0));
    if (size > max_bytes) {
        error.message = "file is " + std::to_string(size) + " bytes, more than the " + std::to_string(max_bytes) + " this reader accepts";
        return std::nullopt;
    }
    in.seekg(0);
    std::string text(size, '\0');
    in.read(text.data(), static_cast<std::streamsize>(size));
    if (static_cast<std::size_t>(in.gcount()) != size) {
        error.message = "read failed";
        return std::nullopt;
    }
    return text;
}

WriteStatus writeTextFileAtomically(const std::filesystem::path& file, const std::string& text) {
    std::filesystem::path tmp = file;
    tmp += ".tmp-hapticut";
    {
        std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
        if (!out) return LoadError{file, 0, std::string("cannot write: ") + std::strerror(errno)};
        out.write(text.data(), static_cast<std::streamsize>(text.size()));
        out.flush();
        if (!out) {
            std::error_code ignored;
            std::filesystem::remove(tmp, ignored);
            return LoadError{file, 0, "write failed (disk full?)"};
        }
    }
    std::error_code ec;
    std::filesystem::rename(tmp, file, ec);
    if (ec) {
        std::filesystem::remove(tmp, ec);
        return LoadError{file, 0, "cannot replace the file: " + ec.message()};
    }
    return std::nullopt;
}

}  // namespace hapticut::mesh::io
