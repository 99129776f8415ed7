// Which springs meet at each node, kept up to date through cuts in time proportional to the edit.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "hapticut/physics/mass_spring_model.h"

namespace hapticut::physics {

class NodeSprings {
public:
    /// Capacity for `nodes` and `springs`, touched up front, so that cuts rarely reallocate.
    void reserve(std::size_t nodes, std::size_t springs);
    /// Lists every spring at both of its ends (allocates: a preparation, not a step).
    void build(const Springs& springs, std::size_t nodes);
    /// After an edit: room for `nodes` nodes and every spring, and each listed spring moved to the
    /// lists of its current ends if they changed since it was last seen (repeats allowed).
    void update(const Springs& springs, std::size_t nodes, std::span<const std::uint32_t> changed);

    std::span<const std::uint32_t> of(std::uint32_t node) const { return ofNode_[node]; }
    /// The other end of spring k from node i.
    static std::uint32_t otherEnd(const Springs& springs, std::uint32_t k, std::uint32_t i) {
        return springs.a[k] == i ? springs.b[k] : springs.a[k];
    }
    std::size_t springCapacity() const { return ends_.capacity(); }

private:
    std::vector<std::vector<std::uint32_t>> ofNode_;  // the springs at each node
    std::vector<std::array<std::uint32_t, 2>> ends_;  // each spring's ends as last seen
};

}  // namespace hapticut::physics
