// The active region (local simulation after Mosegaard & Sørensen 2004): which nodes move and must be
// integrated, which springs act on them, and when nodes fall asleep and wake.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "hapticut/physics/mass_spring_model.h"
#include "hapticut/physics/node_springs.h"

namespace hapticut::physics {

/// A node sleeps once the thesis's snap rule holds it at rest and the force on it is negligible; it
/// wakes when a spring pulls on it, when a tool touches it, or by wake(). Sleeping nodes sit exactly
/// at rest, so the forces between them are exactly zero and leaving them out changes nothing.
/// Nothing here allocates once reserved; every pass is proportional to the region, not the model.
class ActiveRegion {
public:
    /// Capacity for `nodes` and `springs`, touched up front.
    void reserve(std::size_t nodes, std::size_t springs);
    /// Starts over on `model`: every node that is not at rest wakes for the next step.
    void reset(const MassSpringModel& model);
    /// After a cut: room for the model's new nodes and springs, which start asleep.
    void resize(std::size_t nodes, std::size_t springs);
    /// The lists are rebuilt before the next step (the springs at the awake nodes changed).
    void invalidate() { dirty_ = true; }
    /// Wakes `node` for the next step.
    void wake(std::uint32_t node);

    /// Before a step: admits the tools' nodes and their neighbours, the resting neighbours that
    /// updateSleep flagged, and the nodes wake() named; rebuilds the lists if the region changed.
    void admit(const MassSpringModel& model, const NodeSprings& springsAt);
    /// After a step: `force` holds, for nodes(), the accelerations at the end state and, for the rest
    /// of touched(), the spring force on them in newtons (computeActiveAccelerations, or
    /// computeListedAccelerations for at least the nodes at rest). Resting neighbours pulled off rest
    /// (pulledOffRest) wake next step; awake nodes at rest that are not fall asleep.
    void updateSleep(const MassSpringModel& model, const NodeSprings& springsAt, std::span<const Vec3> force);

    /// Whether node i sits exactly at rest, still: the only state a node sleeps in.
    static bool atRest(const Nodes& n, std::uint32_t i) {
        return n.position[i] == n.restPosition[i] && n.velocity[i] == Vec3::Zero();
    }
    /// Whether node i, at rest under this force (N), would settle beyond the snap distance if it alone
    /// were let go, held by its anchor and its springs to its neighbours where they are: such a node
    /// wakes, stays awake, and is not put back at rest (Stepper::step). Judged by its anchor alone, the
    /// edge of a held press's region was woken by pulls its springs held within the snap distance, and
    /// the region changed in every step of a press held on the 100,000 heart.
    static bool pulledOffRest(const MassSpringModel& model, const NodeSprings& springsAt, std::uint32_t i,
                              const Vec3& force_N);

    /// The awake nodes: the ones integrated.
    std::span<const std::uint32_t> nodes() const { return activeNodes_; }
    /// The awake nodes and their resting neighbours: every node an active spring reads.
    std::span<const std::uint32_t> touched() const { return touchedNodes_; }
    /// The springs with an awake end.
    std::span<const std::uint32_t> springs() const { return activeSprings_; }
    /// 1 for an awake node, per node of the model.
    std::span<const std::uint8_t> awakeFlags() const { return awake_; }
    /// Changes whenever the lists do.
    std::uint64_t version() const { return version_; }

private:
    void rebuild(const MassSpringModel& model, const NodeSprings& springsAt);

    bool dirty_ = true;
    std::uint64_t version_ = 0;
    std::vector<std::uint8_t> awake_, touchedMark_, springMark_, wakeNext_;
    std::vector<std::uint32_t> activeNodes_, touchedNodes_, activeSprings_, wakeList_;
    std::vector<std::uint32_t> merged_;  // rebuild's room to merge newly admitted nodes into the sorted ones
};

}  // namespace hapticut::physics
