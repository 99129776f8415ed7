// The shipped sample trajectories, generated from the heart itself so they follow its front surface.
#pragma once

#include "hapticut/collision/bvh.h"
#include "hapticut/haptics/trajectory.h"
#include "hapticut/mesh/surface_mesh.h"

namespace hapticut::scene {

/// Press the front of the heart 6 mm deep, hold, release. Free until 0.6 s, after the force ramp.
haptics::Trajectory pressTrajectory(const mesh::SurfaceMesh& heart, const collision::Bvh& bvh);

/// Press `depth_m` into the front, stroke 4 cm across it following the surface, lift off. 4 mm is a
/// probe's stroke; 12 mm presses with about 2.5 N, past the scalpel's 2 N threshold, so it cuts.
haptics::Trajectory strokeTrajectory(const mesh::SurfaceMesh& heart, const collision::Bvh& bvh, double depth_m);

}  // namespace hapticut::scene
