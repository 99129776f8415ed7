// The progressive cutter.
#include "hapticut/cutting/progressive_cutter.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <utility>

#include "hapticut/common/assert.h"
#include "hapticut/cutting/invariants.h"
#include "hapticut/geometry/triangle.h"
#include "hapticut/geometry/triangle_queries.h"

namespace hapticut::cutting {

namespace {
Vec3 restPoint(const mesh::SurfaceMesh& m, std::uint32_t face, const Vec3& bary) {
    const mesh::Face& f = m.faces[face];
    return bary.x() * m.positions[f[0]] + bary.y() * m.positions[f[1]] + bary.z() * m.positions[f[2]];
}
}  // namespace

bool ProgressiveCutter::onBoundary(std::uint32_t v) const {
    for (std::uint32_t f : model_.facesAround(v))
        for (std::uint32_t x : model_.mesh().faces[f])
            if (x != v && model_.onRim(v, x)) return true;
    return false;
}

bool ProgressiveCutter::recentLip(std::uint32_t v) const {
    const std::size_t recent = std::min(lipVertices_.size(), kRecentLips);
    return std::find(lipVertices_.end() - static_cast<std::ptrdiff_t>(recent), lipVertices_.end(), v) !=
           lipVertices_.end();
}

void ProgressiveCutter::addPoint(std::uint32_t vertex) {
    if (!points_.empty())
        stats_.length_m += (model_.mesh().positions[vertex] - model_.mesh().positions[points_.back()]).norm();
    points_.push_back(vertex);
    lipVertices_.push_back(vertex);
    ++stats_.cutPoints;
    // R17: from the third point on, each new point opens the one before it.
    if (points_.size() >= 3) {
        const std::size_t n = points_.size();
        const std::size_t before = model_.mesh().positions.size(), faces = model_.mesh().faces.size();
        const std::uint32_t prev = points_[n - 3], v = points_[n - 2], next = points_[n - 1];
        if (const auto copy = model_.openCut(prev, v, next, params_.shorten, params_.retract)) {
            stats_.opened = true;
            ++stats_.openings;
            lipVertices_.push_back(*copy);
            if (params_.walls) {
                const auto& x = model_.mesh().positions;
                // As deep as the blade, within limits set by the cut's two edges there (S the shorter, L
                // the longer): a wall face spans an edge and the depth, so a depth far from either edge
                // makes a sliver. Up to 3 S keeps both faces above 18 degrees; where L > 9 S no depth
                // does, and sqrt(S L) keeps the worst of them best.
                const double edgeBefore = (x[v] - x[prev]).norm(), edgeAfter = (x[next] - x[v]).norm();
                const double shorter = std::min(edgeBefore, edgeAfter), longer = std::max(edgeBefore, edgeAfter);
                const double deepest = std::max(params_.maxWallDepthPerEdge * shorter, std::sqrt(shorter * longer));
                const double depth =
                    std::clamp(bladeDepth_m_,
                               std::min(params_.wallDepthPerEdge * 0.5 * (edgeBefore + edgeAfter), deepest), deepest);
                // Next to an earlier wound's floor (crossWound) the opening's floor goes among its
                // corners: under v it would lie on that wound's wall.
                const bool throughWall = model_.isFloor(prev) || model_.isFloor(next);
                if (model_.closeOpening(v, *copy, depth, throughWall)) ++stats_.wallsClosed;
            }
        }
        stats_.facesAdded += static_cast<long>(model_.mesh().faces.size() - faces);
        // A cut that started on a boundary or a wound's lip now opens into it at its first point.
        if (n == 3) model_.separateFans(points_[0]);
        stats_.verticesAdded += static_cast<long>(model_.mesh().positions.size() - before);
    }
}

void ProgressiveCutter::joinAt(std::uint32_t vertex) {
    addPoint(vertex);
    // With three points or more the one before `vertex` has opened up to it, leaving `vertex` pinched
    // between two fans; two points open nothing, and a cut of one edge between two boundaries stays shut.
    if (points_.size() >= 3) {
        const std::size_t before = model_.mesh().positions.size();
        if (model_.separateFans(vertex) > 0) ++stats_.joins;
        stats_.verticesAdded += static_cast<long>(model_.mesh().positions.size() - before);
    }
    endCut();
}

std::optional<std::uint32_t> ProgressiveCutter::floorBeside(std::uint32_t lip) const {
    if (const auto floor = model_.floorUnder(lip)) return floor;
    // A lip vertex a cut split off an edge: the floor vertex its wall face reaches down to.
    const mesh::SurfaceMesh& m = model_.mesh();
    std::optional<std::uint32_t> floor;
    double nearest = 1e300;
    for (std::uint32_t f : model_.facesAround(lip))
        for (std::uint32_t y : m.faces[f])
            if (const double d2 = (m.positions[y] - m.positions[lip]).squaredNorm(); model_.isFloor(y) && d2 < nearest)
                floor = y, nearest = d2;
    return floor;
}

std::optional<ProgressiveCutter::WoundCrossing> ProgressiveCutter::crossingAt(std::uint32_t lip) const {
    // Only a closed wound has a floor to cross by; the organ's open rim and wounds left open are joined.
    // This cut's own lips are joined too: crossing back over them would cut the tissue it just opened.
    if (!params_.walls || std::find(lipVertices_.begin(), lipVertices_.end(), lip) != lipVertices_.end())
        return std::nullopt;
    const mesh::SurfaceMesh& m = model_.mesh();
    const auto& x = m.positions;
    auto neighbours = [&](std::uint32_t v, auto&& visit) {
        for (std::uint32_t f : model_.facesAround(v))
            for (std::uint32_t y : m.faces[f])
                if (y != v) visit(y);
    };
    // A vertex on the organ's open rim as well is joined: the wound there is open to the outside.
    for (std::uint32_t f : model_.facesAround(lip))
        for (std::uint32_t y : m.faces[f])
            if (y != lip && model_.isOpenEdge(lip, y)) return std::nullopt;
    const std::optional<std::uint32_t> floor = floorBeside(lip);
    if (!floor) return std::nullopt;
    // Across the gap: a lip vertex at the same floor that shares no face with this lip (the walls meet
    // only at the floor), the nearest; the lip's own neighbours along the wound share a face with it.
    auto sharesFace = [&](std::uint32_t y) {
        for (std::uint32_t f : model_.facesAround(lip))
            for (std::uint32_t c : m.faces[f])
                if (c == y) return true;
        return false;
    };
    auto onSurface = [&](std::uint32_t y) {
        const auto& around = model_.facesAround(y);
        return std::any_of(around.begin(), around.end(), [&](std::uint32_t f) { return !model_.isWall(f); });
    };
    std::optional<std::uint32_t> farLip;
    double nearest = 1e300;
    neighbours(*floor, [&](std::uint32_t y) {
        if (y == lip || !onSurface(y) || sharesFace(y)) return;
        if (std::find(points_.begin(), points_.end(), y) != points_.end()) return;
        if (const double d2 = (x[y] - x[lip]).squaredNorm(); d2 < nearest) farLip = y, nearest = d2;
    });
    if (!farLip) return std::nullopt;
    return WoundCrossing{*floor, *farLip};
}

void ProgressiveCutter::crossWound(std::uint32_t lip, const WoundCrossing& crossing) {
    // With the floor as the cut's next point the lip opens down to it (addPoint opens a point once the
    // next is known), so the new wound opens into the old one. The cut then starts again from the floor
    // up the far wall, whose lip opens once the cut has left it. The floor is never opened: the blade
    // passes from one wall to the other over it, and the tissue under an earlier wound stays whole.
    addPoint(lip);
    // The cut's length is along the surface: across the gap, not down one wall and up the other.
    const auto& x = model_.mesh().positions;
    const double length = stats_.length_m + (x[crossing.farLip] - x[lip]).norm();
    addPoint(crossing.floor);
    ++stats_.woundsCrossed;
    points_.assign(1, crossing.floor);
    addPoint(crossing.farLip);
    stats_.length_m = length;
    crossedFloor_ = crossing.floor;
}

bool ProgressiveCutter::justCrossed(std::uint32_t lip) const {
    if (!crossedFloor_) return false;
    const auto floor = floorBeside(lip);
    return floor && alongFloorWithin(*crossedFloor_, *floor, kSameCrossingFloorHops);
}

bool ProgressiveCutter::alongFloorWithin(std::uint32_t from, std::uint32_t to, int hops) const {
    // Breadth first over floor vertices joined by an edge, in fixed room: a floor is a curve, so each
    // ring holds a few vertices (two where the curve is simple), and a search that outgrows the room
    // has gone far enough.
    constexpr std::size_t kRoom = 64;
    std::array<std::uint32_t, kRoom> seen{};
    std::size_t count = 0, ringStart = 0;
    seen[count++] = from;
    auto known = [&](std::uint32_t v) {
        return std::find(seen.begin(), seen.begin() + static_cast<std::ptrdiff_t>(count), v) !=
               seen.begin() + static_cast<std::ptrdiff_t>(count);
    };
    const mesh::SurfaceMesh& m = model_.mesh();
    for (int ring = 0; ring <= hops; ++ring) {
        const std::size_t ringEnd = count;
        for (std::size_t i = ringStart; i < ringEnd; ++i) {
            if (seen[i] == to) return true;
            if (ring == hops) continue;
            for (std::uint32_t f : model_.facesAround(seen[i]))
                for (std::uint32_t y : m.faces[f])
                    if (model_.isFloor(y) && !known(y)) {
                        if (count == kRoom) return false;
                        seen[count++] = y;
                    }
        }
        ringStart = ringEnd;
    }
    return false;
}

bool ProgressiveCutter::fanContains(std::uint32_t vertex, const Vec3& q) const {
    const mesh::SurfaceMesh& m = model_.mesh();
    for (std::uint32_t f : model_.facesAround(vertex)) {
        const mesh::Face& face = m.faces[f];
        const auto c =
            geometry::closestPointOnTriangle(q, m.positions[face[0]], m.positions[face[1]], m.positions[face[2]]);
        const double scale = (m.positions[face[1]] - m.positions[face[0]]).norm();
        if ((c.point - q).norm() < 1e-6 * scale) return true;  // on the fan, its edges included
    }
    return false;
}

bool ProgressiveCutter::crossToward(const Vec3& q) {
    const mesh::SurfaceMesh& m = model_.mesh();
    const std::uint32_t last = points_.back();
    const Vec3 from = m.positions[last];
    // Among the edges opposite the last point in its fan, those the way to q crosses, seen along the
    // fan's normal: in the plane of the fan the way leaves it through one edge. The way and the edges
    // do not meet in space on a rough mesh, whose fans bend and fold, and their closest approach in
    // space can lie behind the last point or off every edge. The first crossing wins, unless it would
    // lead back to a point the cut already has.
    Vec3 normal = Vec3::Zero();
    for (std::uint32_t f : model_.facesAround(last))
        if (!model_.isWall(f)) {
            const mesh::Face& face = m.faces[f];
            normal += (m.positions[face[1]] - m.positions[face[0]]).cross(m.positions[face[2]] - m.positions[face[0]]);
        }
    if (!(normal.norm() > 0)) return false;
    normal.normalize();
    auto flat = [&](const Vec3& p) {
        const Vec3 d = p - from;
        return Vec3(d - d.dot(normal) * normal);
    };
    const Vec3 way = flat(q);
    std::vector<Crossing>& crossings = crossings_;
    crossings.clear();
    for (std::uint32_t f : model_.facesAround(last)) {
        // Over the organ's surface only: a wound's walls are crossed by crossWound, from lip to floor to
        // lip, and a walk down a wall's faces would split them edge by edge.
        if (model_.isWall(f)) continue;
        const mesh::Face& face = m.faces[f];
        int k = 0;
        while (face[k] != last) ++k;
        const std::uint32_t a = face[(k + 1) % 3], b = face[(k + 2) % 3];
        // t way = A + u E in the plane.
        const Vec3 A = flat(m.positions[a]), E = flat(m.positions[b]) - A;
        const double den = way.cross(E).dot(normal);
        if (!(std::abs(den) > 1e-12 * way.norm() * E.norm())) continue;  // parallel
        const double t = A.cross(E).dot(normal) / den, u = A.cross(way).dot(normal) / den;
        if (t <= 0 || u < 0 || u > 1) continue;
        // An edge through the last point itself: the other wall of a wound, folded onto this one in the
        // rest shape (CutModel::closeOpening). Crossing there would join two points at one place.
        const Vec3 edge = m.positions[b] - m.positions[a];
        if ((m.positions[a] + u * edge - from).norm() < 1e-3 * edge.norm()) continue;
        crossings.push_back({t, a, b, u});
    }
    std::sort(crossings.begin(), crossings.end(),
              [](const Crossing& x, const Crossing& y) { return x.along < y.along; });
    // A recent lip of this cut, too, lies behind the blade: on a mesh of slivers an edge the way crosses
    // can end at the opened copy of the last point, and joining it would end the cut where it runs.
    auto inCut = [&](std::uint32_t v) {
        return std::find(points_.begin(), points_.end(), v) != points_.end() || recentLip(v);
    };
    bool backIntoItsOwnWound = false;
    bool acrossItsNewLips = false;  // the way crossed a lip this cut has just opened
    for (const Crossing& c : crossings) {
        // A boundary edge is an open end of the organ or an earlier wound: the cut runs into it there
        // and joins it (on the edge, or at an end of it rather than make a sliver).
        const bool boundaryEdge = model_.onRim(c.a, c.b);
        // A lip this cut just opened is no way on: the way to the blade may cross it first where the
        // cut bends, and another edge of the fan leads on. An older lip of its own on the way means
        // the cut has turned back round to the wound it opened before.
        if (boundaryEdge && inCut(c.a) && inCut(c.b)) {
            const bool older = !recentLip(c.a) && !recentLip(c.b);
            backIntoItsOwnWound = backIntoItsOwnWound || older;
            acrossItsNewLips = acrossItsNewLips || !older;
            continue;
        }
        // Nor is an edge between two of its points or lips that is not a lip itself: where a cut along
        // a rough mesh's edges bends back, such an edge spans the bend, and a point on it would lie
        // wedged among the cut's own lips with no way on from it.
        if (inCut(c.a) && inCut(c.b)) {
            acrossItsNewLips = true;
            continue;
        }
        std::uint32_t next = pointOnEdge(c.a, c.b, c.u);
        // Snapped back onto the cut: on a mesh of slivers, where every split near the end makes a worse
        // one, the way on can pass within a snap of a vertex behind the blade. Split the edge farther
        // from it instead, as close to the way as the faces there allow.
        if (inCut(next) && !boundaryEdge && !inCut(next == c.a ? c.b : c.a))
            if (const auto away = splitAwayFrom(c.a, c.b, c.u, next)) next = *away;
        if (inCut(next)) {
            if (boundaryEdge) continue;  // along a lip of its own: nothing to join
            // The blade went on past the cut's first point, which its second point lies behind: nothing
            // has opened yet (addPoint opens from the third), so the cut starts again from the first.
            if (points_.size() == 2 && next == points_[0]) {
                stats_.length_m -= (m.positions[points_[1]] - m.positions[points_[0]]).norm();
                points_.pop_back(), lipVertices_.pop_back();
                --stats_.cutPoints;
                return true;
            }
            continue;  // would step back along the cut
        }
        // A split that snapped to an end of its edge behind the blade would walk the cut backwards, and
        // a cut that doubles back on a rough mesh hems itself in with its own lips. Split the edge clear
        // of that end instead where the faces allow it: on a rough mesh the way can cross the only
        // edge that leads on a hair's breadth from its end behind.
        auto behind = [&](std::uint32_t v) { return (m.positions[v] - from).dot(q - from) <= 0; };
        if ((next == c.a || next == c.b) && behind(next)) {
            const std::uint32_t other = next == c.a ? c.b : c.a;
            const bool splittable = !boundaryEdge && !inCut(other) && !behind(other);
            const auto away = splittable ? splitAwayFrom(c.a, c.b, c.u, next) : std::nullopt;
            if (!away) continue;
            next = *away;
        }
        if (!advanceTo(next)) continue;
        return true;
    }
    // No crossing leads on, and not because the blade came back into this cut's own wound: on a rough
    // mesh the last point can sit on, or past, the far edge of a sliver in its fan, a fan can fold
    // over the way, and every crossing can snap back behind the blade. The cut goes on along the edge
    // to the neighbour most nearly ahead instead. Kept waiting, it stayed where it was while the blade
    // went on (a 4 cm stroke across a jittered 50,000-triangle heart: 17 mm cut).
    if (!backIntoItsOwnWound)
        if (const auto next = neighbourToward(q); next && advanceTo(*next)) return true;
    // Still no way on: the fan folds, seen along its normal, and leaves no opening toward the blade, or
    // only across the lips the cut has just opened, or its one edge there cannot be split clear of the
    // cut. A jittered segmentation's vertex can stick out past all its neighbours, its faces turned
    // over, so that every edge from it leads back. The cut steps along the edge to the neighbour nearest
    // the blade, whichever way it leads, and goes on from there. Kept waiting, it never moved again
    // while the blade pressed on at the force clamp (a stroke across a jittered 960,796-triangle liver:
    // 3.9 mm cut of 50). Only a way across its new lips to a blade close behind it is waited for: the cut
    // ran ahead of the blade along the edges. Behind is taken against the cut's way over its last few
    // points (one step may have been such a detour), and close is within the last point's two rings.
    const std::uint32_t fewBack = points_[points_.size() - std::min<std::size_t>(points_.size(), kWayPoints)];
    const bool bladeAhead = fewBack == last || (q - from).dot(from - m.positions[fewBack]) > 0;
    auto withinTwoRings = [&] {
        for (std::uint32_t f : model_.facesAround(last))
            for (std::uint32_t y : m.faces[f])
                if (y != last && fanContains(y, q)) return true;
        return false;
    };
    if (!backIntoItsOwnWound && (!acrossItsNewLips || bladeAhead || !withinTwoRings()))
        if (const auto next = neighbourNearest(q); next && advanceTo(*next)) return true;
    // A short cut that turned back toward its start: the crack of a blade pressed in at a slant to the
    // surface can first run a few millimetres the wrong way (up the slope) until the stroke pulls it
    // round, and the way back then crosses only the lips it has just opened. It goes on from its first
    // point, nearer the blade, and opens into the short wound there (a cut that starts on a lip). Kept
    // waiting, it cut 2.5 and 3.5 mm of 30 on two jittered 9,714 hearts.
    if (!backIntoItsOwnWound && points_.size() >= 3 && points_.size() <= kTurnedBackCutPoints &&
        !model_.isFloor(points_[0]) && (q - m.positions[points_[0]]).norm() < (q - from).norm()) {
        const std::uint32_t first = points_[0];
        points_.assign(1, first);
        return true;
    }
    // Nothing else leads on: the blade has come back round into this cut's own wound, across it or
    // beside it, and the cut ends there (without joining, which would cut a loop of tissue free). The
    // blade, pressing on, starts a new cut beyond. Kept waiting, the cut never followed again while the
    // crack ran on with the blade (a stroke across the 1,000,000 heart whose crack first ran downhill
    // and turned back beside itself: 3-5 mm cut of 53, in about one real-time run in three).
    if (backIntoItsOwnWound) endCut();
    return false;
}

template <class Visit>
void ProgressiveCutter::forEachNeighbourOnTheSurface(Visit&& visit) const {
    const mesh::SurfaceMesh& m = model_.mesh();
    const std::uint32_t last = points_.back();
    for (std::uint32_t f : model_.facesAround(last)) {
        if (model_.isWall(f)) continue;
        for (std::uint32_t y : m.faces[f]) {
            if (y == last || model_.onRim(last, y)) continue;
            if (std::find(lipVertices_.begin(), lipVertices_.end(), y) != lipVertices_.end()) continue;
            visit(y);
        }
    }
}

std::optional<std::uint32_t> ProgressiveCutter::neighbourToward(const Vec3& q) const {
    const mesh::SurfaceMesh& m = model_.mesh();
    const Vec3 from = m.positions[points_.back()];
    const Vec3 way = (q - from).normalized();
    std::optional<std::uint32_t> best;
    double bestCosine = kMostAskewStep;
    forEachNeighbourOnTheSurface([&](std::uint32_t y) {
        const Vec3 step = m.positions[y] - from;
        const double length = step.norm();
        if (!(length > 0)) return;
        if (const double cosine = step.dot(way) / length; cosine > bestCosine) bestCosine = cosine, best = y;
    });
    return best;
}

std::optional<std::uint32_t> ProgressiveCutter::neighbourNearest(const Vec3& q) const {
    const mesh::SurfaceMesh& m = model_.mesh();
    std::optional<std::uint32_t> best;
    double bestD2 = 1e300;
    forEachNeighbourOnTheSurface([&](std::uint32_t y) {
        if (const double d2 = (m.positions[y] - q).squaredNorm(); d2 < bestD2) bestD2 = d2, best = y;
    });
    return best;
}

std::optional<std::uint32_t> ProgressiveCutter::splitAwayFrom(std::uint32_t a, std::uint32_t b, double u,
                                                              std::uint32_t avoid) {
    const mesh::SurfaceMesh& m = model_.mesh();
    // No split may make a smaller angle than the faces there already have, nor than minAngle_deg where
    // they are better; the best of a few places between the way and the edge's middle.
    double existing = 180;
    for (std::uint32_t f : model_.facesAround(a))
        if (model_.hasCorner(f, b)) {
            const mesh::Face& face = m.faces[f];
            existing = std::min(
                existing, geometry::minAngle(m.positions[face[0]], m.positions[face[1]], m.positions[face[2]]) * 180 /
                              std::numbers::pi);
        }
    const double floor_deg = std::min(existing, params_.minAngle_deg);
    const double fromAvoided = avoid == a ? u : 1 - u;  // the way's place, from the avoided end
    double bestU = -1, bestAngle = -1;
    for (const double clear : {params_.snapFraction, 0.3, 0.4, 0.5}) {
        const double from = std::max(fromAvoided, clear);
        const double split = avoid == a ? from : 1 - from;
        if (const double angle = model_.splitEdgeMinAngle_deg(a, b, split); angle > bestAngle)
            bestAngle = angle, bestU = split;
        if (bestAngle >= params_.minAngle_deg) break;
    }
    if (bestU < 0 || bestAngle < floor_deg) return std::nullopt;
    const std::size_t faces = m.faces.size();
    const std::uint32_t p = model_.splitEdge(a, b, bestU);
    ++stats_.verticesAdded;
    stats_.facesAdded += static_cast<long>(m.faces.size() - faces);
    return p;
}

std::uint32_t ProgressiveCutter::pointOnEdge(std::uint32_t a, std::uint32_t b, double u) {
    // Snap to an end of the edge rather than make a sliver (SPEC beyond: never create slivers).
    const mesh::SurfaceMesh& m = model_.mesh();
    const double length = (m.positions[b] - m.positions[a]).norm();
    const double snap = params_.snapFraction * length;
    const bool sliver = model_.splitEdgeMinAngle_deg(a, b, u) < params_.minAngle_deg;
    if (u * length < snap || (sliver && u < 0.5)) return a;
    if ((1 - u) * length < snap || sliver) return b;
    const std::size_t faces = m.faces.size();
    const std::uint32_t p = model_.splitEdge(a, b, u);
    ++stats_.verticesAdded;
    stats_.facesAdded += static_cast<long>(m.faces.size() - faces);
    return p;
}

bool ProgressiveCutter::advanceTo(std::uint32_t next) {
    // A cut that so far is only its start on a boundary moves along the boundary: nothing lies between.
    if (points_.size() == 1 && onBoundary(points_[0]) && onBoundary(next)) {
        points_[0] = next;
        lipVertices_.assign(1, next);
        return true;
    }
    // Just across a wound (the floor and the far lip so far), the same along the far lip: the cut comes
    // up that wall from the floor under where it leaves the lip, and never crosses back.
    if (points_.size() == 2 && model_.isFloor(points_[0]) && onBoundary(next))
        if (const auto floor = floorBeside(next)) {
            points_ = {*floor, next};
            lipVertices_.push_back(next);
            return true;
        }
    if (!onBoundary(next)) {
        addPoint(next);
        return true;
    }
    const auto crossing = crossingAt(next);
    if (!crossing) {
        joinAt(next);
        return true;
    }
    // The far lip of the wound this cut has just crossed, met again: a wound cut along a rough mesh's
    // edges zigzags, and its far lip can run back into the way. Crossed there, the cut went back to the
    // side it came from, beside where it had entered, where no way led on, and stopped (a stroke across an
    // earlier incision on jittered 9,714 hearts: 21-25 mm cut of 30 on five of sixteen). It is no way on:
    // the cut goes on over the side it is on, round the lip.
    if (justCrossed(next)) return false;
    crossWound(next, *crossing);
    return true;
}

bool ProgressiveCutter::reachBoundary(const Vec3& q) {
    const mesh::SurfaceMesh& m = model_.mesh();
    const std::uint32_t last = points_.back();
    // The last point already touches this cut's own lips; those are not what the blade runs into.
    auto ownLip = [&](std::uint32_t v) {
        return std::find(lipVertices_.begin(), lipVertices_.end(), v) != lipVertices_.end();
    };
    for (std::uint32_t f : model_.facesAround(last)) {
        const mesh::Face& face = m.faces[f];
        int k = 0;
        while (face[k] != last) ++k;
        const std::uint32_t a = face[(k + 1) % 3], b = face[(k + 2) % 3];
        // Only the organ's surface leads anywhere: the edges inside this cut's walls, down to its floor,
        // lie under the lip the blade follows, and snapping to them would join the cut to itself.
        if (!model_.onSurfaceRim(a, b) || (ownLip(a) && ownLip(b))) continue;
        if (justCrossed(a) && justCrossed(b)) continue;  // no way on (advanceTo): leave the edge whole
        const Vec3 ab = m.positions[b] - m.positions[a];
        const double u = std::clamp(ab.dot(q - m.positions[a]) / ab.squaredNorm(), 0.0, 1.0);
        if ((m.positions[a] + u * ab - q).norm() >= params_.snapFraction * ab.norm()) continue;
        const std::uint32_t next = pointOnEdge(a, b, u);
        if (std::find(points_.begin(), points_.end(), next) != points_.end()) return false;
        if (recentLip(next) || !advanceTo(next)) continue;
        return true;
    }
    return false;
}

ProgressiveCutter::BladeProjection ProgressiveCutter::projection(std::uint32_t face, const Vec3& bary,
                                                                 const Vec3& device_m) const {
    // The normal is the surface's over the faces round the face's corners: one face of a rough mesh can
    // tilt tens of degrees from the surface it belongs to, and the blade's depth and the crack's plane
    // follow the surface, not each facet.
    const mesh::SurfaceMesh& m = model_.mesh();
    Vec3 normal = Vec3::Zero();
    for (std::uint32_t corner : m.faces[face])
        for (std::uint32_t f : model_.facesAround(corner))
            if (!model_.isWall(f)) {
                const mesh::Face& g = m.faces[f];
                normal += (m.positions[g[1]] - m.positions[g[0]]).cross(m.positions[g[2]] - m.positions[g[0]]);
            }
    BladeProjection blade{face, bary, 0, normal.norm() > 0 ? Vec3(normal.normalized()) : Vec3::UnitZ()};
    blade.depth_m = (restPoint(m, face, bary) - device_m).dot(blade.normal);
    return blade;
}

std::optional<ProgressiveCutter::BladeProjection> ProgressiveCutter::projectBlade(const Vec3& device_m,
                                                                                  const Vec3& axis) {
    if (points_.empty()) return std::nullopt;
    const mesh::SurfaceMesh& m = model_.mesh();
    // Three rings of faces round the last point: the blade moves well under a face per step at 1 kHz,
    // and a farther target is reached over the next steps.
    nearbyFaces_.clear();
    ring_.assign(1, points_.back());
    for (int ring = 0; ring < 3; ++ring) {
        const std::size_t vertices = ring_.size();
        for (std::size_t i = 0; i < vertices; ++i)
            for (std::uint32_t f : model_.facesAround(ring_[i])) {
                if (std::find(nearbyFaces_.begin(), nearbyFaces_.end(), f) != nearbyFaces_.end()) continue;
                nearbyFaces_.push_back(f);
                for (std::uint32_t v : m.faces[f])
                    if (std::find(ring_.begin(), ring_.end(), v) == ring_.end()) ring_.push_back(v);
            }
    }
    // A blade above the wound it has cut lands on a lip's faces, which would lead the cut back along
    // the lip. Only the tip's own faces may touch this cut's recent lips.
    const std::uint32_t tip = points_.back();
    auto besideTheWound = [&](const mesh::Face& face) {
        if (face[0] == tip || face[1] == tip || face[2] == tip) return false;
        return recentLip(face[0]) || recentLip(face[1]) || recentLip(face[2]);
    };
    // Along the blade: where its line from the tip toward the handle passes through the rest surface,
    // the nearest such place to the tip. The cut is where the blade goes through the surface; the point
    // nearest a tip under a sloping surface lies downhill of that, by the depth times the slope.
    if (axis.squaredNorm() > 0) {
        const Vec3 reach = kBladeReach_m * axis.normalized();
        std::optional<std::pair<std::uint32_t, Vec3>> along;  // face, bary
        double nearest = 1e300;
        for (std::uint32_t f : nearbyFaces_) {
            if (model_.isWall(f) || besideTheWound(m.faces[f])) continue;
            const mesh::Face& face = m.faces[f];
            const Vec3 &a = m.positions[face[0]], &b = m.positions[face[1]], &c = m.positions[face[2]];
            const auto hit = geometry::intersectSegmentTriangle(device_m - reach, device_m + reach, a, b, c);
            if (!hit || std::abs(hit->t - 0.5) >= nearest) continue;
            nearest = std::abs(hit->t - 0.5);
            along = {f, hit->bary};
        }
        if (along) return projection(along->first, along->second, device_m);
    }
    std::optional<std::pair<std::uint32_t, Vec3>> best;
    double bestD2 = 1e300;
    for (std::uint32_t f : nearbyFaces_) {
        // The blade is followed on the organ's surface, not on the walls.
        if (model_.isWall(f) || besideTheWound(m.faces[f])) continue;
        const mesh::Face& face = m.faces[f];
        const Vec3 &a = m.positions[face[0]], &b = m.positions[face[1]], &c = m.positions[face[2]];
        const auto hit = geometry::closestPointOnTriangle(device_m, a, b, c);
        const double d2 = (hit.point - device_m).squaredNorm();
        if (d2 >= bestD2) continue;
        bestD2 = d2;
        best = {f, hit.bary};
    }
    if (!best) return std::nullopt;
    return projection(best->first, best->second, device_m);
}

ProgressiveCutter::ProgressiveCutter(CutModel& model, CutterParams params)
    : model_(model), params_(params), expectedMass_kg_(physics::totalMass(model.model())) {
    // Room for a long cut, and scratch that keeps its memory: a cut in the loop allocates nothing.
    points_.reserve(1024);
    lipVertices_.reserve(2048);
    for (auto* v : {&nearbyFaces_, &ring_}) v->reserve(256);
    crossings_.reserve(64);
#if !defined(NDEBUG) || defined(HAPTICUT_ENABLE_ASSERTS)
    // A model broken before any cut (an unrepaired import's orientation or non-manifold edges) would
    // fail the check after every cut and blame it; such a model is cut unchecked.
    wholeAtStart_ = checkInvariants(model_, expectedMass_kg_, model_.closedBeforeCuts() && params_.walls).ok();
#endif
}

bool ProgressiveCutter::cutAt(std::uint32_t face, const Vec3& bary, double depth_m) {
    bladeDepth_m_ = std::isfinite(depth_m) ? std::max(depth_m, 0.0) : 0.0;
    const bool changed = cutAtUnchecked(face, bary);
#if !defined(NDEBUG) || defined(HAPTICUT_ENABLE_ASSERTS)
    if (changed && wholeAtStart_) {
        const InvariantReport report =
            checkInvariants(model_, expectedMass_kg_, model_.closedBeforeCuts() && params_.walls);
        if (!report.ok()) {
            std::fprintf(stderr, "hapticut: a cut broke the organ: %s\n", report.problems.front().c_str());
            HAPTICUT_ASSERT(report.ok());
        }
    }
#endif
    return changed;
}

bool ProgressiveCutter::cutAtUnchecked(std::uint32_t face, const Vec3& bary) {
    const mesh::SurfaceMesh& m = model_.mesh();
    const Vec3 q = restPoint(m, face, bary);
    if (points_.empty()) {
        if (model_.isWall(face)) return false;  // cuts start on the organ's surface
        // R15: start at a corner if one is close, else in the face (one face becomes three).
        const mesh::Face& f = m.faces[face];
        double shortest = 1e300;
        for (int k = 0; k < 3; ++k)
            shortest = std::min(shortest, (m.positions[f[(k + 1) % 3]] - m.positions[f[k]]).norm());
        ++stats_.cuts;
        if (const auto corner = model_.snapVertex(face, bary, params_.snapFraction * shortest)) {
            addPoint(*corner);
            return false;
        }
        // On or near an edge, split the edge (R16) rather than make a sliver inside the face.
        const std::size_t faces = m.faces.size();
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t a = f[k], b = f[(k + 1) % 3];
            const Vec3 ab = m.positions[b] - m.positions[a];
            const double u = std::clamp(ab.dot(q - m.positions[a]) / ab.squaredNorm(), 0.0, 1.0);
            if ((m.positions[a] + u * ab - q).norm() >= params_.snapFraction * shortest) continue;
            const double at = std::clamp(u, params_.snapFraction, 1 - params_.snapFraction);
            if (model_.splitEdgeMinAngle_deg(a, b, at) < params_.minAngle_deg) break;  // a sliver: try inside the face
            const std::uint32_t v = model_.splitEdge(a, b, at);
            addPoint(v);
            ++stats_.verticesAdded;
            stats_.facesAdded += static_cast<long>(m.faces.size() - faces);
            return true;
        }
        Vec3 inside = bary.cwiseMax(params_.snapFraction / 3);  // keep the new vertex off the face's edges
        inside /= inside.sum();
        if (model_.splitFaceMinAngle_deg(face, inside) < params_.minAngle_deg) {
            // No good place to start here: at the nearest corner.
            int k = 0;
            for (int j = 1; j < 3; ++j)
                if (bary[j] > bary[k]) k = j;
            addPoint(f[k]);
            return false;
        }
        addPoint(model_.splitFace(face, inside));
        ++stats_.verticesAdded;
        stats_.facesAdded += static_cast<long>(m.faces.size() - faces);
        return true;
    }
    // R16: still among the faces around the last point, nothing to do; beyond them, cross edges
    // toward q one after another, so a fast stroke cuts every face on its way in order.
    const std::size_t vertices = m.positions.size();
    for (int i = 0; i < params_.maxCrossingsPerCall && cutting() && !fanContains(points_.back(), q); ++i)
        if (!crossToward(q)) break;
    // At the organ's open edge or a wound's lip the blade slides off without crossing another edge:
    // within the snap distance of such a boundary, the cut runs on to it and joins it.
    if (cutting()) reachBoundary(q);
    // A cut that is only its start, on a lip, with the blade gone across the gap: the lip's faces do
    // not lead there. Start again under the blade, on the far side.
    if (points_.size() == 1 && onBoundary(points_[0]) && !fanContains(points_[0], q)) {
        endCut();
        --stats_.cuts;
        const bool started = cutAtUnchecked(face, bary);
        return started || m.positions.size() != vertices;
    }
    return m.positions.size() != vertices;
}

}  // namespace hapticut::cutting
