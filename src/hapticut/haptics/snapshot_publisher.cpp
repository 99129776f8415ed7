// Snapshot slots kept up to date through cuts.
#include "hapticut/haptics/snapshot_publisher.h"

#include <algorithm>

#include "hapticut/common/reserve.h"

namespace hapticut::haptics {

void SnapshotPublisher::prepare(std::span<const Vec3> positions, std::span<const mesh::Face> faces,
                                std::span<const mesh::FaceUvs> uvs, std::span<const std::uint8_t> walls, long version,
                                int handCount) {
    // Room for what cuts add, as the organ's own arrays have (CutModel), so publishing rarely allocates.
    for (Snapshot& s : buffer_.slots()) {
        reserveTouched(s.positions, roomToGrow(positions.size()));
        s.positions.assign(positions.begin(), positions.end());
        reserveTouched(s.faces, roomToGrow(faces.size()));
        s.faces.assign(faces.begin(), faces.end());
        reserveTouched(s.uvs, roomToGrow(faces.size()));
        s.uvs.assign(uvs.begin(), uvs.end());
        reserveTouched(s.wallFaces, roomToGrow(faces.size()));
        s.wallFaces.assign(walls.begin(), walls.end());
        s.topologyVersion = version;
        s.handCount = handCount;
    }
    slotVersion_.fill(version);
    for (std::size_t k = 0; k < 3; ++k) {
        moved_[k].clear();
        reserveTouched(moved_[k], positions.size() / 4 + 1);
        reserveTouched(movedMark_[k], roomToGrow(positions.size()));
        movedMark_[k].assign(positions.size(), 0);
    }
    // Every slot starts with the organ as it is, so the first snapshots copy only what moved: the whole
    // copy they made took the haptic thread 2 ms a slot on a 1,000,000-triangle organ.
    wholeCopy_.fill(false);
    faceLog_.clear();
    faceLog_.reserve(4096);
}

void SnapshotPublisher::nodesMoved(std::span<const std::uint32_t> nodes) {
    for (std::size_t k = 0; k < 3; ++k) {
        if (wholeCopy_[k]) continue;
        std::vector<std::uint32_t>& list = moved_[k];
        std::vector<std::uint8_t>& mark = movedMark_[k];
        for (std::uint32_t i : nodes) {
            if (i >= mark.size()) continue;        // a node added since this slot was filled: it copies the new tail
            if (list.size() == list.capacity()) {  // too many: copy all
                wholeCopy_[k] = true;
                break;
            }
            if (!mark[i]) mark[i] = 1, list.push_back(i);
        }
    }
}

void SnapshotPublisher::facesChanged(long version, std::span<const std::uint32_t> faces) {
    for (std::uint32_t f : faces) faceLog_.push_back({version, f});
}

Snapshot& SnapshotPublisher::fill(std::span<const Vec3> positions, std::span<const mesh::Face> faces,
                                  std::span<const mesh::FaceUvs> uvs, std::span<const std::uint8_t> walls,
                                  long version) {
    Snapshot& s = buffer_.writeSlot();
    const auto slot = static_cast<std::size_t>(&s - buffer_.slots().data());
    // Only what moved since this slot was last written, and the nodes cuts added since (at the end: the
    // slots were reserved with room to grow); all of it when too much moved. Copying every node after
    // each cut cost the haptic thread a millisecond a slot on a 1,000,000-triangle organ.
    if (wholeCopy_[slot]) {
        s.positions.assign(positions.begin(), positions.end());
        copiedByLastFill_ = positions.size();
    } else {
        const std::size_t had = std::min(s.positions.size(), positions.size());
        s.positions.resize(positions.size());
        std::copy(positions.begin() + static_cast<std::ptrdiff_t>(had), positions.end(),
                  s.positions.begin() + static_cast<std::ptrdiff_t>(had));
        copiedByLastFill_ = positions.size() - had;
        for (std::uint32_t i : moved_[slot])
            if (i < had) s.positions[i] = positions[i], ++copiedByLastFill_;
    }
    for (std::uint32_t i : moved_[slot]) movedMark_[slot][i] = 0;
    moved_[slot].clear();
    if (movedMark_[slot].size() < positions.size()) movedMark_[slot].resize(positions.size(), 0);  // a cut grew it
    wholeCopy_[slot] = false;
    if (s.topologyVersion != version) {
        // Catch up on the faces the cuts since this slot's version changed, not the whole mesh.
        s.faces.resize(faces.size());
        s.uvs.resize(uvs.size());
        s.wallFaces.resize(walls.size());
        for (const FaceChange& c : faceLog_) {
            if (c.version <= s.topologyVersion) continue;
            s.faces[c.face] = faces[c.face];
            if (c.face < uvs.size()) s.uvs[c.face] = uvs[c.face];
            if (c.face < walls.size()) s.wallFaces[c.face] = walls[c.face];
        }
        s.topologyVersion = version;
        slotVersion_[slot] = version;
        // What every slot has is needed no more.
        const long everywhere = *std::min_element(slotVersion_.begin(), slotVersion_.end());
        faceLog_.erase(faceLog_.begin(), std::find_if(faceLog_.begin(), faceLog_.end(),
                                                      [&](const FaceChange& c) { return c.version > everywhere; }));
    }
    return s;
}

}  // namespace hapticut::haptics
