// A hash map from 64-bit keys to 32-bit values in one flat array, for lookups inside the haptic loop.
//
// std::unordered_map allocates a node per entry and chases two pointers per lookup; on a large organ's
// edge index (hundreds of thousands of springs) that was a third of a cut event's time. Here an entry is
// one slot: open addressing with linear probing (Knuth, TAOCP vol. 3, 6.4), deletion by shifting the
// entries behind back into the gap (Knuth's Algorithm R), so no tombstones pile up and nothing ever
// needs an in-place rehash. With room reserved, inserting and erasing never allocate.
//
// Keys may be spread over the table by a hash of the whole key, or kept in order of their high halves
// (Spread::ByHighHalf): an edge's key (mesh::edgeKey) then lands next to the keys of the other edges of
// its lower vertex, and those of the vertices numbered near it. A cut looks up the edges round the
// vertices it reaches, which lie near each other in a mesh numbered for locality; spread by a hash,
// each lookup touched a page of its own in a table of 128 MB (the 1,000,000-triangle heart), and on a
// virtual machine the first touch of a page left alone for a while can take 100-250 µs.
#pragma once

#include <algorithm>
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

    enum class Spread {
        Hashed,  // any keys: a hash of the whole key picks the first slot
        // Keys whose high halves count from 0 with a few keys each (an edge's lower vertex): a high half
        // with many (a vertex joined to hundreds) makes a long run that its neighbours' lookups walk.
        ByHighHalf,
    };

    explicit FlatKeyMap(Spread spread = Spread::Hashed) : spread_(spread) { rehash(kMinSlots); }

    std::size_t size() const { return size_; }
    /// How many entries fit before the next insert allocates.
    std::size_t room() const { return slots_.size() / 2; }

    /// Makes room for `entries`, touching the memory, so that growing to that size never allocates.
    /// Spread by high halves, the table's runs are laid out for high halves below `highHalves` too.
    void reserve(std::size_t entries, std::size_t highHalves = 0) {
        highHalves_ = std::max(highHalves_, highHalves);
        const std::size_t slots = std::max(slots_.size(), slotsFor(entries));
        if (slots > slots_.size() || (spread_ == Spread::ByHighHalf && runBitsFor(slots) != runBits_)) rehash(slots);
    }

    std::optional<std::uint32_t> find(std::uint64_t key) const {
        const std::optional<std::size_t> slot = slotOf(key);
        return slot ? std::optional(slots_[*slot].value) : std::nullopt;
    }

    bool contains(std::uint64_t key) const { return find(key).has_value(); }

    /// The slot holding key, if it is there: where in memory a lookup ends (for tests of the spread).
    std::optional<std::size_t> slotOf(std::uint64_t key) const {
        for (std::size_t i = home(key);; i = (i + 1) & mask_) {
            if (slots_[i].key == key) return i;
            if (slots_[i].key == kEmptyKey) return std::nullopt;
        }
    }

    /// How many slots a lookup of key reads, whether it is there or not (for tests of the spread).
    std::size_t probes(std::uint64_t key) const {
        std::size_t read = 1;
        for (std::size_t i = home(key); slots_[i].key != key && slots_[i].key != kEmptyKey; i = (i + 1) & mask_) ++read;
        return read;
    }

    /// Sets key's value, adding the key if it is new.
    void set(std::uint64_t key, std::uint32_t value) {
        HAPTICUT_ASSERT(key != kEmptyKey);
        if (size_ + 1 > room()) rehash(std::max(2 * slots_.size(), slotsFor(size_ + 1)));
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
    static constexpr std::size_t kRunSlots = 8;

    std::size_t home(std::uint64_t key) const {
        // Fibonacci hashing: the product's top bits mix all of the key's bits (edge keys differ mostly
        // in their low halves).
        if (spread_ == Spread::Hashed) return static_cast<std::size_t>((key * 0x9E3779B97F4A7C15ull) >> shift_);
        // The high half picks a run of slots, the mixed low half a slot in it; high halves past those the
        // runs were laid out for wrap round (correct, only less local) until the table grows.
        const std::uint64_t inRun = runBits_ > 0 ? (key & 0xFFFFFFFFull) * 0x9E3779B97F4A7C15ull >> (64 - runBits_) : 0;
        return static_cast<std::size_t>(((key >> 32 << runBits_) | inRun) & mask_);
    }

    /// Slots for `entries`: at most half full, and spread by high halves, at least kRunSlots a high half.
    /// A run of four slots held a vertex's three edges on average, and more round a cut: at that load
    /// linear probing's clusters join, and a lookup of an edge that is not there walked 5-8 slots on the
    /// hearts whose table rounded to four (1,619, 9,714, 100,000 triangles).
    std::size_t slotsFor(std::size_t entries) const {
        const std::size_t least = spread_ == Spread::ByHighHalf ? kRunSlots * std::max<std::size_t>(highHalves_, 1) : 0;
        return std::bit_ceil(std::max({2 * entries, least, kMinSlots}));
    }

    /// Each high half's run of slots: as long as the table can give every high half seen or reserved for.
    int runBitsFor(std::size_t slots) const {
        const std::size_t runs = std::max<std::size_t>(highHalves_, 1);
        return slots >= runs ? static_cast<int>(std::bit_width(slots / runs)) - 1 : 0;
    }

    void rehash(std::size_t slots) {
        std::vector<Slot> old = std::move(slots_);
        for (const Slot& s : old)
            if (s.key != kEmptyKey) highHalves_ = std::max<std::size_t>(highHalves_, (s.key >> 32) + 1);
        runBits_ = runBitsFor(slots);
        slots_.assign(slots, Slot{});  // written, so in memory before the loop needs it
        mask_ = slots - 1;
        shift_ = 64 - std::countr_zero(slots);
        size_ = 0;
        for (const Slot& s : old)
            if (s.key != kEmptyKey) set(s.key, s.value);
    }

    Spread spread_;
    std::vector<Slot> slots_;
    std::size_t mask_ = 0, size_ = 0;
    int shift_ = 64;
    std::size_t highHalves_ = 0;  // spread by high halves: one more than the largest seen or reserved for
    int runBits_ = 0;             // spread by high halves: each one's run holds 2^runBits_ slots
};

}  // namespace hapticut
