// A tool tip's footprint on the surface: the contact's load spread over the nodes under a tip of
// finite size, so that the same press meets the same tissue on a coarse and on a fine mesh of an organ.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "hapticut/collision/bvh.h"
#include "hapticut/mesh/vertex_faces.h"
#include "hapticut/physics/point_spring.h"

namespace hapticut::haptics {

/// The load of a tip of radius r pressing at c is a smooth pressure q(y) ∝ (1 - |y - c|²/r²)² over the
/// surface within r of c. Node i takes ∫ q N_i dA, N_i its linear hat function: the consistent load
/// vector of linear elements. A point load (the thesis's R9) meets anchors and springs that shrink with
/// the mesh, so a finer mesh feels softer; a load spread over a fixed area meets the same anchors per
/// area at any mesh finer than the tip. Each face near c is integrated by splitting it until its pieces
/// are under r/3 across, so a tip smaller than the faces gives the barycentric point load.
///
/// A mesh whose faces are larger than the tip cannot show the dent under it: its nodes spread the load
/// over their whole share of the surface. What it misses is a spring in series with the tool's
/// coupling: the centre of a footprint on anchors of k_p per m² sinks F / (k_p ∫q/q(0) dA), and the
/// touched triangle's corners give Σ N_k(c) w_k F / K_k of it. The rest is the footprint's subgrid
/// compliance, which falls to zero as the mesh resolves the tip.
struct FootprintSpread {
    bool complete = true;  // false: more nodes than a tool can load, cut to the nearest faces
    double subgridCompliance_m_per_N = 0;
};

class ContactFootprint {
public:
    /// Room for an organ of this many nodes and faces, and more to grow into; call again after cuts.
    void fitTo(std::size_t nodes, std::size_t faces);
    /// Fills `tool` with the nodes under a tip of radius_m touching `face` at `bary`, found by walking
    /// the faces round each vertex from the touched face outwards; `anchorStiffness_N_per_m` is the
    /// nodes' positioning springs, for the subgrid compliance. Allocation-free once fitted. The same as
    /// begin, advance with no limit and finish.
    FootprintSpread spread(const collision::SurfaceView& surface, const mesh::VertexFaces& around,
                           std::span<const double> anchorStiffness_N_per_m, std::uint32_t face, const Vec3& bary,
                           double radius_m, physics::PointSpring& tool) noexcept;

    /// A build in steps, so that a footprint of thousands of nodes costs a haptic step no more than the
    /// faces it is given: begin where the tip touches, advance a number of faces at a time until it says
    /// the footprint is whole, then finish into the tool. A new begin abandons a build under way.
    void begin(const collision::SurfaceView& surface, std::uint32_t face, const Vec3& bary, double radius_m) noexcept;
    /// Integrates up to `maxFaces` more faces; true once every face under the tip is in.
    bool advance(const collision::SurfaceView& surface, const mesh::VertexFaces& around, std::size_t maxFaces) noexcept;
    /// The faces the build under way has integrated or passed by so far.
    std::size_t facesDone() const noexcept { return next_; }
    /// Gives `tool` the footprint built (the touched triangle, as in the thesis, when nothing lay under
    /// the tip) and its subgrid compliance.
    FootprintSpread finish(const collision::SurfaceView& surface, const mesh::VertexFaces& around,
                           std::span<const double> anchorStiffness_N_per_m, physics::PointSpring& tool) noexcept;

private:
    /// ∫ q N_k dA over one face for its corners k, by splitting it into pieces under r/3 across.
    Vec3 integrateFace(const collision::SurfaceView& surface, std::uint32_t face, const Vec3& centre_m,
                       double radius_m) const noexcept;
    /// See FootprintSpread; `area_m2` is ∫q/q(0) dA, the footprint's area at full pressure.
    double subgridCompliance(const collision::SurfaceView& surface, const mesh::VertexFaces& around,
                             std::span<const double> anchorStiffness_N_per_m, double area_m2) const noexcept;

    // Stamps instead of flags, so nothing needs clearing between calls.
    std::vector<std::uint32_t> faceStamp_, nodeStamp_, nodeSlot_;
    std::uint32_t stamp_ = 0;
    std::vector<std::uint32_t> queue_;  // faces to look at, reserved once
    // The build under way: where the tip touches, how far the walk has gone, and the nodes and their
    // loads so far (kept here, not in a tool, so that the tool loads its last footprint meanwhile).
    std::uint32_t face_ = 0;
    Vec3 bary_ = Vec3::Zero(), centre_m_ = Vec3::Zero();
    double radius_m_ = 0, total_ = 0;
    std::size_t next_ = 0;
    bool complete_ = true;
    std::uint32_t count_ = 0;
    std::vector<std::uint32_t> nodes_;
    std::vector<double> loads_;
};

/// The pressure profile of a tip at s = distance / radius: (1 - s²)² inside, 0 outside; smooth at the
/// rim, so a node's share changes smoothly as the tip slides.
inline double tipPressure(double s) {
    const double u = 1 - s * s;
    return u > 0 ? u * u : 0;
}

}  // namespace hapticut::haptics
