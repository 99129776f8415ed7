// Latest-value handoff between one writer and one reader; neither side ever waits or allocates.
#pragma once

#include <array>
#include <atomic>

namespace hapticut {

template <class T>
class TripleBuffer {
public:
    /// The slot the writer fills next; sizing its arrays once up front keeps publish allocation-free.
    T& writeSlot() { return slots_[write_]; }
    void publish() { write_ = shared_.exchange(write_ | kFresh, std::memory_order_acq_rel) & kIndex; }
    /// The newest published value (the same one again if nothing new was published).
    const T& readLatest() {
        if (shared_.load(std::memory_order_relaxed) & kFresh)
            read_ = shared_.exchange(read_, std::memory_order_acq_rel) & kIndex;
        return slots_[read_];
    }
    /// All three slots, e.g. to reserve capacity before the writer starts.
    std::array<T, 3>& slots() { return slots_; }

private:
    static constexpr unsigned kFresh = 4, kIndex = 3;
    std::array<T, 3> slots_{};
    std::atomic<unsigned> shared_{1};
    unsigned write_ = 0, read_ = 2;
};

}  // namespace hapticut
