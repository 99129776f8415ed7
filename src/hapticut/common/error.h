// Error: what went wrong, where (a file and a line, when there is one), in words a user can act on.
// The library reports every runtime failure as a Result<T, Error> (result.h); no exception crosses its API.
#pragma once

#include <filesystem>
#include <optional>
#include <string>

namespace hapticut {

struct Error {
    std::filesystem::path file;  // empty when the problem is not about a file
    int line = 0;                // 1-based; 0 when the problem is not tied to a line
    std::string message;         // "expected 3 vertex indices, found 2"

    /// "file:line: message", the form compilers use, so editors can jump to it; just the message without a file.
    std::string toString() const;
};

/// A remark about input that still loaded, e.g. an edge list that disagrees with the faces.
using Warning = Error;

/// How an operation that returns nothing went: empty on success.
using Status = std::optional<Error>;
using WriteStatus = Status;

}  // namespace hapticut
