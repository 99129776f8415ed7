// Publishing snapshots from the loop to the renderer through a triple buffer, bringing each slot's
// positions and faces up to date from what moved and what the cuts changed since the slot was last
// written, instead of copying the whole organ.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "hapticut/common/triple_buffer.h"
#include "hapticut/haptics/snapshot.h"

namespace hapticut::haptics {

class SnapshotPublisher {
public:
    /// Sizes every slot for the organ, with room to grow as cuts add to it, and fills it with the organ as it
    /// is, at topology version `version`.
    void prepare(std::span<const Vec3> positions, std::span<const mesh::Face> faces, std::span<const mesh::FaceUvs> uvs,
                 std::span<const std::uint8_t> walls, long version, int handCount);
    /// The faces that topology version `version` rewrote or added; kept until every slot has them.
    void facesChanged(long version, std::span<const std::uint32_t> faces);
    /// The nodes a step moved (repeats allowed); each slot copies them when next filled. Past a quarter
    /// of the organ a slot copies everything instead.
    void nodesMoved(std::span<const std::uint32_t> nodes);
    /// Every node may have moved (a reset): each slot copies them all when next filled.
    void allNodesMoved() { wholeCopy_.fill(true); }
    /// The slot to write, its positions copied and its faces, UVs and wall flags caught up to `version`;
    /// the caller fills in the rest and calls publish(). Allocation-free while the organ stays within its
    /// room to grow.
    Snapshot& fill(std::span<const Vec3> positions, std::span<const mesh::Face> faces,
                   std::span<const mesh::FaceUvs> uvs, std::span<const std::uint8_t> walls, long version);
    void publish() { buffer_.publish(); }
    /// How many nodes' positions the last fill copied.
    std::size_t copiedByLastFill() const { return copiedByLastFill_; }

    TripleBuffer<Snapshot>& buffer() { return buffer_; }

private:
    struct FaceChange {
        long version;
        std::uint32_t face;
    };
    TripleBuffer<Snapshot> buffer_;
    std::vector<FaceChange> faceLog_;
    std::array<long, 3> slotVersion_{};  // the topology version each slot was last brought to
    // Per slot: the nodes moved since it was last filled, marked so each is listed once, or a whole copy.
    std::array<std::vector<std::uint32_t>, 3> moved_;
    std::array<std::vector<std::uint8_t>, 3> movedMark_;
    std::array<bool, 3> wholeCopy_{};
    std::size_t copiedByLastFill_ = 0;
};

}  // namespace hapticut::haptics
