// The springs at each node.
#include "hapticut/physics/node_springs.h"

#include <algorithm>

#include "hapticut/common/reserve.h"

namespace hapticut::physics {

void NodeSprings::reserve(std::size_t nodes, std::size_t springs) {
    reserveTouched(ofNode_, nodes);
    reserveTouched(ends_, springs);
}

void NodeSprings::build(const Springs& springs, std::size_t nodes) {
    const std::size_t ns = springs.size();
    ofNode_.assign(nodes, {});
    ends_.resize(ns);
    for (std::uint32_t k = 0; k < ns; ++k) {
        ends_[k] = {springs.a[k], springs.b[k]};
        ofNode_[springs.a[k]].push_back(k), ofNode_[springs.b[k]].push_back(k);
    }
}

void NodeSprings::update(const Springs& springs, std::size_t nodes, std::span<const std::uint32_t> changed) {
    constexpr std::uint32_t kNone = 0xffffffffu;
    ofNode_.resize(nodes);
    ends_.resize(springs.size(), {kNone, kNone});
    for (std::uint32_t k : changed) {
        const std::array<std::uint32_t, 2> now{springs.a[k], springs.b[k]};
        std::array<std::uint32_t, 2>& seen = ends_[k];
        if (seen == now) continue;
        for (std::uint32_t end : seen) {
            if (end == kNone) continue;
            auto& list = ofNode_[end];
            list.erase(std::remove(list.begin(), list.end(), k), list.end());
        }
        for (std::uint32_t end : now) ofNode_[end].push_back(k);
        seen = now;
    }
}

}  // namespace hapticut::physics
