// Enclosed volume and the pressure that keeps it.
#include "hapticut/physics/volume_pressure.h"

namespace hapticut::physics {

double enclosedVolume(std::span<const Vec3> x, std::span<const mesh::Face> faces) {
    double six = 0;
    for (const mesh::Face& f : faces) six += x[f[0]].dot(x[f[1]].cross(x[f[2]]));
    return six / 6;
}

double addPressureForces(std::span<const Vec3> x, std::span<const mesh::Face> faces, double bulk_Pa,
                         double restVolume_m3, std::span<Vec3> f) {
    const double volume = enclosedVolume(x, faces);
    if (!(restVolume_m3 > 0)) return volume;
    const double pressure = bulk_Pa * (restVolume_m3 - volume) / restVolume_m3;
    // dV/dx_a over face (a, b, c) is (x_b x x_c) / 6, and likewise round the face.
    for (const mesh::Face& face : faces) {
        const Vec3 &a = x[face[0]], &b = x[face[1]], &c = x[face[2]];
        f[face[0]] += (pressure / 6) * b.cross(c);
        f[face[1]] += (pressure / 6) * c.cross(a);
        f[face[2]] += (pressure / 6) * a.cross(b);
    }
    return volume;
}

}  // namespace hapticut::physics
