// Temporary files removed on signals, from a handler that only calls async-signal-safe functions.
#include "hapticut/common/temp_files.h"

#include <unistd.h>

#include <array>
#include <atomic>
#include <csignal>
#include <cstring>

namespace hapticut {

namespace {

constexpr int kSlots = 16;
constexpr std::size_t kMaxPath = 4096;

struct Slot {
    std::atomic<bool> taken{false};  // owned by a writer
    std::atomic<bool> armed{false};  // its path is complete: the handler may read it
    char path[kMaxPath]{};
};
std::array<Slot, kSlots> slots;
static_assert(std::atomic<bool>::is_always_lock_free, "read from a signal handler");

extern "C" void removeTempFilesAndDie(int signal) {
    for (Slot& slot : slots)
        if (slot.armed.load(std::memory_order_acquire)) ::unlink(slot.path);
    std::signal(signal, SIG_DFL);
    std::raise(signal);
}

}  // namespace

void removeTempFilesOnSignals() {
    for (const int signal : {SIGINT, SIGTERM, SIGHUP}) std::signal(signal, removeTempFilesAndDie);
}

int registerTempFile(const std::filesystem::path& file) noexcept {
    const std::string& text = file.native();
    if (text.size() >= kMaxPath) return -1;
    for (int i = 0; i < kSlots; ++i) {
        Slot& slot = slots[static_cast<std::size_t>(i)];
        if (slot.taken.exchange(true, std::memory_order_acquire)) continue;
        std::memcpy(slot.path, text.c_str(), text.size() + 1);
        slot.armed.store(true, std::memory_order_release);
        return i;
    }
    return -1;
}

void releaseTempFile(int slot) noexcept {
    if (slot < 0 || slot >= kSlots) return;
    slots[static_cast<std::size_t>(slot)].armed.store(false, std::memory_order_release);
    slots[static_cast<std::size_t>(slot)].taken.store(false, std::memory_order_release);
}

}  // namespace hapticut
