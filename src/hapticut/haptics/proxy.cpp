// God-object proxy: carry with the touched surface, then collide-and-slide toward the device.
#include "hapticut/haptics/proxy.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Dense>

#include "hapticut/collision/point_inside.h"
#include "hapticut/collision/surface_side.h"
#include "hapticut/geometry/triangle.h"
#include "hapticut/geometry/triangle_queries.h"

namespace hapticut::haptics {

Vec3 faceNormal(const collision::SurfaceView& s, std::uint32_t face) {
    const mesh::Face& f = s.faces[face];
    return geometry::unitNormal(s.positions[f[0]], s.positions[f[1]], s.positions[f[2]]);
}

Vec3 pointOnFace(const collision::SurfaceView& s, std::uint32_t face, const Vec3& bary) {
    const mesh::Face& f = s.faces[face];
    return bary.x() * s.positions[f[0]] + bary.y() * s.positions[f[1]] + bary.z() * s.positions[f[2]];
}

void GodObjectProxy::reset(const Vec3& position_m) {
    position_ = position_m;
    contact_ = {};
    planeCount_ = 0;
}

void GodObjectProxy::carryWithSurface(const collision::SurfaceView& s) {
    if (!contact_.active || contact_.face >= s.faces.size()) return;
    const Vec3 n = contact_.side * faceNormal(s, contact_.face);
    position_ = pointOnFace(s, contact_.face, contact_.bary) + params_.offset_m * n;
}

void GodObjectProxy::pushOutIfInside(const collision::SurfaceView& s, const collision::Bvh& bvh,
                                     std::optional<std::uint32_t> near_face) {
    // The guarantee that the proxy is never inside, whatever happened: a surface that swept over a
    // free proxy, or a contact face carrying the proxy behind a neighbour that folded over it in a deep
    // crease. A sweep leaves it within a step's tissue motion of the surface, where the nearest surface
    // point decides (insideNear), at a cost independent of the organ's size.
    double reach = 2e-3;  // m: more than tissue moves in one haptic step
    // A face known to be near bounds the search to what is nearer still: a few boxes, not all within 2 mm.
    if (near_face && *near_face < s.faces.size()) {
        const mesh::Face& f = s.faces[*near_face];
        const auto c =
            geometry::closestPointOnTriangle(position_, s.positions[f[0]], s.positions[f[1]], s.positions[f[2]]);
        reach = std::min(reach, (c.point - position_).norm() * (1 + 1e-9) + 1e-15);
    }
    auto near = bvh.closestPoint(s, position_, reach);
    if (!near) {
        // Nothing within reach: outside, unless a touching proxy went deep into the tissue in one
        // update, which only one already behind a fold can (it slides on freely there): parity decides.
        if (!params_.closedSurface || !startedInContact_) return;
        ++paritySideChecks_;
        if (!collision::insideClosedSurface(bvh, s, position_)) return;
        near = bvh.closestPoint(s, position_);
        if (!near) return;
    } else if (!insideNear(s, bvh, *near)) {
        return;
    }
    const Vec3 out = near->point - position_;
    const double len = out.norm();
    position_ = near->point + params_.offset_m * (len > 0 ? Vec3(out / len) : faceNormal(s, near->face));
    ++pushOuts_;
    deepestPushOut_m_ = std::max(deepestPushOut_m_, len);
}

bool GodObjectProxy::insideNear(const collision::SurfaceView& s, const collision::Bvh& bvh,
                                const collision::SurfacePoint& near) {
    const Vec3 away = position_ - near.point;
    // On an open surface only the nearest face's normal can say, where the nearest point is inside a face.
    if (!params_.closedSurface) return near.bary.minCoeff() > 1e-9 && faceNormal(s, near.face).dot(away) < 0;
    // On a closed surface the faces round the nearest point decide when they agree (surface_side.h),
    // and ray parity where they do not (robust at creases and vertex pits).
    collision::Side side =
        topology_ ? collision::sideOfClosedSurface(s, *topology_, near, position_) : collision::Side::Unsure;
    // A hard press can fold the tissue over the proxy until the surface crosses itself. The faces round
    // the nearest point then say outside while parity counts the fold as a layer: a surface crossed on
    // a short way out says so. A fold farther away than that does not hold this contact.
    if (side == collision::Side::Outside) {
        constexpr double kFoldReach_m = 5e-3;
        const Vec3 wayOut = away.norm() > 0 ? Vec3(away.normalized()) : faceNormal(s, near.face);
        bool crossed = bvh.countCrossings(s, position_, position_ + kFoldReach_m * wayOut) != 0;
        // Two sheets pressed through each other, the lips of a wound, put a point in one lip's tissue in
        // front of the other lip: the faces round its nearest point (that lip's) say outside, and a proxy
        // that rested on that lip and left it this update is free in the tissue (a scalpel lifted out of
        // a cut on a jittered heart went 1.8 mm in so). A second sheet crossed just behind the nearest
        // point says so; a proxy that rests on the surface, within its offset, is not looked at.
        if (!crossed && startedInContact_ && away.norm() > 2 * params_.offset_m) {
            constexpr double kSheetReach_m = 1e-3;
            crossed = bvh.countCrossings(s, position_, near.point - kSheetReach_m * wayOut) > 1;
        }
        if (!crossed) return false;
        side = collision::Side::Unsure;
    }
    if (side == collision::Side::Inside) return true;
    ++paritySideChecks_;
    return collision::insideClosedSurface(bvh, s, position_);
}

Vec3 GodObjectProxy::constrainedGoal(const Vec3& device_m) const {
    // The point nearest the device that satisfies every plane: try each subset of planes as equalities
    // (at most 7 subsets for 3 planes) and keep the nearest feasible projection (active-set search).
    auto feasible = [&](const Vec3& x) {
        for (int i = 0; i < planeCount_; ++i)
            if (planes_[i].normal.dot(x) < planes_[i].offset - 1e-12) return false;
        return true;
    };
    if (feasible(device_m)) return device_m;
    Vec3 best = position_;
    double bestD2 = std::numeric_limits<double>::infinity();
    for (int mask = 1; mask < (1 << planeCount_); ++mask) {
        int idx[3], m = 0;
        for (int i = 0; i < planeCount_; ++i)
            if (mask & (1 << i)) idx[m++] = i;
        // x = d - sum(lambda_j n_j) with n_i·x = c_i: solve the Gram system G lambda = n·d - c.
        Eigen::Matrix3d g = Eigen::Matrix3d::Identity();  // unused rows stay identity, so one 3x3 solve fits every m
        Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
        for (int a = 0; a < m; ++a) {
            rhs[a] = planes_[idx[a]].normal.dot(device_m) - planes_[idx[a]].offset;
            for (int b = 0; b < m; ++b) g(a, b) = planes_[idx[a]].normal.dot(planes_[idx[b]].normal);
        }
        Eigen::FullPivLU<Eigen::Matrix3d> lu(g);
        if (lu.rank() < 3) continue;  // parallel planes: this subset has no single projection
        const Eigen::Vector3d lambda = lu.solve(rhs);
        Vec3 x = device_m;
        for (int a = 0; a < m; ++a) x -= lambda[a] * planes_[idx[a]].normal;
        const double d2 = (x - device_m).squaredNorm();
        if (d2 < bestD2 && feasible(x)) bestD2 = d2, best = x;
    }
    return best;
}

Vec3 GodObjectProxy::applyFriction(const Vec3& goal, const Vec3& device_m, const Vec3& from) const {
    // On one plane the coupling k (proxy - device) splits into a normal part k |goal - device| and a
    // tangential part k |proxy - goal|. Within the static cone the proxy stays where it is; beyond it,
    // it slides toward the goal but stops where the tangential part equals the dynamic limit.
    // Only a proxy that began the step resting on the surface can stick; one arriving from free space
    // just lands.
    if (planeCount_ != 1 || !startedInContact_ || (params_.staticFriction <= 0 && params_.dynamicFriction <= 0))
        return goal;
    const double normal = (goal - device_m).norm();
    const Vec3& n = planes_[0].normal;
    Vec3 tangential = from - goal;
    tangential -= n * n.dot(tangential);  // only the part along the plane
    const double slip = tangential.norm();
    if (slip <= params_.staticFriction * normal) return from;
    const double held = params_.dynamicFriction * normal;
    return slip > held ? Vec3(goal + tangential * (held / slip)) : goal;
}

std::optional<collision::SegmentHit> GodObjectProxy::crossingRound(const collision::SurfaceView& s, std::uint32_t face,
                                                                   const Vec3& to) const {
    const double reach = 2 * params_.offset_m / (to - position_).norm();  // as a fraction of the way
    std::optional<collision::SegmentHit> first;
    auto consider = [&](std::uint32_t f) {
        const mesh::Face& corners = s.faces[f];
        const auto hit = geometry::intersectSegmentTriangle(position_, to, s.positions[corners[0]],
                                                            s.positions[corners[1]], s.positions[corners[2]]);
        if (hit && hit->t <= reach && (!first || hit->t < first->t))
            first = collision::SegmentHit{f, hit->t, position_ + hit->t * (to - position_), hit->bary};
        return false;
    };
    if (topology_)
        facesRound(s, face, consider);
    else
        consider(face);
    return first;
}

std::optional<std::uint32_t> GodObjectProxy::restingFace(const collision::SurfaceView& s, const Vec3& device_m,
                                                         std::optional<std::uint32_t> slid_on) const {
    if (!slid_on || *slid_on >= s.faces.size()) return std::nullopt;
    const auto crossing = crossingRound(s, *slid_on, device_m);
    return crossing ? std::optional(crossing->face) : std::nullopt;
}

std::optional<collision::SegmentHit> GodObjectProxy::firstHitRoundContact(const collision::SurfaceView& s,
                                                                          const collision::Bvh& bvh,
                                                                          const Vec3& goal) const {
    // A proxy resting on the surface, pressed further in, meets the face it rests on or one round it
    // within about its offset: a face there crossed that soon is the first, and the tree need not be
    // walked (a face from elsewhere would have to lie within that distance of the proxy).
    if (topology_ && contact_.active && contact_.face < s.faces.size())
        if (auto crossing = crossingRound(s, contact_.face, goal)) return crossing;
    return bvh.firstHit(s, position_, goal);
}

void GodObjectProxy::findContact(const collision::SurfaceView& s, const collision::Bvh& bvh,
                                 std::optional<std::uint32_t> touched_face) {
    const double reach = 3 * params_.offset_m;
    std::optional<collision::SurfacePoint> near;
    if (!touched_face && contact_.active) touched_face = contact_.face;
    if (touched_face && topology_ && *touched_face < s.faces.size()) {
        // R12: the faces around the touched face's corners first; they hold every face the proxy can
        // slide onto across an edge or a vertex in one step.
        double best = reach * reach;
        facesRound(s, *touched_face, [&](std::uint32_t f) {
            const mesh::Face& face = s.faces[f];
            const auto c = geometry::closestPointOnTriangle(position_, s.positions[face[0]], s.positions[face[1]],
                                                            s.positions[face[2]]);
            const double d2 = (c.point - position_).squaredNorm();
            if (d2 < best || (!near && d2 <= best)) best = d2, near = collision::SurfacePoint{f, c.point, c.bary, 0};
            return false;
        });
        if (near) ++fastPathContacts_;
    }
    if (!near) {
        ++treeContactQueries_;
        near = bvh.closestPoint(s, position_, reach);
    }
    if (!near) {
        contact_.active = false;
        return;
    }
    // The side is the one the proxy came from, kept while the contact lasts: a proxy never crosses the
    // surface, and under a deep press folded faces can point the other way, which must not flip it.
    const bool continuing = contact_.active;
    contact_.active = true;
    contact_.face = near->face;
    contact_.bary = near->bary;
    if (!continuing) contact_.side = faceNormal(s, near->face).dot(position_ - near->point) >= 0 ? 1.0 : -1.0;
}

void GodObjectProxy::surfaceRemeshed(const collision::SurfaceView& s, const collision::Bvh& bvh, bool closed_surface) {
    params_.closedSurface = closed_surface;
    const Contact before = contact_;
    contact_.active = false;
    planeCount_ = 0;
    findContact(s, bvh);
    if (before.active && contact_.active) contact_.side = before.side;  // the proxy has not moved: still the same side
}

void GodObjectProxy::followSurface(const collision::SurfaceView& s, const collision::Bvh& bvh) {
    carryWithSurface(s);
    pushOutIfInside(s, bvh, contact_.active ? std::optional(contact_.face) : std::nullopt);
    findContact(s, bvh);
}

int GodObjectProxy::update(const Vec3& device_m, const collision::SurfaceView& s, const collision::Bvh& bvh) {
    carryWithSurface(s);
    // A free proxy may have been swept over by the surface; a touching one is checked once, at the
    // end of the update, which also catches a carry that put it behind a folded neighbour.
    startedInContact_ = contact_.active;
    if (!contact_.active) pushOutIfInside(s, bvh);
    contactStart_ = position_;  // where a sticking proxy stays
    planeCount_ = 0;
    Vec3 goal = device_m;
    std::optional<std::uint32_t> lastHitFace;
    if (contact_.active) lastHitFace = contact_.face;
    // A proxy that lifted off heads for the device from where it is: the way there was just searched.
    std::optional<collision::SegmentHit> towardDevice;
    for (int iteration = 0; iteration < params_.maxIterations; ++iteration) {
        if ((goal - position_).squaredNorm() < 1e-24) break;
        const auto hit = towardDevice                          ? towardDevice
                         : iteration == 0 && startedInContact_ ? firstHitRoundContact(s, bvh, goal)
                                                               : bvh.firstHit(s, position_, goal);
        towardDevice.reset();
        if (!hit) {
            position_ = goal;
            if (planeCount_ == 0 || (goal - device_m).squaredNorm() < 1e-24) break;
            // On a convex surface the planes' extensions leave the surface: if the surface toward the
            // device is now farther than the offset, the proxy has lifted off, so drop the planes and
            // head for the device again. The next hit brings it back onto the surface now rather than
            // a step later. Resting on the planes (flat or concave), it stays.
            // Usually the proxy rests on the face it slid along or one round it: a face within twice the
            // offset toward the device means the first face is too, and the tree need not be walked.
            if (const auto resting = restingFace(s, device_m, lastHitFace)) {
                lastHitFace = *resting;
                break;
            }
            const auto below = bvh.firstHit(s, position_, device_m);
            if (!below) break;
            if (below->t * (device_m - position_).norm() <= 2 * params_.offset_m) {
                lastHitFace = below->face;  // the face the proxy rests on now, whose neighbours hold its contact
                break;
            }
            planeCount_ = 0;
            goal = device_m;
            towardDevice = below;
            continue;
        }
        lastHitFace = hit->face;
        Vec3 n = faceNormal(s, hit->face);
        if (n.dot(position_ - hit->point) < 0) n = -n;  // the side the proxy came from (back faces count, R10)
        // Back off along the way in as well as lifting along the normal: a hit on an edge lifted only
        // along one face's normal would leave the proxy in the plane of the other face, and the next
        // segment could then start on that face and slip through it.
        const Vec3 travel = hit->point - position_;
        const double travelled = travel.norm();
        const double backoff = std::min(params_.offset_m, travelled);
        position_ =
            hit->point + params_.offset_m * n - (travelled > 0 ? Vec3(backoff / travelled * travel) : Vec3::Zero());
        if (planeCount_ == 3) break;  // held in a corner by three planes
        planes_[planeCount_++] = {n, n.dot(hit->point) + params_.offset_m};
        goal = applyFriction(constrainedGoal(device_m), device_m, contactStart_);
    }
    // The face last hit, or touched when the update began, bounds the search for the nearest surface
    // point: usually it lies within the offset, and the search then looks no farther. It is the
    // touched face whose neighbours are searched for the contact, too: on a fine mesh a slide can
    // leave the neighbours of the face touched when the update began.
    pushOutIfInside(s, bvh, lastHitFace);
    findContact(s, bvh, lastHitFace);
    return planeCount_;
}

}  // namespace hapticut::haptics
