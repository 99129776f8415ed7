// The shipped sample trajectories, generated from the organ itself so they follow its front surface.
#pragma once

#include "hapticut/collision/bvh.h"
#include "hapticut/haptics/trajectory.h"
#include "hapticut/mesh/surface_mesh.h"

namespace hapticut::scene {

/// The heart's front where the shipped trajectories touch it: 1 cm below its centre (x, y in metres).
inline const Vec2 kHeartFront(0.0, -0.01);

/// Press the organ's front at `where` (x, y) 6 mm deep, hold, release. Free until 0.6 s, after the force ramp.
haptics::Trajectory pressTrajectory(const mesh::SurfaceMesh& organ, const collision::Bvh& bvh,
                                    const Vec2& where = kHeartFront);

/// Press `depth_m` into the front, stroke 4 cm across it in x, centred on `where`, following the surface,
/// lift off. 4 mm is a probe's stroke; 12 mm presses the heart with about 2.5 N, past the scalpel's 2 N
/// threshold, so it cuts.
haptics::Trajectory strokeTrajectory(const mesh::SurfaceMesh& organ, const collision::Bvh& bvh, double depth_m,
                                     const Vec2& where = kHeartFront);

}  // namespace hapticut::scene
