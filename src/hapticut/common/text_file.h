// Whole text files read safely and written atomically, for every loader and writer in the project.
#pragma once

#include <cstddef>
#include <cstdio>
#include <filesystem>
#include <string>
#include <string_view>

#include "hapticut/common/error.h"
#include "hapticut/common/result.h"

namespace hapticut {

/// Reads a whole file as text; refuses a folder, a file it cannot open, or one larger than max_bytes.
Result<std::string, Error> readTextFile(const std::filesystem::path& file,
                                        std::size_t max_bytes = std::size_t{4} << 30);

/// Writes through a temporary file and a rename, so a failed write never destroys an existing file.
[[nodiscard]] WriteStatus writeTextFileAtomically(const std::filesystem::path& file, const std::string& text);

/// A file written piece by piece as it is produced, into a temporary file beside the target
/// (`target.tmp-hapticut`) that replaces it only when commit() succeeds: a failed, abandoned or
/// interrupted write (removeTempFilesOnSignals) leaves the target as it was, and no temporary file.
/// A stale temporary file of a killed process is replaced by the next write of the same target.
class AtomicFile {
public:
    /// Refuses a target that is a folder, and a temporary file that cannot be created.
    static Result<AtomicFile, Error> create(const std::filesystem::path& file);
    AtomicFile(AtomicFile&& other) noexcept;
    AtomicFile& operator=(AtomicFile&&) = delete;
    ~AtomicFile();  // abandons the write unless it was committed

    /// Appends; false once any write failed (commit() then says why).
    bool write(std::string_view bytes);
    /// Flushes and renames the temporary file over the target.
    [[nodiscard]] WriteStatus commit();
    /// Removes the temporary file; the target stays as it was.
    void abandon() noexcept;
    const std::filesystem::path& target() const { return file_; }

private:
    AtomicFile(std::filesystem::path file, std::filesystem::path tmp, std::FILE* out, int signalSlot);

    std::filesystem::path file_, tmp_;
    std::FILE* out_ = nullptr;
    int signalSlot_ = -1;  // temp_files.h
    bool pending_ = true;  // the temporary file exists and has not replaced the target
    int error_ = 0;        // errno of the first failed write
};

}  // namespace hapticut
