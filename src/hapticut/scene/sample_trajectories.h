// The shipped sample trajectories, generated from the organ itself so they follow its front surface.
#pragma once

#include <vector>

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

/// The organ's front at (x, y), where a ray from +z first meets it (a point in front of the origin when
/// nothing is there), and its outward normal there across 3 mm of it: a hand follows the organ's shape,
/// not each facet's.
Vec3 frontPoint(const mesh::SurfaceMesh& organ, const collision::Bvh& bvh, double x, double y);
Vec3 frontNormal(const mesh::SurfaceMesh& organ, const collision::Bvh& bvh, double x, double y);

/// An incision as a trainee following a line drawn across the front makes it: the scalpel set on the
/// surface at (x0, y), drawn to x1 at 3 cm/s with the blade `depth_m` under the surface along its normal,
/// and lifted.
haptics::Trajectory incisionStroke(const mesh::SurfaceMesh& organ, const collision::Bvh& bvh, double y, double x0,
                                   double x1, double depth_m);

/// A palpation: the probe pressed 5 mm into the front along its normal at each point in turn, a second
/// apart, with a mark (the second button) in the press at index `mark` (none when out of range).
haptics::Trajectory palpationSession(const mesh::SurfaceMesh& organ, const collision::Bvh& bvh,
                                     const std::vector<Vec2>& presses, int mark);

}  // namespace hapticut::scene
