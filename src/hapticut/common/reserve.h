// Capacity that is ready to use: reserved and already touched, so growing into it later costs no page
// faults (on a loaded machine each one can take microseconds, which a 1 kHz loop notices).
#pragma once

#include <cstddef>
#include <vector>

namespace hapticut {

/// How much room to keep for arrays that cuts grow: half as much again, and a little more for small
/// organs. One policy for the organ, the stepper, the tree and the snapshots.
inline std::size_t roomToGrow(std::size_t n) { return n + n / 2 + 1024; }

/// A value whose copies write every byte: a default-constructed Eigen vector is left uninitialised,
/// so resizing with it would reserve pages and never touch them.
template <class T>
T touchingValue() {
    if constexpr (requires { T::Zero(); })
        return T::Zero();
    else
        return T{};
}

/// Reserves room for `capacity` elements and writes every one of them once, keeping the size. Room
/// already there is left alone: asked again after every cut, rewriting it all cost 10-200 ms at a
/// million nodes.
template <class T>
void reserveTouched(std::vector<T>& v, std::size_t capacity) {
    if (capacity <= v.capacity()) return;
    const std::size_t size = v.size();
    v.reserve(capacity);
    v.resize(capacity, touchingValue<T>());
    v.resize(size);
}

}  // namespace hapticut
