// Safe whole-file reading and writing.
#include "hapticut/common/text_file.h"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <system_error>
#include <utility>

#include "hapticut/common/temp_files.h"

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
    auto out = AtomicFile::create(file);
    if (!out) return out.error();
    out->write(text);
    return out->commit();
}

AtomicFile::AtomicFile(std::filesystem::path file, std::filesystem::path tmp, std::FILE* out, int signalSlot)
    : file_(std::move(file)), tmp_(std::move(tmp)), out_(out), signalSlot_(signalSlot) {}

AtomicFile::AtomicFile(AtomicFile&& other) noexcept
    : file_(std::move(other.file_)),
      tmp_(std::move(other.tmp_)),
      out_(std::exchange(other.out_, nullptr)),
      signalSlot_(std::exchange(other.signalSlot_, -1)),
      pending_(std::exchange(other.pending_, false)),
      error_(other.error_) {}

AtomicFile::~AtomicFile() { abandon(); }

Result<AtomicFile, Error> AtomicFile::create(const std::filesystem::path& file) {
    std::error_code ec;
    if (std::filesystem::is_directory(file, ec)) return unexpected(Error{file, 0, "is a folder, expected a file"});
    std::filesystem::path tmp = file;
    tmp += ".tmp-hapticut";
    // Registered before it exists, so that no signal can come between its creation and its registration.
    const int slot = registerTempFile(tmp);
    std::FILE* out = std::fopen(tmp.c_str(), "wb");
    if (!out) {
        const int error = errno;
        releaseTempFile(slot);
        return unexpected(Error{file, 0, std::string("cannot write: ") + std::strerror(error)});
    }
    return AtomicFile(file, std::move(tmp), out, slot);
}

bool AtomicFile::write(std::string_view bytes) {
    if (!out_ || error_ != 0) return false;
    if (std::fwrite(bytes.data(), 1, bytes.size(), out_) != bytes.size()) error_ = errno != 0 ? errno : EIO;
    return error_ == 0;
}

WriteStatus AtomicFile::commit() {
    if (!out_) return Error{file_, 0, "already written or abandoned"};
    if (error_ == 0 && std::fflush(out_) != 0) error_ = errno != 0 ? errno : EIO;
    if (std::fclose(std::exchange(out_, nullptr)) != 0 && error_ == 0) error_ = errno != 0 ? errno : EIO;
    if (error_ != 0) {
        abandon();
        return Error{file_, 0, std::string("write failed: ") + std::strerror(error_)};
    }
    std::error_code ec;
    std::filesystem::rename(tmp_, file_, ec);
    if (ec) {
        const std::string reason = ec.message();
        abandon();
        return Error{file_, 0, "cannot replace the file: " + reason};
    }
    pending_ = false;
    releaseTempFile(std::exchange(signalSlot_, -1));
    return std::nullopt;
}

void AtomicFile::abandon() noexcept {
    if (out_) std::fclose(std::exchange(out_, nullptr));
    if (std::exchange(pending_, false)) {
        std::error_code ignored;
        std::filesystem::remove(tmp_, ignored);
    }
    releaseTempFile(std::exchange(signalSlot_, -1));
}

}  // namespace hapticut
