// The progressive cutter.
#include "hapticut/cutting/progressive_cutter.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "hapticut/common/assert.h"
#include "hapticut/cutting/invariants.h"
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
            if (x != v && model_.facesOfEdge(v, x).size() < 2) return true;
    return false;
}

void ProgressiveCutter::addPoint(std::uint32_t vertex) {
    if (!points_.empty()) stats_.length_m += (model_.mesh().positions[vertex] - model_.mesh().positions[points_.back()]).norm();
    points_.push_back(vertex);
    ++stats_.cutPoints;
    // R17: from the third point on, each new point opens the one before it.
    if (points_.size() >= 3) {
        const std::size_t n = points_.size();
        const std::size_t before = model_.mesh().positions.size();
        if (model_.openCut(points_[n - 3], points_[n - 2], points_[n - 1], params_.shorten, params_.retract)) stats_.opened = true;
        stats_.verticesAdded += static_cast<long>(model_.mesh().positions.size() - before);
    }
}

bool ProgressiveCutter::fanContains(std::uint32_t vertex, const Vec3& q) const {
    const mesh::SurfaceMesh& m = model_.mesh();
    for (std::uint32_t f : model_.facesAround(vertex)) {
        const mesh::Face& face = m.faces[f];
        const auto c = geometry::closestPointOnTriangle(q, m.positions[face[0]], m.positions[face[1]], m.positions[face[2]]);
        const double scale = (m.positions[face[1]] - m.positions[face[0]]).norm();
        if ((c.point - q).norm() < 1e-6 * scale) return true;  // on the fan, its edges included
    }
    return false;
}

bool ProgressiveCutter::crossToward(const Vec3& q) {
    const mesh::SurfaceMesh& m = model_.mesh();
    const std::uint32_t last = points_.back();
    const Vec3 from = m.positions[last];
    // Among the edges opposite the last point in its fan, those the way to q crosses: the closest
    // approach of the line from -> q and the edge's line, inside the edge and ahead of `from`. The
    // nearest approach wins, unless it would lead back to a point the cut already has.
    struct Crossing {
        double gap;
        std::uint32_t a, b;
        double u;
    };
    std::vector<Crossing> crossings;
    for (std::uint32_t f : model_.facesAround(last)) {
        const mesh::Face& face = m.faces[f];
        int k = 0;
        while (face[k] != last) ++k;
        const std::uint32_t a = face[(k + 1) % 3], b = face[(k + 2) % 3];
        const Vec3 d1 = q - from, d2 = m.positions[b] - m.positions[a], r = from - m.positions[a];
        const double aa = d1.dot(d1), bb = d1.dot(d2), cc = d2.dot(d2), dd = d1.dot(r), ee = d2.dot(r);
        const double den = aa * cc - bb * bb;
        if (den <= 1e-30 * aa * cc) continue;  // parallel
        const double t = (bb * ee - cc * dd) / den, u = (aa * ee - bb * dd) / den;
        if (t <= 0 || u < 0 || u > 1) continue;
        crossings.push_back({((from + t * d1) - (m.positions[a] + u * d2)).norm(), a, b, u});
    }
    std::sort(crossings.begin(), crossings.end(), [](const Crossing& x, const Crossing& y) { return x.gap < y.gap; });
    auto inCut = [&](std::uint32_t v) { return std::find(points_.begin(), points_.end(), v) != points_.end(); };
    for (const Crossing& c : crossings) {
        // A boundary edge is an open end of the organ or an earlier wound: the cut ends there (joining
        // it cleanly is future work).
        if (model_.facesOfEdge(c.a, c.b).size() < 2) return false;
        // Snap to an end of the edge rather than make a sliver (SPEC beyond: never create slivers).
        const double length = (m.positions[c.b] - m.positions[c.a]).norm();
        const double snap = params_.snapFraction * length;
        std::uint32_t next;
        const bool sliver = model_.splitEdgeMinAngle_deg(c.a, c.b, c.u) < params_.minAngle_deg;
        if (c.u * length < snap || (sliver && c.u < 0.5)) next = c.a;
        else if ((1 - c.u) * length < snap || sliver) next = c.b;
        else {
            const std::size_t faces = m.faces.size();
            next = model_.splitEdge(c.a, c.b, c.u);
            ++stats_.verticesAdded;
            stats_.facesAdded += static_cast<long>(m.faces.size() - faces);
        }
        if (inCut(next)) continue;  // would step back along the cut
        // An open end of the organ or an earlier wound ends the cut (joining it cleanly is future work).
        if (onBoundary(next)) return false;
        addPoint(next);
        return true;
    }
    return false;
}

std::optional<ProgressiveCutter::BladeProjection> ProgressiveCutter::projectBlade(const Vec3& device_m) {
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
    std::optional<BladeProjection> best;
    double bestD2 = 1e300;
    for (std::uint32_t f : nearbyFaces_) {
        const mesh::Face& face = m.faces[f];
        const Vec3 &a = m.positions[face[0]], &b = m.positions[face[1]], &c = m.positions[face[2]];
        const auto hit = geometry::closestPointOnTriangle(device_m, a, b, c);
        const double d2 = (hit.point - device_m).squaredNorm();
        if (d2 >= bestD2) continue;
        bestD2 = d2;
        const Vec3 normal = (b - a).cross(c - a).normalized();
        best = BladeProjection{f, hit.bary, (hit.point - device_m).dot(normal)};
    }
    return best;
}

ProgressiveCutter::ProgressiveCutter(CutModel& model, CutterParams params)
    : model_(model), params_(params), expectedMass_kg_(physics::totalMass(model.model())) {}

bool ProgressiveCutter::cutAt(std::uint32_t face, const Vec3& bary) {
    const bool changed = cutAtUnchecked(face, bary);
#if !defined(NDEBUG) || defined(HAPTICUT_ENABLE_ASSERTS)
    if (changed) {
        const InvariantReport report = checkInvariants(model_, expectedMass_kg_);
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
        // R15: start at a corner if one is close, else in the face (one face becomes three).
        const mesh::Face& f = m.faces[face];
        double shortest = 1e300;
        for (int k = 0; k < 3; ++k) shortest = std::min(shortest, (m.positions[f[(k + 1) % 3]] - m.positions[f[k]]).norm());
        ++stats_.cuts;
        if (const auto corner = model_.snapVertex(face, bary, params_.snapFraction * shortest); corner && !onBoundary(*corner)) {
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
            if (model_.facesOfEdge(a, b).size() < 2) break;  // an open end or a wound: start inside the face
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
            // No good place to start here: at the nearest corner if it is free, else not at all.
            int k = 0;
            for (int j = 1; j < 3; ++j)
                if (bary[j] > bary[k]) k = j;
            --stats_.cuts;
            if (onBoundary(f[k])) return false;
            ++stats_.cuts;
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
    bool changed = false;
    for (int i = 0; i < params_.maxCrossingsPerCall && !fanContains(points_.back(), q); ++i) {
        const std::size_t vertices = m.positions.size();
        if (!crossToward(q)) break;
        changed = changed || m.positions.size() != vertices;
    }
    return changed;
}

}  // namespace hapticut::cutting
