// The active region: admission before a step, sleep after it.
#include "hapticut/physics/active_region.h"

#include <algorithm>

#include "hapticut/common/reserve.h"

namespace hapticut::physics {

void ActiveRegion::reserve(std::size_t nodes, std::size_t springs) {
    for (auto* list : {&activeNodes_, &touchedNodes_, &wakeList_, &merged_}) reserveTouched(*list, nodes);
    for (auto* marks : {&awake_, &wakeNext_, &touchedMark_}) reserveTouched(*marks, nodes);
    reserveTouched(springMark_, springs);
    reserveTouched(activeSprings_, springs);
}

void ActiveRegion::reset(const MassSpringModel& model) {
    const std::size_t n = model.nodes.size();
    awake_.assign(n, 0);
    wakeNext_.assign(n, 0);
    touchedMark_.assign(n, 0);
    springMark_.assign(model.springs.size(), 0);
    activeNodes_.clear();
    touchedNodes_.clear();
    activeSprings_.clear();
    wakeList_.clear();
    for (std::uint32_t i = 0; i < n; ++i)
        if (!atRest(model.nodes, i)) wake(i);
    ++version_;
    dirty_ = true;
}

void ActiveRegion::resize(std::size_t nodes, std::size_t springs) {
    for (auto* marks : {&awake_, &wakeNext_, &touchedMark_}) marks->resize(nodes, 0);
    springMark_.resize(springs, 0);
    dirty_ = true;
}

void ActiveRegion::wake(std::uint32_t node) {
    if (node >= wakeNext_.size() || wakeNext_[node]) return;
    wakeNext_[node] = 1;
    wakeList_.push_back(node);  // reserved for every node: never allocates
}

void ActiveRegion::admit(const MassSpringModel& model, const NodeSprings& springsAt) {
    // Only candidates are looked at, so this stays proportional to the region: the tools' nodes, the
    // resting neighbours flagged by updateSleep, and wake() calls.
    auto admitNode = [&](std::uint32_t i) {
        if (wakeNext_[i] && !awake_[i]) {
            awake_[i] = 1;
            activeNodes_.push_back(i);
            dirty_ = true;
        }
        wakeNext_[i] = 0;
    };
    for (const PointSpring& tool : model.tools) {
        if (!tool.active) continue;
        for (std::uint32_t i : tool.loadedNodes()) {
            // The tool's nodes and their neighbours are always awake: within one step a push travels
            // further than the one ring the region grows by per step.
            wakeNext_[i] = 1;
            admitNode(i);
            for (const std::uint32_t k : springsAt.of(i)) {
                const std::uint32_t j = NodeSprings::otherEnd(model.springs, k, i);
                wakeNext_[j] = 1;
                admitNode(j);
            }
        }
    }
    for (std::size_t k = 0; k < touchedNodes_.size(); ++k) admitNode(touchedNodes_[k]);
    for (std::uint32_t i : wakeList_) admitNode(i);
    wakeList_.clear();
    if (dirty_) rebuild(model, springsAt);
}

void ActiveRegion::rebuild(const MassSpringModel& model, const NodeSprings& springsAt) {
    // The awake nodes in index order, so that the solve's unknowns follow the organ's vertex order (its
    // neighbours near in index; mesh/vertex_order.h) rather than the order they woke in. Falling asleep
    // keeps the order, so only the nodes admitted since the last rebuild, at the end, are sorted and
    // merged in: proportional to the region, and no allocation (merged_ is reserved).
    const auto tail = std::is_sorted_until(activeNodes_.begin(), activeNodes_.end());
    if (tail != activeNodes_.end()) {
        std::sort(tail, activeNodes_.end());
        merged_.resize(activeNodes_.size());
        std::merge(activeNodes_.begin(), tail, tail, activeNodes_.end(), merged_.begin());
        std::copy(merged_.begin(), merged_.end(), activeNodes_.begin());
    }
    for (std::uint32_t k : activeSprings_) springMark_[k] = 0;
    for (std::uint32_t i : touchedNodes_) touchedMark_[i] = 0;
    activeSprings_.clear();
    touchedNodes_.clear();
    for (std::uint32_t i : activeNodes_) {
        touchedMark_[i] = 1;
        touchedNodes_.push_back(i);
    }
    for (std::uint32_t i : activeNodes_)
        for (const std::uint32_t k : springsAt.of(i)) {
            if (springMark_[k]) continue;
            springMark_[k] = 1;
            activeSprings_.push_back(k);
            for (std::uint32_t j : {model.springs.a[k], model.springs.b[k]})
                if (!touchedMark_[j]) touchedMark_[j] = 1, touchedNodes_.push_back(j);
        }
    ++version_;
    dirty_ = false;
}

bool ActiveRegion::pulledOffRest(const MassSpringModel& model, const NodeSprings& springsAt, std::uint32_t i,
                                 const Vec3& force_N) {
    const double anchor = model.nodes.anchorStiffness[i], reach = model.snapDistance_m;
    const double f2 = force_N.squaredNorm();
    if (f2 <= anchor * anchor * reach * reach) return false;  // the anchor alone holds it within reach
    // Its springs hold it too. Let go with its neighbours where they are, it settles where
    // K d = f, K = k_anchor I + Σ k n nᵀ: each spring resists along its own direction. No direction is
    // stiffer than k_anchor + Σ k, so a pull past that bound needs no solve: the region's resting edge
    // is judged every step (an LDLT for each was 16% of a held press's step on the 9,714 heart).
    const std::span<const std::uint32_t> springs = springsAt.of(i);
    double stiffest = anchor;
    for (const std::uint32_t s : springs) stiffest += model.springs.stiffness[s];
    if (f2 > stiffest * stiffest * reach * reach) return true;
    double xx = anchor, xy = 0, xz = 0, yy = anchor, yz = 0, zz = anchor;
    const std::vector<Vec3>& x = model.nodes.position;
    for (const std::uint32_t s : springs) {
        const Vec3 n = x[NodeSprings::otherEnd(model.springs, s, i)] - x[i];
        const double length2 = n.squaredNorm();
        if (length2 == 0) continue;
        const double c = model.springs.stiffness[s] / length2;
        xx += c * n.x() * n.x(), xy += c * n.x() * n.y(), xz += c * n.x() * n.z();
        yy += c * n.y() * n.y(), yz += c * n.y() * n.z(), zz += c * n.z() * n.z();
    }
    // d = adj(K) f / det(K), compared without dividing: |adj(K) f| > reach · det(K). A direction nothing
    // resists (no anchor, and springs in a plane pulled across it) has det(K) = 0: pulled.
    const double cxx = yy * zz - yz * yz, cxy = xz * yz - xy * zz, cxz = xy * yz - xz * yy;
    const double determinant = xx * cxx + xy * cxy + xz * cxz;
    if (!(determinant > 1e-12 * stiffest * stiffest * stiffest)) return true;
    const Mat3 adjugate{
        {cxx, cxy, cxz}, {cxy, xx * zz - xz * xz, xy * xz - xx * yz}, {cxz, xy * xz - xx * yz, xx * yy - xy * xy}};
    return (adjugate * force_N).squaredNorm() > reach * reach * determinant * determinant;
}

void ActiveRegion::updateSleep(const MassSpringModel& model, const NodeSprings& springsAt,
                               std::span<const Vec3> force) {
    // Resting neighbours that their springs pull off rest wake for the next step (a one-step delay, far
    // below what the tissue does in 1 ms).
    const Nodes& n = model.nodes;
    for (std::uint32_t i : touchedNodes_)
        if (!awake_[i] && pulledOffRest(model, springsAt, i, force[i])) wakeNext_[i] = 1;
    std::size_t kept = 0;
    for (std::uint32_t i : activeNodes_) {
        if (atRest(n, i) && !pulledOffRest(model, springsAt, i, force[i] * n.mass[i]) && !wakeNext_[i]) {
            awake_[i] = 0;
            dirty_ = true;
        } else {
            activeNodes_[kept++] = i;
        }
    }
    activeNodes_.resize(kept);
}

}  // namespace hapticut::physics
