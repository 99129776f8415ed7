// Bounded single-producer single-consumer queue: lock-free, allocation-free after construction.
#pragma once

#include <array>
#include <atomic>
#include <cstddef>
#include <optional>

namespace hapticut {

template <class T, std::size_t kCapacity>
class SpscQueue {
    static_assert((kCapacity & (kCapacity - 1)) == 0, "capacity must be a power of two");

public:
    /// False when full: the caller decides (UI commands can simply be retried next frame).
    bool push(const T& value) {
        const std::size_t head = head_.load(std::memory_order_relaxed);
        if (head - tail_.load(std::memory_order_acquire) == kCapacity) return false;
        items_[head & (kCapacity - 1)] = value;
        head_.store(head + 1, std::memory_order_release);
        return true;
    }
    std::optional<T> pop() {
        const std::size_t tail = tail_.load(std::memory_order_relaxed);
        if (tail == head_.load(std::memory_order_acquire)) return std::nullopt;
        T value = items_[tail & (kCapacity - 1)];
        tail_.store(tail + 1, std::memory_order_release);
        return value;
    }

private:
    std::array<T, kCapacity> items_{};
    alignas(64) std::atomic<std::size_t> head_{0};
    alignas(64) std::atomic<std::size_t> tail_{0};
};

}  // namespace hapticut
