// The shipped sample trajectories: a press, a probe's stroke and a scalpel's cut across the front of an organ.
#include "hapticut/scene/sample_trajectories.h"

#include <algorithm>
#include <cmath>
#include <tuple>

namespace hapticut::scene {

namespace {

/// The front surface of the organ at (x, y): where a ray from +z first meets it.
double frontSurfaceZ(const mesh::SurfaceMesh& organ, const collision::Bvh& bvh, double x, double y) {
    const collision::SurfaceView view{organ.positions, organ.faces};
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

haptics::Trajectory pressTrajectory(const mesh::SurfaceMesh& organ, const collision::Bvh& bvh, const Vec2& where) {
    const double z = frontSurfaceZ(organ, bvh, where.x(), where.y());
    haptics::Trajectory t;
    for (const auto& [time, dz] :
         {std::pair{0.0, 0.03}, {0.6, 0.005}, {1.0, -0.006}, {1.5, -0.006}, {1.8, 0.03}, {2.5, 0.03}})
        t.points.push_back(at(time, Vec3(where.x(), where.y(), z + dz), time >= 0.6 && time <= 1.5));
    return t;
}

haptics::Trajectory strokeTrajectory(const mesh::SurfaceMesh& organ, const collision::Bvh& bvh, double depth_m,
                                     const Vec2& where) {
    const double y = where.y(), x0 = where.x() - 0.02, x1 = where.x() + 0.02, depth = depth_m;
    haptics::Trajectory t;
    t.points.push_back(at(0.0, Vec3(x0, y, frontSurfaceZ(organ, bvh, x0, y) + 0.03)));
    t.points.push_back(at(0.6, Vec3(x0, y, frontSurfaceZ(organ, bvh, x0, y) + 0.003)));
    for (int i = 0; i <= 40; ++i) {  // 4 cm in 1 s, a sample every 25 ms
        const double x = x0 + (x1 - x0) * i / 40.0;
        t.points.push_back(at(0.9 + 0.025 * i, Vec3(x, y, frontSurfaceZ(organ, bvh, x, y) - depth), 1));
    }
    t.points.push_back(at(2.2, Vec3(x1, y, frontSurfaceZ(organ, bvh, x1, y) + 0.03)));
    t.points.push_back(at(2.8, Vec3(x1, y, frontSurfaceZ(organ, bvh, x1, y) + 0.03)));
    return t;
}

Vec3 frontPoint(const mesh::SurfaceMesh& organ, const collision::Bvh& bvh, double x, double y) {
    return Vec3(x, y, frontSurfaceZ(organ, bvh, x, y));
}

Vec3 frontNormal(const mesh::SurfaceMesh& organ, const collision::Bvh& bvh, double x, double y) {
    constexpr double d = 0.003;
    const Vec3 alongX = frontPoint(organ, bvh, x + d, y) - frontPoint(organ, bvh, x - d, y);
    const Vec3 alongY = frontPoint(organ, bvh, x, y + d) - frontPoint(organ, bvh, x, y - d);
    return alongX.cross(alongY).normalized();
}

haptics::Trajectory incisionStroke(const mesh::SurfaceMesh& organ, const collision::Bvh& bvh, double y, double x0,
                                   double x1, double depth_m) {
    const auto surface = [&](double x, double offset_m) -> Vec3 {
        return frontPoint(organ, bvh, x, y) + offset_m * frontNormal(organ, bvh, x, y);
    };
    haptics::Trajectory t;
    t.points.push_back(at(0.0, surface(x0, 0.03)));
    t.points.push_back(at(0.6, surface(x0, 0.003), 1));
    const int samples = std::max(1, static_cast<int>(std::lround(std::abs(x1 - x0) / 0.001)));  // a sample a millimetre
    const double end_s = 0.9 + std::abs(x1 - x0) / 0.03;
    for (int i = 0; i <= samples; ++i) {
        const double u = static_cast<double>(i) / samples;
        t.points.push_back(at(0.9 + u * (end_s - 0.9), surface(x0 + u * (x1 - x0), -depth_m), 1));
    }
    t.points.push_back(at(end_s + 0.3, surface(x1, 0.03)));
    return t;
}

haptics::Trajectory palpationSession(const mesh::SurfaceMesh& organ, const collision::Bvh& bvh,
                                     const std::vector<Vec2>& presses, int mark) {
    haptics::Trajectory t;
    double start = 0;
    for (std::size_t i = 0; i < presses.size(); ++i) {
        const Vec3 p = frontPoint(organ, bvh, presses[i].x(), presses[i].y());
        const Vec3 n = frontNormal(organ, bvh, presses[i].x(), presses[i].y());
        const bool marked = static_cast<int>(i) == mark;
        for (const auto& [time, offset, buttons] : {std::tuple{0.0, 0.02, 0u},
                                                    {0.3, 0.004, 1u},
                                                    {0.6, -0.005, 1u},
                                                    {0.75, -0.005, marked ? 3u : 1u},
                                                    {0.85, -0.005, 1u},
                                                    {1.0, 0.004, 1u}})
            t.points.push_back(at(start + time, p + offset * n, buttons));
        start += 1.2;
    }
    t.points.push_back(at(start, t.points.back().sample.position_m + 0.02 * Vec3::UnitZ()));
    return t;
}

}  // namespace hapticut::scene
