// The temporary files a write is filling, removed when a signal ends the process before it can finish:
// an interrupted `convert` leaves its target as it was, and no half-written file beside it.
#pragma once

#include <filesystem>

namespace hapticut {

/// SIGINT, SIGTERM and SIGHUP remove every registered temporary file, then end the process as the
/// signal would have. Call once at startup; a StopSignal in scope takes the signals over (its command
/// finishes or abandons its files itself) and hands them back when it ends.
void removeTempFilesOnSignals();

/// Registers `file` for removal on a signal until the returned slot is released; -1 when every slot
/// is taken (the file is then only not removed on a signal).
int registerTempFile(const std::filesystem::path& file) noexcept;
void releaseTempFile(int slot) noexcept;

}  // namespace hapticut
