// The shipped sample trajectories: a press, a probe's stroke and a scalpel's cut across the front of the heart.
#include "hapticut/scene/sample_trajectories.h"

namespace hapticut::scene {

namespace {

/// The front surface of the heart at (x, y): where a ray from +z first meets it.
double frontSurfaceZ(const mesh::SurfaceMesh& heart, const collision::Bvh& bvh, double x, double y) {
    const collision::SurfaceView view{heart.positions, heart.faces};
    const auto hit = bvh.firstHit(view, Vec3(x, y, 0.2), Vec3(x, y, -0.2));
    return hit ? hit->point.z() : 0.0;
}

haptics::TrajectoryPoint at(double t, const Vec3& p, std::uint32_t button = 0) {
    haptics::TrajectoryPoint point;
    point.t_s = t;
    point.sample.position_m = p;
    point.sample.buttons = button;
    return point;
}

}  // namespace

haptics::Trajectory pressTrajectory(const mesh::SurfaceMesh& heart, const collision::Bvh& bvh) {
    const double z = frontSurfaceZ(heart, bvh, 0.0, -0.01);
    haptics::Trajectory t;
    for (const auto& [time, dz] :
         {std::pair{0.0, 0.03}, {0.6, 0.005}, {1.0, -0.006}, {1.5, -0.006}, {1.8, 0.03}, {2.5, 0.03}})
        t.points.push_back(at(time, Vec3(0.0, -0.01, z + dz), time >= 0.6 && time <= 1.5));
    return t;
}

haptics::Trajectory strokeTrajectory(const mesh::SurfaceMesh& heart, const collision::Bvh& bvh, double depth_m) {
    const double y = -0.01, x0 = -0.02, x1 = 0.02, depth = depth_m;
    haptics::Trajectory t;
    t.points.push_back(at(0.0, Vec3(x0, y, frontSurfaceZ(heart, bvh, x0, y) + 0.03)));
    t.points.push_back(at(0.6, Vec3(x0, y, frontSurfaceZ(heart, bvh, x0, y) + 0.003)));
    for (int i = 0; i <= 40; ++i) {  // 4 cm in 1 s, a sample every 25 ms
        const double x = x0 + (x1 - x0) * i / 40.0;
        t.points.push_back(at(0.9 + 0.025 * i, Vec3(x, y, frontSurfaceZ(heart, bvh, x, y) - depth), 1));
    }
    t.points.push_back(at(2.2, Vec3(x1, y, frontSurfaceZ(heart, bvh, x1, y) + 0.03)));
    t.points.push_back(at(2.8, Vec3(x1, y, frontSurfaceZ(heart, bvh, x1, y) + 0.03)));
    return t;
}

}  // namespace hapticut::scene
