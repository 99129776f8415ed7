// LoadError: what went wrong reading or writing a file, with the file and the line.
#pragma once

#include <filesystem>
#include <optional>
#include <string>

namespace hapticut::mesh::io {

struct LoadError {
    std::filesystem::path file;
    int line = 0;         // 1-based; 0 when the problem is not tied to a line
    std::string message;  // "expected 3 vertex indices, found 2"

    /// "file:line: message", the form compilers use, so editors can jump to it.
    std::string toString() const;
};

/// A non-fatal remark about a file that still loaded, e.g. an edge list that disagrees with the faces.
using LoadWarning = LoadError;

/// Empty on success.
using WriteStatus = std::optional<LoadError>;

/// Reads a whole file as text; refuses files that are not text (NUL bytes) or larger than max_bytes.
std::optional<std::string> readTextFile(const std::filesystem::path& file, LoadError& error,
                                        std::size_t max_bytes = std::size_t{4} << 30);

/// Writes through a temporary file and a rename, so a failed write never destroys an existing file.
[[nodiscard]] WriteStatus writeTextFileAtomically(const std::filesystem::path& file, const std::string& text);

}  // namespace hapticut::mesh::io
