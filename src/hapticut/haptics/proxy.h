// God-object proxy (SPEC R8; Zilles & Salisbury 1995, Ruspini et al. 1997): a point that follows the
// device but never enters the surface, constrained by up to three contact planes.
#pragma once

#include <array>
#include <cstdint>
#include <optional>

#include "hapticut/collision/bvh.h"
#include "hapticut/mesh/vertex_faces.h"

namespace hapticut::haptics {

struct ProxyParams {
    double offset_m = 1e-5;  // the proxy keeps this far outside the surface, so it never sits exactly on it
    int maxIterations = 16;  // collide-and-slide passes per update
    /// A closed surface lets the proxy check itself with the ray-parity inside test; an open one
    /// (a patch, a cut-open organ) falls back to the nearest face's normal.
    bool closedSurface = false;
    /// Friction between the proxy and the surface (0: frictionless). The coupling force's tangential
    /// part may reach staticFriction times its normal part before the proxy slips; sliding, it stays
    /// at dynamicFriction times the normal part (the friction cone on the god object).
    double staticFriction = 0;
    double dynamicFriction = 0;
};

struct Contact {
    bool active = false;
    std::uint32_t face = 0;
    Vec3 bary = Vec3::Zero();  // where on the face, so the proxy can ride along as the face deforms
    double side = 1;           // +1 on the face's front (outward) side, -1 behind it
};

class GodObjectProxy {
public:
    explicit GodObjectProxy(ProxyParams params = {}) : params_(params) {}

    void reset(const Vec3& position_m);
    /// Moves the proxy toward the device point without crossing the surface. Returns how many contact
    /// planes constrain it afterwards (0 to 3).
    int update(const Vec3& device_m, const collision::SurfaceView& surface, const collision::Bvh& bvh);

    /// Keeps the proxy on the surface it touches after the surface moved (e.g. after a physics step),
    /// without moving it toward the device: so the proxy and the surface published together agree.
    void followSurface(const collision::SurfaceView& surface, const collision::Bvh& bvh);

    /// R12: with the faces around each vertex, a touching proxy looks for its contact among the faces
    /// around the touched face first and queries the whole tree only when none is within reach.
    /// The topology must outlive the proxy and match the surface (cutting updates it).
    void setTopology(const mesh::VertexFaces* topology) { topology_ = topology; }
    long fastPathContacts() const { return fastPathContacts_; }

    /// After a cut the touched face's index may name another triangle: find the contact again from the
    /// proxy's position with the whole tree. Only the ray-parity check of a closed surface is lost once
    /// a cut has opened it.
    void surfaceRemeshed(const collision::SurfaceView& surface, const collision::Bvh& bvh, bool closed_surface);
    long treeContactQueries() const { return treeContactQueries_; }
    /// How often ray parity decided the proxy's side of a closed surface: the faces round the nearest
    /// point disagreed (collision/surface_side.h), a fold lay over the proxy, or it was deep inside.
    long paritySideChecks() const { return paritySideChecks_; }
    /// How often the proxy was found inside the tissue and pushed out to the nearest surface point (a
    /// surface that swept over a free proxy, a slide that ended inside), and the deepest it was then (m).
    /// The penetration measured after each update cannot see these; the force can jump where one happens.
    long pushOuts() const { return pushOuts_; }
    double deepestPushOut_m() const { return deepestPushOut_m_; }

    const Vec3& position() const { return position_; }
    const Contact& contact() const { return contact_; }
    const ProxyParams& params() const { return params_; }

private:
    struct Plane {
        Vec3 normal = Vec3::Zero();  // unit, pointing to the side the proxy is on
        double offset = 0;           // the plane is normal·x = offset
    };
    void carryWithSurface(const collision::SurfaceView& surface);
    /// `near_face`, when known, is a face near the proxy; it bounds the search for the nearest.
    void pushOutIfInside(const collision::SurfaceView& surface, const collision::Bvh& bvh,
                         std::optional<std::uint32_t> near_face = std::nullopt);
    /// Whether the proxy is inside, given the surface's nearest point to it.
    bool insideNear(const collision::SurfaceView& surface, const collision::Bvh& bvh,
                    const collision::SurfacePoint& near);
    /// Calls visit(f) once for each face round the corners of `face` (itself included), until it
    /// returns true; the faces round a corner in turn, skipping those met round an earlier corner.
    template <class Visit>
    void facesRound(const collision::SurfaceView& surface, std::uint32_t face, Visit&& visit) const {
        const mesh::Face& corners = surface.faces[face];
        for (std::size_t corner = 0; corner < 3; ++corner)
            for (std::uint32_t f : topology_->of(corners[corner])) {
                const mesh::Face& other = surface.faces[f];
                auto holds = [&](std::size_t c) {
                    return other[0] == corners[c] || other[1] == corners[c] || other[2] == corners[c];
                };
                if ((corner > 0 && holds(0)) || (corner > 1 && holds(1))) continue;
                if (visit(f)) return;
            }
    }
    /// The nearest crossing of the way to `to` within twice the offset among `face` and, with the
    /// topology, the faces round it.
    std::optional<collision::SegmentHit> crossingRound(const collision::SurfaceView& surface, std::uint32_t face,
                                                       const Vec3& to) const;
    /// A face round `slid_on` that the way to the device crosses within twice the offset: the proxy
    /// rests on the surface.
    std::optional<std::uint32_t> restingFace(const collision::SurfaceView& surface, const Vec3& device_m,
                                             std::optional<std::uint32_t> slid_on) const;
    /// The first face the way to `goal` crosses, from the faces round the contact when one of them is
    /// crossed within twice the offset, else from the tree.
    std::optional<collision::SegmentHit> firstHitRoundContact(const collision::SurfaceView& surface,
                                                              const collision::Bvh& bvh, const Vec3& goal) const;
    Vec3 constrainedGoal(const Vec3& device_m) const;
    Vec3 applyFriction(const Vec3& goal, const Vec3& device_m, const Vec3& from) const;
    /// The contact from the faces round `touched_face` (the contact's face if not given) when one is
    /// within reach (R12), from the whole tree otherwise.
    void findContact(const collision::SurfaceView& surface, const collision::Bvh& bvh,
                     std::optional<std::uint32_t> touched_face = std::nullopt);

    ProxyParams params_;
    Vec3 position_ = Vec3::Zero();
    Vec3 contactStart_ = Vec3::Zero();
    bool startedInContact_ = false;
    Contact contact_;
    std::array<Plane, 3> planes_{};
    int planeCount_ = 0;
    const mesh::VertexFaces* topology_ = nullptr;
    long fastPathContacts_ = 0, treeContactQueries_ = 0, paritySideChecks_ = 0, pushOuts_ = 0;
    double deepestPushOut_m_ = 0;
};

/// Unit normal of a face on the current (deformed) positions.
Vec3 faceNormal(const collision::SurfaceView& surface, std::uint32_t face);

/// The point at barycentric coordinates `bary` on a face.
Vec3 pointOnFace(const collision::SurfaceView& surface, std::uint32_t face, const Vec3& bary);

}  // namespace hapticut::haptics
