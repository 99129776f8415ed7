// Faulting in a thread's malloc arena ahead of its real-time work.
#include "hapticut/common/thread_heap.h"

#include <cstdlib>
#include <memory>
#include <vector>

namespace hapticut {

namespace {

struct FreeDeleter {
    void operator()(char* p) const { std::free(p); }
};

/// The block above the freed ones, held for the thread's life (see prefaultThreadHeap).
thread_local std::unique_ptr<char, FreeDeleter> heldAbove;

}  // namespace

void prefaultThreadHeap(std::size_t bytes) {
    // Blocks under glibc's mmap threshold (128 KiB) come from the thread's own arena, each above the
    // last. The last is held, so the ones freed below it coalesce into one free chunk that later small
    // allocations are split from; freed into the arena's top instead, they would be trimmed back to the
    // system at once.
    constexpr std::size_t kBlock = 96 * 1024, kPage = 4096;
    const std::size_t count = bytes / kBlock + 1;
    std::vector<char*> blocks;
    blocks.reserve(count);
    for (std::size_t i = 0; i < count; ++i) {
        auto* block = static_cast<char*>(std::malloc(kBlock));
        if (block == nullptr) break;
        for (std::size_t k = 0; k < kBlock; k += kPage) static_cast<volatile char*>(block)[k] = 0;
        blocks.push_back(block);
    }
    if (blocks.empty()) return;
    heldAbove.reset(blocks.back());
    blocks.pop_back();
    for (char* block : blocks) std::free(block);
}

}  // namespace hapticut
