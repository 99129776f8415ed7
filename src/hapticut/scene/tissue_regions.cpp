// Regions as a field: spheres and boxes by their equations, meshes by ray parity on their own tree.
#include "hapticut/scene/tissue_regions.h"

#include <memory>

#include "hapticut/collision/bvh.h"
#include "hapticut/collision/point_inside.h"
#include "hapticut/mesh/mesh_report.h"
#include "hapticut/scene/model_source.h"

namespace hapticut::scene {

namespace {

/// A mesh region's surface and its tree, shared by every copy of the field.
struct RegionSurface {
    mesh::SurfaceMesh mesh;
    collision::Bvh bvh;
    collision::SurfaceView view() const { return {mesh.positions, mesh.faces}; }
};

struct PlacedRegion {
    SceneRegion region;
    std::shared_ptr<const RegionSurface> surface;  // mesh regions only

    bool holds(const Vec3& p) const {
        switch (region.shape) {
            case SceneRegion::Shape::Sphere:
                return (p - region.center_m).squaredNorm() <= region.radius_m * region.radius_m;
            case SceneRegion::Shape::Box:
                return ((p - region.center_m).cwiseAbs().array() <= 0.5 * region.size_m.array()).all();
            case SceneRegion::Shape::Mesh: return collision::insideClosedSurface(surface->bvh, surface->view(), p);
        }
        return false;
    }
};

}  // namespace

Result<physics::MaterialField, Error> materialField(const std::vector<SceneRegion>& regions,
                                                    const std::filesystem::path& sceneFile) {
    if (regions.empty()) return physics::MaterialField{};
    std::vector<PlacedRegion> placed;
    for (std::size_t i = 0; i < regions.size(); ++i) {
        PlacedRegion r{regions[i], nullptr};
        if (r.region.shape == SceneRegion::Shape::Mesh) {
            const std::string where = "regions[" + std::to_string(i) + "].mesh: ";
            auto source = loadModelSource(r.region.mesh, 0, {});
            if (!source) return unexpected(Error{sceneFile, r.region.line, where + source.error().toString()});
            const mesh::MeshReport report = mesh::validateMesh(source->mesh);
            if (!report.closed)
                return unexpected(Error{sceneFile, r.region.line,
                                        where + r.region.mesh + " is not a closed surface (" +
                                            std::to_string(report.boundaryEdges) +
                                            " open edges): its inside is not defined; hapticut convert --repair"});
            auto surface = std::make_shared<RegionSurface>();
            surface->mesh = std::move(source->mesh);
            surface->bvh.build(surface->view());
            r.surface = std::move(surface);
        }
        placed.push_back(std::move(r));
    }
    return physics::MaterialField([placed = std::move(placed)](const Vec3& p) {
        for (auto r = placed.rbegin(); r != placed.rend(); ++r)
            if (r->holds(p))
                return physics::MaterialScale{r->region.stiffnessScale, r->region.dampingScale,
                                              r->region.toughnessScale};
        return physics::MaterialScale{};
    });
}

}  // namespace hapticut::scene
