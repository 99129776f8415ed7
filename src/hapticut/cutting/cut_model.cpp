// Topology edits of the cuttable organ, keeping surface and mass-spring model consistent.
#include "hapticut/cutting/cut_model.h"

#include <algorithm>
#include <array>

#include "hapticut/common/assert.h"
#include "hapticut/common/reserve.h"
#include "hapticut/geometry/triangle.h"
#include "hapticut/mesh/adjacency.h"

namespace hapticut::cutting {

using mesh::edgeKey;

namespace {
/// How far apart an opening's lips move in the rest shape, per local edge length (see openCut).
constexpr double kRestGapPerEdge = 0.05;
}  // namespace

CutModel::CutModel(mesh::SurfaceMesh mesh, physics::MassSpringModel model, physics::MaterialField field)
    : mesh_(std::move(mesh)), model_(std::move(model)), field_(std::move(field)) {
    HAPTICUT_ASSERT(mesh_.positions.size() == model_.nodes.size());
    mesh::completeMesh(mesh_);
    facesAround_ = mesh::buildVertexFaces(mesh_.faces, mesh_.positions.size());
    const mesh::MeshAdjacency adjacency = mesh::buildAdjacency(mesh_.faces);
    closedBeforeCuts_ = !mesh_.faces.empty();
    for (std::size_t e = 0; e < adjacency.edges.size() && closedBeforeCuts_; ++e)
        closedBeforeCuts_ = adjacency.facesOfEdge(e).size() == 2;
    const physics::Springs& s = model_.springs;
    springOfEdge_.reserve(roomToGrow(s.size()), roomToGrow(mesh_.positions.size()));  // as the arrays below
    for (std::uint32_t k = 0; k < s.size(); ++k) springOfEdge_.set(edgeKey(s.a[k], s.b[k]), k);
    // New springs and anchors follow the model's material: springs scale as 1/L (as the
    // resolution-independent material does), anchors with the node's mass (mass follows area). The means
    // are of the tissue without its regions, whose scale each new one takes where it is.
    double kl = 0, dl = 0, km = 0, dm = 0, mass = 0;
    const std::vector<Vec3>& rest = mesh_.positions;
    for (std::size_t k = 0; k < s.size(); ++k) {
        const physics::MaterialScale m = scaleAt(0.5 * (rest[s.a[k]] + rest[s.b[k]]));
        kl += s.stiffness[k] * s.restLength[k] / m.stiffness, dl += s.damping[k] * s.restLength[k] / m.damping;
    }
    for (std::size_t i = 0; i < model_.nodes.size(); ++i) {
        const physics::MaterialScale m = scaleAt(rest[i]);
        km += model_.nodes.anchorStiffness[i] / m.stiffness, dm += model_.nodes.anchorDamping[i] / m.damping;
        mass += model_.nodes.mass[i];
    }
    if (s.size() > 0)
        stiffnessTimesLength_ = kl / static_cast<double>(s.size()),
        dampingTimesLength_ = dl / static_cast<double>(s.size());
    if (mass > 0) anchorStiffnessPerKg_ = km / mass, anchorDampingPerKg_ = dm / mass;
    // Room to grow: a cut appends to every array, and a reallocation of a large organ's arrays in the
    // haptic loop would cost milliseconds. Half as much again covers hours of cutting.
    const std::size_t nodes = roomToGrow(mesh_.positions.size()), springs = roomToGrow(s.size()),
                      faces = roomToGrow(mesh_.faces.size());
    reserveTouched(mesh_.positions, nodes);
    reserveTouched(facesAround_.around, nodes);
    physics::Nodes& n = model_.nodes;
    for (auto* v : {&n.position, &n.velocity, &n.restPosition, &n.externalForce}) reserveTouched(*v, nodes);
    for (auto* v : {&n.mass, &n.inverseMass, &n.anchorStiffness, &n.anchorDamping}) reserveTouched(*v, nodes);
    physics::Springs& sp = model_.springs;
    for (auto* v : {&sp.a, &sp.b}) reserveTouched(*v, springs);
    for (auto* v : {&sp.restLength, &sp.stiffness, &sp.damping}) reserveTouched(*v, springs);
    reserveTouched(mesh_.edges, springs);
    reserveTouched(mesh_.faces, faces);
    reserveTouched(mesh_.uvs, faces);
    reserveTouched(mesh_.normals, faces);
    if (mesh_.hasParts()) reserveTouched(mesh_.faceParts, faces);
    reserveTouched(wall_, faces);
    wall_.assign(mesh_.faces.size(), 0);
    reserveTouched(floorUnder_, nodes);
    // Scratch that keeps its memory: a cut in the loop allocates nothing it does not keep.
    for (auto* v : {&shortened_, &fanFaces_, &fanStart_, &edgeFaces_, &left_, &leftVertices_}) v->reserve(64);
    floorUnder_.assign(mesh_.positions.size(), kNoFloor);
}

std::optional<std::uint32_t> CutModel::springOf(std::uint32_t a, std::uint32_t b) const {
    return springOfEdge_.find(edgeKey(a, b));
}

std::vector<std::uint32_t> CutModel::facesOfEdge(std::uint32_t a, std::uint32_t b) const {
    std::vector<std::uint32_t> out;
    facesOfEdge(a, b, out);
    return out;
}

void CutModel::facesOfEdge(std::uint32_t a, std::uint32_t b, std::vector<std::uint32_t>& out) const {
    out.clear();
    for (std::uint32_t f : facesAround_.around[a])
        if (hasCorner(f, b)) out.push_back(f);
}

CutModel::EdgeFaces CutModel::edgeFaces(std::uint32_t a, std::uint32_t b) const {
    EdgeFaces count;
    for (std::uint32_t f : facesAround_.around[a])
        if (hasCorner(f, b)) ++(isWall(f) ? count.wall : count.surface);
    return count;
}

bool CutModel::onRim(std::uint32_t a, std::uint32_t b) const {
    const EdgeFaces e = edgeFaces(a, b);
    return e.wall > 0 || e.surface < 2;
}

bool CutModel::onSurfaceRim(std::uint32_t a, std::uint32_t b) const {
    const EdgeFaces e = edgeFaces(a, b);
    return e.surface > 0 && (e.wall > 0 || e.surface < 2);
}

bool CutModel::isOpenEdge(std::uint32_t a, std::uint32_t b) const {
    const EdgeFaces e = edgeFaces(a, b);
    return e.surface + e.wall < 2;
}

std::uint32_t CutModel::addVertex(Vec3 rest, Vec3 position, Vec3 velocity, double mass) {
    const auto v = static_cast<std::uint32_t>(mesh_.positions.size());
    mesh_.positions.push_back(rest);
    physics::Nodes& n = model_.nodes;
    if (keepRetiredPositions_ && n.position.size() == n.position.capacity()) {
        // Grow by hand so the old array can be kept: push_back would free it under the views.
        std::vector<Vec3> grown;
        reserveTouched(grown, roomToGrow(n.position.size()));
        grown.assign(n.position.begin(), n.position.end());
        retiredPositions_.push_back(std::exchange(n.position, std::move(grown)));
    }
    n.position.push_back(position);
    n.velocity.push_back(velocity);
    n.restPosition.push_back(rest);
    n.externalForce.push_back(Vec3::Zero());
    n.mass.push_back(mass);
    n.inverseMass.push_back(mass > 0 ? 1 / mass : 0);
    const physics::MaterialScale m = scaleAt(rest);
    n.anchorStiffness.push_back(anchorStiffnessPerKg_ * mass * m.stiffness);
    n.anchorDamping.push_back(anchorDampingPerKg_ * mass * m.damping);
    facesAround_.around.emplace_back();
    floorUnder_.push_back(kNoFloor);
    changes_.nodes.push_back(v);
    return v;
}

void CutModel::setMass(std::uint32_t v, double mass) {
    physics::Nodes& n = model_.nodes;
    n.mass[v] = mass;
    n.inverseMass[v] = mass > 0 ? 1 / mass : 0;
    const physics::MaterialScale m = scaleAt(mesh_.positions[v]);
    n.anchorStiffness[v] = anchorStiffnessPerKg_ * mass * m.stiffness;
    n.anchorDamping[v] = anchorDampingPerKg_ * mass * m.damping;
    changes_.nodes.push_back(v);
}

void CutModel::touchSpring(std::uint32_t k) {
    changes_.springs.push_back(k);
    changes_.nodes.push_back(model_.springs.a[k]);
    changes_.nodes.push_back(model_.springs.b[k]);
}

void CutModel::moveSpringEnd(std::uint32_t k, std::uint32_t from, std::uint32_t to) {
    physics::Springs& s = model_.springs;
    const std::uint32_t other = s.a[k] == from ? s.b[k] : s.a[k];
    springOfEdge_.erase(edgeKey(from, other));
    (s.a[k] == from ? s.a[k] : s.b[k]) = to;
    springOfEdge_.set(edgeKey(to, other), k);
    mesh_.edges[k] = {s.a[k], s.b[k]};  // mesh_.edges stays parallel to the springs: edge k is spring k
    changes_.nodes.push_back(from);
    touchSpring(k);
}

void CutModel::addSpring(std::uint32_t a, std::uint32_t b) {
    if (springOfEdge_.contains(edgeKey(a, b))) return;
    physics::Springs& s = model_.springs;
    const double length = (mesh_.positions[b] - mesh_.positions[a]).norm();
    springOfEdge_.set(edgeKey(a, b), static_cast<std::uint32_t>(s.size()));
    s.a.push_back(a);
    s.b.push_back(b);
    s.restLength.push_back(length);
    s.stiffness.push_back(0);
    s.damping.push_back(0);
    setSpringMaterial(static_cast<std::uint32_t>(s.size() - 1), mesh_.positions[a], mesh_.positions[b], length);
    mesh_.edges.push_back({a, b});
    touchSpring(static_cast<std::uint32_t>(s.size() - 1));
}

void CutModel::setSpringMaterial(std::uint32_t k, const Vec3& restA, const Vec3& restB, double length) {
    const physics::MaterialScale m = scaleAt(0.5 * (restA + restB));
    model_.springs.stiffness[k] = m.stiffness * stiffnessTimesLength_ / std::max(length, 1e-9);
    model_.springs.damping[k] = m.damping * dampingTimesLength_ / std::max(length, 1e-9);
}

void CutModel::replaceFace(std::uint32_t face, const mesh::Face& corners, const mesh::FaceUvs& uvs) {
    for (std::uint32_t v : mesh_.faces[face]) {
        auto& around = facesAround_.around[v];
        around.erase(std::remove(around.begin(), around.end(), face), around.end());
    }
    mesh_.faces[face] = corners;
    mesh_.uvs[face] = uvs;
    mesh_.normals[face] =
        geometry::unitNormal(mesh_.positions[corners[0]], mesh_.positions[corners[1]], mesh_.positions[corners[2]]);
    for (std::uint32_t v : corners) facesAround_.around[v].push_back(face);
    changes_.faces.push_back(face);
}

std::uint32_t CutModel::appendFace(const mesh::Face& corners, const mesh::FaceUvs& uvs, bool wall, std::uint32_t part) {
    const auto face = static_cast<std::uint32_t>(mesh_.faces.size());
    mesh_.faces.push_back(corners);
    wall_.push_back(wall ? 1 : 0);
    mesh_.uvs.push_back(uvs);
    if (mesh_.hasParts()) mesh_.faceParts.push_back(part);
    mesh_.normals.push_back(
        geometry::unitNormal(mesh_.positions[corners[0]], mesh_.positions[corners[1]], mesh_.positions[corners[2]]));
    for (std::uint32_t v : corners) facesAround_.around[v].push_back(face);
    changes_.faces.push_back(face);
    return face;
}

std::uint32_t CutModel::splitFace(std::uint32_t face, const Vec3& bary) {
    const mesh::Face f = mesh_.faces[face];
    const mesh::FaceUvs uv = mesh_.uvs[face];
    const physics::Nodes& n = model_.nodes;
    // Returns a Vec3, not an Eigen expression: an expression would refer to temporaries gone by then.
    auto mix = [&](const std::vector<Vec3>& values) -> Vec3 {
        return bary.x() * values[f[0]] + bary.y() * values[f[1]] + bary.z() * values[f[2]];
    };
    // The rest point lies on the undeformed face (R15's k' = k - N((k - a)·N) for a point given in the
    // face's own barycentric coordinates), so the new springs' rest lengths are right.
    const Vec3 rest = mix(mesh_.positions);
    const Vec3 position = mix(n.position);
    const Vec3 velocity = mix(n.velocity);
    // The face's three masses are shared equally among its corners and the new vertex (R15).
    const double faceMass = n.mass[f[0]] + n.mass[f[1]] + n.mass[f[2]];
    for (std::uint32_t v : f) setMass(v, faceMass / 4);
    const std::uint32_t k = addVertex(rest, position, velocity, faceMass / 4);
    const Vec2 uvk = bary.x() * uv[0] + bary.y() * uv[1] + bary.z() * uv[2];
    replaceFace(face, {f[0], f[1], k}, {uv[0], uv[1], uvk});
    const bool wall = isWall(face);  // a split wall stays wall
    appendFace({f[1], f[2], k}, {uv[1], uv[2], uvk}, wall, mesh_.partOf(face));
    appendFace({f[2], f[0], k}, {uv[2], uv[0], uvk}, wall, mesh_.partOf(face));
    for (std::uint32_t v : f) addSpring(v, k);
    return k;
}

std::uint32_t CutModel::splitEdge(std::uint32_t a, std::uint32_t b, double u) {
    HAPTICUT_ASSERT(u > 0 && u < 1);
    std::vector<std::uint32_t>& faces = edgeFaces_;
    facesOfEdge(a, b, faces);
    physics::Nodes& n = model_.nodes;
    const Vec3 rest = (1 - u) * mesh_.positions[a] + u * mesh_.positions[b];
    const Vec3 position = (1 - u) * n.position[a] + u * n.position[b];
    const Vec3 velocity = (1 - u) * n.velocity[a] + u * n.velocity[b];
    // The new vertex takes a third of each end's mass, weighted by closeness (total conserved).
    const double fromA = n.mass[a] * (1 - u) / 3, fromB = n.mass[b] * u / 3;
    for (const auto& [v, take] : {std::pair{a, fromA}, std::pair{b, fromB}}) setMass(v, n.mass[v] - take);
    const std::uint32_t p = addVertex(rest, position, velocity, fromA + fromB);

    // The edge's spring now joins a and p (its end at b moves to p); p and b get a new one (R16).
    if (const auto k = springOf(a, b)) {
        physics::Springs& s = model_.springs;
        moveSpringEnd(*k, b, p);
        const double length = (mesh_.positions[p] - mesh_.positions[a]).norm();
        s.restLength[*k] = length;
        setSpringMaterial(*k, mesh_.positions[a], mesh_.positions[p], length);
    }
    addSpring(a, p);
    addSpring(p, b);
    for (std::uint32_t face : faces) {
        // Name the face (x, y, c) with x -> y the edge in the face's own winding.
        mesh::Face f = mesh_.faces[face];
        mesh::FaceUvs uv = mesh_.uvs[face];
        int k = 0;
        while (!((f[k] == a && f[(k + 1) % 3] == b) || (f[k] == b && f[(k + 1) % 3] == a))) ++k;
        const std::uint32_t x = f[k], y = f[(k + 1) % 3], c = f[(k + 2) % 3];
        const Vec2 ux = uv[k], uy = uv[(k + 1) % 3], uc = uv[(k + 2) % 3];
        const double t = x == a ? u : 1 - u;  // where p lies from x toward y
        const Vec2 up = (1 - t) * ux + t * uy;
        replaceFace(face, {x, p, c}, {ux, up, uc});
        appendFace({p, y, c}, {up, uy, uc}, isWall(face), mesh_.partOf(face));
        addSpring(p, c);
    }
    return p;
}

std::optional<std::uint32_t> CutModel::openCut(std::uint32_t prev, std::uint32_t v, std::uint32_t next, double shorten,
                                               double retract) {
    // In a consistently oriented mesh the face whose winding runs v -> next lies on the left of the cut.
    auto runs = [&](std::uint32_t f, std::uint32_t from, std::uint32_t to) {
        const mesh::Face& face = mesh_.faces[f];
        for (int k = 0; k < 3; ++k)
            if (face[k] == from && face[(k + 1) % 3] == to) return true;
        return false;
    };
    std::optional<std::uint32_t> start;
    for (std::uint32_t f : facesAround_.around[v])
        if (runs(f, v, next)) start = f;
    if (!start) return std::nullopt;

    // Walk round v from the left face across the edges through v, away from next, until the edge to
    // prev (or to prev's floor, past the wall that closed the cut's tip) or a boundary: those faces are
    // the left side.
    const std::uint32_t prevFloor = floorUnder_[prev];
    std::vector<std::uint32_t>& left = left_;
    left.clear();
    std::uint32_t face = *start;
    for (std::size_t guard = 0; guard <= facesAround_.around[v].size(); ++guard) {
        left.push_back(face);
        // In face (v, x, y) with v -> x first, the edge walked across next is (y, v).
        const mesh::Face& f = mesh_.faces[face];
        int k = 0;
        while (f[k] != v) ++k;
        const std::uint32_t y = f[(k + 2) % 3];
        if (y == prev || y == prevFloor) break;
        std::optional<std::uint32_t> across;
        for (std::uint32_t g : facesAround_.around[v])
            if (g != face && runs(g, v, y)) across = g;
        if (!across || std::find(left.begin(), left.end(), *across) != left.end())
            break;  // a boundary, or all the way round
        face = *across;
    }
    if (left.size() == facesAround_.around[v].size()) return std::nullopt;  // no right side: nothing to open

    physics::Nodes& n = model_.nodes;
    const double half = n.mass[v] / 2;
    const std::uint32_t w = addVertex(mesh_.positions[v], n.position[v], n.velocity[v], half);
    setMass(v, half);

    // Left faces take the duplicate; their vertices other than the cut ends move their springs to it.
    std::vector<std::uint32_t>& leftVertices = leftVertices_;
    leftVertices.clear();
    for (std::uint32_t f : left) {
        mesh::Face corners = mesh_.faces[f];
        for (std::uint32_t& c : corners) {
            if (c == v)
                c = w;
            else
                leftVertices.push_back(c);
        }
        replaceFace(f, corners, mesh_.uvs[f]);
    }
    std::sort(leftVertices.begin(), leftVertices.end());
    leftVertices.erase(std::unique(leftVertices.begin(), leftVertices.end()), leftVertices.end());
    physics::Springs& s = model_.springs;
    for (std::uint32_t x : leftVertices) {
        const auto k = springOf(v, x);
        if (!k) continue;
        if (edgeFaces(v, x).total() > 0) {  // the edge still has a right-side face: a cut edge, both lips need a spring
            addSpring(w, x);
            continue;
        }
        moveSpringEnd(*k, v, w);
    }
    // Pull the wound open: every spring at either copy a little shorter, except along the cut. After
    // the opening the cut's edges at v and v' are boundary edges (the lips) or, behind them, edges of
    // the walls that closed the cut so far; neither is shortened.
    for (std::uint32_t copy : {v, w})
        for (std::uint32_t f : facesAround_.around[copy])
            for (std::uint32_t x : mesh_.faces[f]) {
                if (x == copy || onRim(copy, x)) continue;
                const auto k = springOf(copy, x);
                if (!k || std::find(shortened_.begin(), shortened_.end(), *k) != shortened_.end()) continue;
                shortened_.push_back(*k);
                s.restLength[*k] *= 1 - shorten;
                touchSpring(*k);
            }
    shortened_.clear();
    if (retract > 0) {
        // The surface normal at v crossed with the cut's direction points across the cut, to the left lip.
        const Vec3 along = mesh_.positions[next] - mesh_.positions[prev];
        const Vec3 side = restNormalAround(v, {w}).cross(along);
        if (side.norm() > 0) {
            const double edge = 0.5 * ((mesh_.positions[v] - mesh_.positions[prev]).norm() +
                                       (mesh_.positions[next] - mesh_.positions[v]).norm());
            const Vec3 shift = side.normalized() * (retract * edge);
            n.restPosition[w] += shift;
            n.restPosition[v] -= shift;
            // The rest shape gapes a little too, so walls that close the gap (closeOpening) form a narrow
            // V instead of two walls folded onto each other, on which a later cut could join two points
            // at one place by a spring of no length. A little: moving a lip further would crush the
            // triangles beside it.
            const Vec3 restShift = side.normalized() * (kRestGapPerEdge * edge);
            mesh_.positions[w] += restShift;
            mesh_.positions[v] -= restShift;
            for (std::uint32_t copy : {v, w})
                for (std::uint32_t f : facesAround_.around[copy]) {
                    const mesh::Face& c = mesh_.faces[f];
                    mesh_.normals[f] =
                        geometry::unitNormal(mesh_.positions[c[0]], mesh_.positions[c[1]], mesh_.positions[c[2]]);
                }
        }
    }
    return w;
}

std::optional<std::uint32_t> CutModel::floorUnder(std::uint32_t v) const {
    return floorUnder_[v] == kNoFloor ? std::nullopt : std::optional<std::uint32_t>(floorUnder_[v]);
}

Vec3 CutModel::restNormalAround(std::uint32_t v, std::initializer_list<std::uint32_t> others) const {
    Vec3 surface = Vec3::Zero(), all = Vec3::Zero();
    auto add = [&](std::uint32_t x) {
        for (std::uint32_t f : facesAround_.around[x]) {
            const mesh::Face& c = mesh_.faces[f];
            const Vec3 area =
                (mesh_.positions[c[1]] - mesh_.positions[c[0]]).cross(mesh_.positions[c[2]] - mesh_.positions[c[0]]);
            all += area;
            if (!isWall(f)) surface += area;
        }
    };
    add(v);
    for (std::uint32_t x : others) add(x);
    const Vec3 normal = surface.norm() > 0 ? surface : all;
    return normal.norm() > 0 ? Vec3(normal.normalized()) : Vec3::Zero();
}

bool CutModel::isFloor(std::uint32_t v) const {
    const auto& around = facesAround_.around[v];
    return !around.empty() && std::all_of(around.begin(), around.end(), [&](std::uint32_t f) { return isWall(f); });
}

std::optional<std::uint32_t> CutModel::closeOpening(std::uint32_t v, std::uint32_t w, double depth_m,
                                                    bool amongCorners) {
    // The boundary edge leaving x in its face's winding, if there is exactly one (two: a pinch).
    auto boundaryFrom = [&](std::uint32_t x) -> std::optional<std::uint32_t> {
        std::optional<std::uint32_t> out;
        for (std::uint32_t f : facesAround_.around[x]) {
            const mesh::Face& face = mesh_.faces[f];
            int k = 0;
            while (face[k] != x) ++k;
            const std::uint32_t y = face[(k + 1) % 3];
            if (edgeFaces(x, y).total() != 1) continue;
            if (out) return std::nullopt;
            out = y;
        }
        return out;
    };
    // The gap openCut left is the hole v -> a -> b -> c -> v through w (next and behind are a and c, or
    // c and a): anything longer ran into an open rim or an unclosed wound, and stays open.
    std::array<std::uint32_t, 4> hole{v, 0, 0, 0};
    for (int i = 1; i <= 4; ++i) {
        const auto to = boundaryFrom(hole[static_cast<std::size_t>(i - 1)]);
        if (!to || (i < 4 && *to == v) || (i == 4 && *to != v)) return std::nullopt;
        if (i < 4) hole[static_cast<std::size_t>(i)] = *to;
    }
    if (hole[2] != w || hole[1] == hole[3]) return std::nullopt;
    const Vec3 normal = restNormalAround(v, {w});
    // Lips that did not gape apart (openCut without retract) would fold the two walls onto each other.
    if (normal.norm() == 0 || !(depth_m > 0) || (mesh_.positions[w] - mesh_.positions[v]).norm() < 1e-3 * depth_m)
        return std::nullopt;

    physics::Nodes& n = model_.nodes;
    const double fromV = n.mass[v] / 3, fromW = n.mass[w] / 3;  // the floor's share (total conserved)
    setMass(v, n.mass[v] - fromV);
    setMass(w, n.mass[w] - fromW);
    Vec3 rest = 0.5 * (mesh_.positions[v] + mesh_.positions[w]) - depth_m * normal;
    Vec3 position = 0.5 * (n.position[v] + n.position[w]) - depth_m * normal;
    if (amongCorners) {
        // The middle of the three places the hole spans: the lips (v and w, side by side), next and behind.
        auto middle = [&](const std::vector<Vec3>& x) {
            return (0.5 * (x[hole[0]] + x[hole[2]]) + x[hole[1]] + x[hole[3]]) / 3.0;
        };
        rest = middle(mesh_.positions), position = middle(n.position);
    }
    const std::uint32_t q = addVertex(rest, position, 0.5 * (n.velocity[v] + n.velocity[w]), fromV + fromW);
    floorUnder_[v] = floorUnder_[w] = q;

    // The walls' own UVs for their material: v from 0 at a lip to 1 at the floor, u along the cut in
    // wall depths, so the shader darkens toward the floor and streaks along the cut.
    const Vec3 along = (mesh_.positions[hole[1]] - mesh_.positions[hole[3]]).normalized();
    auto uvOf = [&](std::uint32_t x) {
        const double u = mesh_.positions[x].dot(along) / depth_m;
        return Vec2(u, x == q || isFloor(x) ? 1.0 : 0.0);
    };
    std::array<Vec2, 4> uv{};
    for (std::size_t i = 0; i < 4; ++i) uv[i] = uvOf(hole[i]);
    const Vec2 uvq = uvOf(q);
    // Each hole edge x -> y runs so in its one face; the wall face on its other side runs y -> x. The
    // walls are of the part the hole opened.
    const std::uint32_t part = mesh_.partOf(facesAround_.around[hole[0]].front());
    for (std::size_t i = 0; i < 4; ++i) {
        const std::size_t j = (i + 1) % 4;
        appendFace({hole[j], hole[i], q}, {uv[j], uv[i], uvq}, true, part);
    }
    for (std::uint32_t x : hole) addSpring(q, x);
    return q;
}

void CutModel::fansAround(std::uint32_t v, std::vector<std::uint32_t>& faces,
                          std::vector<std::uint32_t>& fanStart) const {
    faces.clear();
    fanStart.clear();
    const std::vector<std::uint32_t>& around = facesAround_.around[v];
    // Flood each fan from a face not yet taken, across shared edges through v. Fans are small (a
    // vertex's valence), so the linear searches cost less than any set would.
    for (std::uint32_t seed : around) {
        if (std::find(faces.begin(), faces.end(), seed) != faces.end()) continue;
        fanStart.push_back(static_cast<std::uint32_t>(faces.size()));
        faces.push_back(seed);
        for (std::size_t i = fanStart.back(); i < faces.size(); ++i) {
            const mesh::Face f = mesh_.faces[faces[i]];
            for (std::uint32_t x : f) {
                if (x == v) continue;
                if (edgeFaces(v, x).total() != 2) continue;  // a boundary edge: the fan ends here
                for (std::uint32_t g : around)
                    if (hasCorner(g, x) && std::find(faces.begin(), faces.end(), g) == faces.end()) faces.push_back(g);
            }
        }
    }
    fanStart.push_back(static_cast<std::uint32_t>(faces.size()));
}

int CutModel::separateFans(std::uint32_t v) {
    fansAround(v, fanFaces_, fanStart_);
    const std::size_t fans = fanStart_.size() - 1;
    if (fans <= 1) return 0;
    physics::Nodes& n = model_.nodes;
    const double mass = n.mass[v];
    const auto total = static_cast<double>(fanFaces_.size());
    double given = 0;
    for (std::size_t k = 1; k < fans; ++k) {
        const double share = mass * static_cast<double>(fanStart_[k + 1] - fanStart_[k]) / total;
        given += share;
        const std::uint32_t w = addVertex(mesh_.positions[v], n.position[v], n.velocity[v], share);
        n.restPosition[w] = n.restPosition[v];  // the anchor as v's, which an opening may have moved
        for (std::uint32_t i = fanStart_[k]; i < fanStart_[k + 1]; ++i) {
            const std::uint32_t f = fanFaces_[i];
            mesh::Face corners = mesh_.faces[f];
            // Each edge through v belongs to one fan only (two faces on an edge are in the same fan), so
            // its spring moves with the fan; the fan's next face on that edge finds it moved already.
            for (std::uint32_t x : corners)
                if (x != v)
                    if (const auto spring = springOf(v, x)) moveSpringEnd(*spring, v, w);
            for (std::uint32_t& c : corners)
                if (c == v) c = w;
            replaceFace(f, corners, mesh_.uvs[f]);
        }
    }
    setMass(v, mass - given);
    return static_cast<int>(fans - 1);
}

double CutModel::splitEdgeMinAngle_deg(std::uint32_t a, std::uint32_t b, double u) const {
    const auto& x = mesh_.positions;
    const Vec3 p = (1 - u) * x[a] + u * x[b];
    double worst = 180;
    for (std::uint32_t f : facesAround_.around[a]) {
        if (!hasCorner(f, b)) continue;
        const mesh::Face& face = mesh_.faces[f];
        std::uint32_t c = face[0];
        for (std::uint32_t v : face)
            if (v != a && v != b) c = v;
        worst = std::min({worst, geometry::minAngle(x[a], p, x[c]), geometry::minAngle(p, x[b], x[c])});
    }
    return worst * 180 / 3.14159265358979323846;
}

double CutModel::splitFaceMinAngle_deg(std::uint32_t face, const Vec3& bary) const {
    const auto& x = mesh_.positions;
    const mesh::Face& f = mesh_.faces[face];
    const Vec3 p = bary.x() * x[f[0]] + bary.y() * x[f[1]] + bary.z() * x[f[2]];
    double worst = 180;
    for (int k = 0; k < 3; ++k) worst = std::min(worst, geometry::minAngle(x[f[k]], x[f[(k + 1) % 3]], p));
    return worst * 180 / 3.14159265358979323846;
}

std::optional<std::uint32_t> CutModel::snapVertex(std::uint32_t face, const Vec3& bary, double radius_m) const {
    const mesh::Face& f = mesh_.faces[face];
    const Vec3 point =
        bary.x() * mesh_.positions[f[0]] + bary.y() * mesh_.positions[f[1]] + bary.z() * mesh_.positions[f[2]];
    std::optional<std::uint32_t> best;
    double bestDistance = radius_m;
    for (std::uint32_t v : f) {
        const double d = (mesh_.positions[v] - point).norm();
        if (d <= bestDistance) bestDistance = d, best = v;
    }
    return best;
}

}  // namespace hapticut::cutting
