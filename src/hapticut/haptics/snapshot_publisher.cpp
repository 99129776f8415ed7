// Snapshot slots kept up to date through cuts.
#include "hapticut/haptics/snapshot_publisher.h"

#include <algorithm>

#include "hapticut/common/reserve.h"

namespace hapticut::haptics {

void SnapshotPublisher::prepare(std::span<const Vec3> positions, std::span<const mesh::Face> faces,
                                std::span<const mesh::FaceUvs> uvs, long version, int handCount) {
    // Room for what cuts add, as the organ's own arrays have (CutModel), so publishing rarely allocates.
    for (Snapshot& s : buffer_.slots()) {
        reserveTouched(s.positions, roomToGrow(positions.size()));
        s.positions.resize(positions.size());
        reserveTouched(s.faces, roomToGrow(faces.size()));
        s.faces.assign(faces.begin(), faces.end());
        reserveTouched(s.uvs, roomToGrow(faces.size()));
        s.uvs.assign(uvs.begin(), uvs.end());
        s.topologyVersion = version;
        s.handCount = handCount;
    }
    slotVersion_.fill(version);
    faceLog_.clear();
    faceLog_.reserve(4096);
}

void SnapshotPublisher::facesChanged(long version, std::span<const std::uint32_t> faces) {
    for (std::uint32_t f : faces) faceLog_.push_back({version, f});
}

Snapshot& SnapshotPublisher::fill(std::span<const Vec3> positions, std::span<const mesh::Face> faces,
                                  std::span<const mesh::FaceUvs> uvs, long version) {
    Snapshot& s = buffer_.writeSlot();
    // Sizes change only after a cut; the slots were reserved with room to grow.
    s.positions.assign(positions.begin(), positions.end());
    if (s.topologyVersion != version) {
        // Catch up on the faces the cuts since this slot's version changed, not the whole mesh.
        s.faces.resize(faces.size());
        s.uvs.resize(uvs.size());
        for (const FaceChange& c : faceLog_) {
            if (c.version <= s.topologyVersion) continue;
            s.faces[c.face] = faces[c.face];
            if (c.face < uvs.size()) s.uvs[c.face] = uvs[c.face];
        }
        s.topologyVersion = version;
        slotVersion_[static_cast<std::size_t>(&s - buffer_.slots().data())] = version;
        // What every slot has is needed no more.
        const long everywhere = *std::min_element(slotVersion_.begin(), slotVersion_.end());
        faceLog_.erase(faceLog_.begin(), std::find_if(faceLog_.begin(), faceLog_.end(),
                                                      [&](const FaceChange& c) { return c.version > everywhere; }));
    }
    return s;
}

}  // namespace hapticut::haptics
