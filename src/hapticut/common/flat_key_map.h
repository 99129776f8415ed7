// A hash map from 64-bit keys to 32-bit values in one flat array, for lookups inside the haptic loop.
//
// std::unordered_map allocates a node per entry and chases two pointers per lookup; on a large organ's
// edge index (hundreds of thousands of springs) that was a third of a cut event's time. Here an entry is
// one slot: open addressing with linear probing (Knuth, TAOCP vol. 3, 6.4), deletion by shifting the
// entries behind back into the gap (Knuth's Algorithm R), so no tombstones pile up and nothing ever
// needs an in-place rehash. With room reserved, inserting and erasing never allocate.
#pragma once

#include <bit>
#include <cstdint>
#include <optional>
#include <vector>

#include "hapticut/common/assert.h"

namespace hapticut {

class FlatKeyMap {
public:
    /// The one key that cannot be stored: it marks an empty slot.
    static constexpr std::uint64_t kEmptyKey = ~std::uint64_t{0};

    FlatKeyMap() { rehash(kMinSlots); }

    std::size_t size() const { return size_; }
    /// How many entries fit before the next insert allocates.
    std::size_t room() const { return slots_.size() / 2; }

    /// Makes room for `entries`, touching the memory, so that growing to that size never allocates.
    void reserve(std::size_t entries) {
        if (entries > room()) rehash(std::bit_ceil(2 * entries));
    }

    std::optional<std::uint32_t> find(std::uint64_t key) const {
        for (std::size_t i = home(key);; i = (i + 1) & mask_) {
            if (slots_[i].key == key) return slots_[i].value;
            if (slots_[i].key == kEmptyKey) return std::nullopt;
        }
    }

    bool contains(std::uint64_t key) const { return find(key).has_value(); }

    /// Sets key's value, adding the key if it is new.
    void set(std::uint64_t key, std::uint32_t value) {
        HAPTICUT_ASSERT(key != kEmptyKey);
        if (size_ + 1 > room()) rehash(2 * slots_.size());
        std::size_t i = home(key);
        while (slots_[i].key != kEmptyKey && slots_[i].key != key) i = (i + 1) & mask_;
        if (slots_[i].key == kEmptyKey) ++size_;
        slots_[i] = {key, value};
    }

    /// Removes key; false if it was not there.
    bool erase(std::uint64_t key) {
        std::size_t gap = home(key);
        while (slots_[gap].key != key) {
            if (slots_[gap].key == kEmptyKey) return false;
            gap = (gap + 1) & mask_;
        }
        // Each entry behind the gap, up to the next empty slot, moves into it unless its own home lies
        // after the gap (cyclically, in (gap, j]): a lookup for it must still pass no empty slot.
        for (std::size_t j = (gap + 1) & mask_; slots_[j].key != kEmptyKey; j = (j + 1) & mask_) {
            const std::size_t h = home(slots_[j].key);
            const bool staysAfterGap = gap <= j ? (gap < h && h <= j) : (gap < h || h <= j);
            if (staysAfterGap) continue;
            slots_[gap] = slots_[j];
            gap = j;
        }
        slots_[gap].key = kEmptyKey;
        --size_;
        return true;
    }

private:
    struct Slot {
        std::uint64_t key = kEmptyKey;
        std::uint32_t value = 0;
    };
    static constexpr std::size_t kMinSlots = 16;

    std::size_t home(std::uint64_t key) const {
        // Fibonacci hashing: the product's top bits mix all of the key's bits (edge keys differ mostly
        // in their low halves).
        return static_cast<std::size_t>((key * 0x9E3779B97F4A7C15ull) >> shift_);
    }

    void rehash(std::size_t slots) {
        std::vector<Slot> old = std::move(slots_);
        slots_.assign(slots, Slot{});  // written, so in memory before the loop needs it
        mask_ = slots - 1;
        shift_ = 64 - std::countr_zero(slots);
        size_ = 0;
        for (const Slot& s : old)
            if (s.key != kEmptyKey) set(s.key, s.value);
    }

    std::vector<Slot> slots_;
    std::size_t mask_ = 0, size_ = 0;
    int shift_ = 64;
};

}  // namespace hapticut
