// The snapshot slots: filled with the organ when prepared, so the first snapshots copy only what moved.
#include "hapticut/haptics/snapshot_publisher.h"

#include <gtest/gtest.h>

#include <vector>

namespace hapticut::haptics {
namespace {

struct Organ {
    std::vector<Vec3> positions;
    std::vector<mesh::Face> faces;
    std::vector<mesh::FaceUvs> uvs;
    std::vector<std::uint8_t> walls;
    explicit Organ(std::size_t nodes) {
        for (std::size_t i = 0; i < nodes; ++i) positions.emplace_back(0.001 * static_cast<double>(i), 0.5, -0.25);
        for (std::uint32_t i = 0; i + 2 < nodes; ++i) faces.push_back({i, i + 1, i + 2});
        uvs.resize(faces.size());
        walls.assign(faces.size(), 0);
    }
};

// A slot a renderer reads before the first snapshot, and every slot the loop fills first, hold the
// organ as prepared: the first fills copy only the nodes that moved since (a whole copy of a
// 1,000,000-triangle organ took the haptic thread 2 ms a slot, and made its only overruns).
TEST(SnapshotPublisher, TheFirstSnapshotsCopyOnlyWhatMovedSinceThePreparation) {
    Organ organ(1000);
    SnapshotPublisher publisher;
    publisher.prepare(organ.positions, organ.faces, organ.uvs, organ.walls, 0, 1);
    EXPECT_EQ(publisher.buffer().readLatest().positions, organ.positions) << "read before any snapshot";
    for (int fill = 0; fill < 3; ++fill) {  // each of the three slots in turn
        const auto moved = static_cast<std::uint32_t>(7 * fill + 3);
        organ.positions[moved].x() += 1e-3;
        const std::uint32_t list[] = {moved};
        publisher.nodesMoved(list);
        (void)publisher.fill(organ.positions, organ.faces, organ.uvs, organ.walls, 0);
        publisher.publish();
        // The slot copied what moved since it was last written: here, since it was prepared.
        EXPECT_EQ(publisher.copiedByLastFill(), static_cast<std::size_t>(fill + 1)) << "fill " << fill;
        // Read as a renderer does, which hands the writer the slot it held: the three slots take turns.
        EXPECT_EQ(publisher.buffer().readLatest().positions, organ.positions) << "fill " << fill;
    }
    // A reset moves every node: the next fill copies them all.
    publisher.allNodesMoved();
    (void)publisher.fill(organ.positions, organ.faces, organ.uvs, organ.walls, 0);
    EXPECT_EQ(publisher.copiedByLastFill(), organ.positions.size());
}

}  // namespace
}  // namespace hapticut::haptics
