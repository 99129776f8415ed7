// Procedural tool meshes: the scalpel and the probe. Units are metres; the tool's interaction point is
// the origin and the handle runs along +z, toward the user, as a stylus does in a haptic device's frame.
#include "hapticut/mesh/procedural/tools.h"

#include <array>

#include "hapticut/mesh/procedural/primitives.h"

namespace hapticut::mesh::procedural {

SurfaceMesh makeScalpel() {
    // Blade profile in the plane of the blade (x across, z along the tool), extruded 0.6 mm thick in y.
    const std::array<Vec2, 5> blade = {Vec2(0.0, 0.0), Vec2(0.004, 0.012), Vec2(0.004, 0.030), Vec2(-0.003, 0.030),
                                       Vec2(-0.003, 0.010)};
    SurfaceMesh prism = makePrism(blade, -0.0003, 0.0003);
    // makePrism extrudes along z; turn it so the profile's second axis runs along the tool (+z).
    for (Vec3& p : prism.positions) p = Vec3(p.x(), p.z(), p.y());
    for (Face& f : prism.faces) std::swap(f[1], f[2]);  // the axis swap mirrors, so restore outward winding
    computeFaceNormals(prism);

    SurfaceMesh scalpel = prism;
    appendMesh(scalpel, makeCylinder(Vec3(0, 0, 0.028), Vec3::UnitZ(), 0.0045, 0.100, 16));
    return scalpel;
}

SurfaceMesh makeProbe() {
    SurfaceMesh probe = makeSphere(Vec3(0, 0, 0.0025), 0.0025, 12, 8);
    appendMesh(probe, makeCylinder(Vec3(0, 0, 0.004), Vec3::UnitZ(), 0.0015, 0.120, 12));
    return probe;
}

}  // namespace hapticut::mesh::procedural
