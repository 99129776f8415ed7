// The organ as cutting changes it: surface and mass-spring model kept consistent under topology edits
// (SPEC R15-R16), with the lookups the cutter needs (faces around a vertex, the spring of an edge).
#pragma once

#include <cstdint>
#include <initializer_list>
#include <optional>
#include <utility>
#include <vector>

#include "hapticut/common/flat_key_map.h"
#include "hapticut/mesh/surface_mesh.h"
#include "hapticut/mesh/vertex_faces.h"
#include "hapticut/physics/mass_spring_model.h"
#include "hapticut/physics/material.h"

namespace hapticut::cutting {

/// What the edits since the last clearChanges() touched, so that the haptic loop brings its stepper,
/// tree and snapshots up to date in time proportional to the cut rather than to the organ. Entries
/// may repeat; every consumer treats them as a set.
struct TopologyChanges {
    std::vector<std::uint32_t>
        nodes;  // new, or their mass, anchor or springs changed (both ends of every listed spring)
    std::vector<std::uint32_t> springs;  // new, or their ends, rest length or stiffness changed
    std::vector<std::uint32_t> faces;    // new, or their corners changed
    bool empty() const { return nodes.empty() && springs.empty() && faces.empty(); }
    void clear() { nodes.clear(), springs.clear(), faces.clear(); }
};

/// Node i of the model is vertex i of the mesh; spring k of the model is an edge of the faces.
/// mesh.positions hold the rest (undeformed) shape, model.nodes.position the deformed one.
class CutModel {
public:
    /// `field`: the tissue's regions (physics::applyMaterialField has scaled `model` by it); the springs and
    /// anchors cuts add take the scale where they are. Empty: uniform tissue.
    CutModel(mesh::SurfaceMesh mesh, physics::MassSpringModel model, physics::MaterialField field = {});

    const mesh::SurfaceMesh& mesh() const { return mesh_; }
    const physics::MassSpringModel& model() const { return model_; }
    /// Whether the organ was closed (every edge on two faces) before any cut; with walls it stays so.
    bool closedBeforeCuts() const { return closedBeforeCuts_; }
    physics::MassSpringModel& model() { return model_; }

    const std::vector<std::uint32_t>& facesAround(std::uint32_t vertex) const { return facesAround_.around[vertex]; }
    /// The faces around every vertex, kept current through every edit (the proxy's fast path reads it).
    const mesh::VertexFaces& vertexFaces() const { return facesAround_; }
    /// Everything the edits changed since the last clearChanges().
    const TopologyChanges& changes() const { return changes_; }
    void clearChanges() { changes_.clear(); }

    /// The spring along edge (a, b), if there is one.
    std::optional<std::uint32_t> springOf(std::uint32_t a, std::uint32_t b) const;
    /// The faces that have edge (a, b), in any orientation (two on a manifold interior edge).
    std::vector<std::uint32_t> facesOfEdge(std::uint32_t a, std::uint32_t b) const;
    /// The same into `out`, which keeps its memory from call to call.
    void facesOfEdge(std::uint32_t a, std::uint32_t b, std::vector<std::uint32_t>& out) const;
    /// Whether edge (a, b) is an open end of the organ, a wound's lip or inside its walls: on fewer than
    /// two faces, or on a wall. Cuts stop there and openings do not shorten its spring. Allocates nothing.
    bool onRim(std::uint32_t a, std::uint32_t b) const;
    /// The rim as the blade on the surface meets it: an open end or a wound's lip, with the organ's
    /// surface on at least one side; not an edge inside a wound's walls, down to its floor.
    bool onSurfaceRim(std::uint32_t a, std::uint32_t b) const;
    /// Whether edge (a, b) is an open end: on one face only.
    bool isOpenEdge(std::uint32_t a, std::uint32_t b) const;

    /// R15: a new vertex inside `face` at barycentric `bary` of the face's rest triangle, which becomes
    /// three faces. The rest position lies on the undeformed face, so the new springs get correct rest
    /// lengths; the deformed position and velocity are interpolated; UVs are interpolated per corner;
    /// the face's three masses are shared among the four vertices (total conserved exactly).
    std::uint32_t splitFace(std::uint32_t face, const Vec3& bary);

    /// R16: a new vertex on edge (a, b) at a + u (b - a), u in (0, 1); both faces on the edge become
    /// two each, the edge's spring becomes two, and springs join the new vertex to the opposite corners.
    /// The new vertex takes a share of a's and b's mass (total conserved exactly).
    std::uint32_t splitEdge(std::uint32_t a, std::uint32_t b, double u);

    /// R17: opens the cut at v, the cut running prev -> v -> next along mesh edges. The faces on the
    /// left of the cut (seen from outside) that use v get a duplicate v' at the same place: positioning
    /// spring, half of v's mass, the left side's springs moved to it, new springs along the cut edges for
    /// the new lip. Then every spring at v and v' except those along the cut (the lips) is shortened
    /// by `shorten` (0.1: 10%), so the wound pulls open. Stiff positioning springs hold every node to its
    /// anchor, so shortening alone barely opens a wound: `retract` moves the two copies' anchors apart,
    /// each by that fraction of the local edge length, across the cut in the surface's plane, as cut
    /// tissue under tension retracts. The walk round v stops at the edge to prev or at a
    /// boundary, so an already opened prev (a progressive cut) works the same. Returns v', or nothing
    /// when v has no face on the left of v -> next.
    /// When prev opened with walls (closeOpening), the walk stops instead at prev's floor vertex, the
    /// far side of the wall that closed the cut's tip, so the walls stay with their own side.
    std::optional<std::uint32_t> openCut(std::uint32_t prev, std::uint32_t v, std::uint32_t next, double shorten = 0.1,
                                         double retract = 0);

    /// SPEC beyond (thesis 2.3): after openCut(prev, v, next) gave v its copy w, the gap between the lips
    /// is closed with walls, so a closed organ stays closed and the tool meets tissue inside the wound.
    /// The gap is a hole of four edges, v -> next -> w -> behind (behind: prev, or prev's floor vertex);
    /// a floor vertex q goes `depth_m` under v into the organ, with mass (a share of v's and w's) and an
    /// anchor, and four wall faces join q to the hole's edges, with springs from q to each corner. The
    /// floor vertices of a cut form its floor curve, where its two walls meet. Returns q, or nothing when
    /// the gap is not such a hole (it ran into the organ's open rim), which is then left open.
    /// `amongCorners`: the floor vertex goes to the middle of the hole's corners instead (v and w side by
    /// side counted as one place), for a cut through an earlier wound's wall (one corner is that wound's
    /// floor, right under v): a floor under v would lie on the wall's own line and make its faces slivers.
    std::optional<std::uint32_t> closeOpening(std::uint32_t v, std::uint32_t w, double depth_m,
                                              bool amongCorners = false);
    /// The floor vertex the walls under v's opening meet at, if v opened with walls.
    std::optional<std::uint32_t> floorUnder(std::uint32_t v) const;
    /// Per face: 1 for a wound's wall (closeOpening made it, or a cut split one), 0 for the organ's surface.
    const std::vector<std::uint8_t>& wallFaces() const { return wall_; }
    bool isWall(std::uint32_t face) const { return wall_[face] != 0; }
    bool hasCorner(std::uint32_t face, std::uint32_t v) const {
        const mesh::Face& f = mesh_.faces[face];
        return f[0] == v || f[1] == v || f[2] == v;
    }
    /// Whether every face round v is a wall: a wound's floor vertex, down inside the organ.
    bool isFloor(std::uint32_t v) const;

    /// Where a cut meets an open boundary or an earlier wound, or starts on one, the vertex there is left
    /// joining two fans of faces that touch only at it. This gives each fan beyond the first its own
    /// copy of v (same place and anchor, v's mass shared by the fans' face counts, the fan's springs
    /// moved to it), so the wounds join into one opening and the surface stays manifold. Returns how
    /// many copies it made (0 when v's faces form one fan).
    int separateFans(std::uint32_t v);
    /// The fans of faces round v: faces joined across the edges through v that two faces share.
    /// Each fan's faces are listed together; `fanStart` gives where each fan begins (plus the end).
    void fansAround(std::uint32_t v, std::vector<std::uint32_t>& faces, std::vector<std::uint32_t>& fanStart) const;

    /// The smallest angle (degrees) of the faces splitEdge(a, b, u) would make, on the rest shape.
    double splitEdgeMinAngle_deg(std::uint32_t a, std::uint32_t b, double u) const;
    /// The smallest angle (degrees) of the faces splitFace(face, bary) would make, on the rest shape.
    double splitFaceMinAngle_deg(std::uint32_t face, const Vec3& bary) const;

    /// The vertex of `face` nearest to the rest point at `bary`, if it lies within `radius_m`.
    std::optional<std::uint32_t> snapVertex(std::uint32_t face, const Vec3& bary, double radius_m) const;

    /// The tissue's scale at a point of the rest shape: its region's, or none.
    physics::MaterialScale scaleAt(const Vec3& rest) const { return field_ ? field_(rest) : physics::MaterialScale{}; }

    /// For whoever holds views of model().nodes.position between edits (Python's no-copy array): when a
    /// cut outgrows the array, the old one is kept for takeRetiredPositions() instead of freed, so the
    /// views read stale numbers, never freed memory. Off by default.
    void keepRetiredPositions(bool keep) { keepRetiredPositions_ = keep; }
    /// The arrays the node positions moved out of since the last call, oldest first.
    std::vector<std::vector<Vec3>> takeRetiredPositions() { return std::exchange(retiredPositions_, {}); }

private:
    struct EdgeFaces {
        int surface = 0, wall = 0;  // faces on edge (a, b) of the organ's surface and of wounds' walls
        int total() const { return surface + wall; }
    };
    EdgeFaces edgeFaces(std::uint32_t a, std::uint32_t b) const;
    /// By value: callers pass elements of the very arrays this grows (a copy of vertex v), which a
    /// reallocation would leave dangling mid-call.
    std::uint32_t addVertex(Vec3 rest, Vec3 position, Vec3 velocity, double mass);
    void addSpring(std::uint32_t a, std::uint32_t b);
    /// v's mass is now `mass`; its anchor follows (mass follows area).
    void setMass(std::uint32_t v, double mass);
    /// Spring k now runs from `from`'s end to `to` (its other end unchanged).
    void moveSpringEnd(std::uint32_t k, std::uint32_t from, std::uint32_t to);
    void touchSpring(std::uint32_t k);
    void replaceFace(std::uint32_t face, const mesh::Face& corners, const mesh::FaceUvs& uvs);
    /// A new face; `wall`: a wound's wall.
    std::uint32_t appendFace(const mesh::Face& corners, const mesh::FaceUvs& uvs, bool wall, std::uint32_t part);
    /// A new spring's (or a shortened one's) stiffness and damping for its rest ends.
    void setSpringMaterial(std::uint32_t k, const Vec3& restA, const Vec3& restB, double length);
    /// The unit normal of the rest surface round v and its copies `others`, over the organ's own faces
    /// (walls would tilt it); over all faces when v has only walls; zero when they cancel out.
    Vec3 restNormalAround(std::uint32_t v, std::initializer_list<std::uint32_t> others) const;

    mesh::SurfaceMesh mesh_;
    physics::MassSpringModel model_;
    mesh::VertexFaces facesAround_;
    // edgeKey -> spring, looked up many times a cut; kept in order of the edges' lower vertices, so that
    // a cut's lookups stay on a few pages of it.
    FlatKeyMap springOfEdge_{FlatKeyMap::Spread::ByHighHalf};
    TopologyChanges changes_;
    bool closedBeforeCuts_ = false;
    std::vector<std::uint8_t> wall_;         // per face
    std::vector<std::uint32_t> floorUnder_;  // per vertex: the floor vertex of its opening, or kNoFloor
    static constexpr std::uint32_t kNoFloor = ~std::uint32_t{0};
    std::vector<std::uint32_t> shortened_;            // scratch for openCut: each spring shortened once
    std::vector<std::uint32_t> fanFaces_, fanStart_;  // scratch for separateFans
    std::vector<std::uint32_t> edgeFaces_;            // scratch for splitEdge
    std::vector<std::uint32_t> left_, leftVertices_;  // scratch for openCut
    // Material of new springs and anchors: the means of the model's own, per unit length and mass.
    physics::MaterialField field_;
    bool keepRetiredPositions_ = false;
    std::vector<std::vector<Vec3>> retiredPositions_;
    double stiffnessTimesLength_ = 0, dampingTimesLength_ = 0, anchorStiffnessPerKg_ = 0, anchorDampingPerKg_ = 0;
};

}  // namespace hapticut::cutting
