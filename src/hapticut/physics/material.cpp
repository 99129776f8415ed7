// Building a mass-spring model from a mesh.
#include "hapticut/physics/material.h"

#include "hapticut/common/assert.h"
#include "hapticut/geometry/triangle.h"

namespace hapticut::physics {

namespace {

MassSpringModel modelWithNodes(const mesh::SurfaceMesh& mesh) {
    MassSpringModel model;
    Nodes& n = model.nodes;
    const std::size_t count = mesh.positions.size();
    n.position = mesh.positions;
    n.restPosition = mesh.positions;
    n.velocity.assign(count, Vec3::Zero());
    n.externalForce.assign(count, Vec3::Zero());
    n.mass.assign(count, 0.0);
    n.inverseMass.assign(count, 0.0);
    n.anchorStiffness.assign(count, 0.0);
    n.anchorDamping.assign(count, 0.0);
    Springs& s = model.springs;
    for (const mesh::Edge& e : mesh.edges) {
        s.a.push_back(e[0]);
        s.b.push_back(e[1]);
        s.restLength.push_back((mesh.positions[e[1]] - mesh.positions[e[0]]).norm());
    }
    s.stiffness.assign(s.a.size(), 0.0);
    s.damping.assign(s.a.size(), 0.0);
    return model;
}

/// A third of each adjacent face's area per node, m².
std::vector<double> nodeAreas(const mesh::SurfaceMesh& mesh) {
    std::vector<double> area(mesh.positions.size(), 0.0);
    for (const mesh::Face& f : mesh.faces) {
        const double a = geometry::triangleArea(mesh.positions[f[0]], mesh.positions[f[1]], mesh.positions[f[2]]) / 3;
        for (std::uint32_t v : f) area[v] += a;
    }
    return area;
}

void setMass(Nodes& n, std::size_t i, double mass_kg) {
    n.mass[i] = mass_kg;
    n.inverseMass[i] = mass_kg > 0 ? 1 / mass_kg : 0;  // a massless node (in no face) stays put
}

}  // namespace

MassSpringModel buildModel(const mesh::SurfaceMesh& mesh, const Material& material) {
    MassSpringModel model = modelWithNodes(mesh);
    const std::vector<double> area = nodeAreas(mesh);
    double total = 0;
    for (double a : area) total += a;
    HAPTICUT_ASSERT(total > 0);
    for (std::size_t i = 0; i < area.size(); ++i) {
        setMass(model.nodes, i, material.totalMass_kg * area[i] / total);
        model.nodes.anchorStiffness[i] = material.positioningStiffness_N_per_m3 * area[i];
        model.nodes.anchorDamping[i] = material.positioningDamping_Ns_per_m3 * area[i];
    }
    Springs& s = model.springs;
    for (std::size_t i = 0; i < s.size(); ++i) {
        const double length = std::max(s.restLength[i], 1e-9);
        s.stiffness[i] = material.structuralStiffness_N / length;
        s.damping[i] = material.structuralDamping_Ns / length;
    }
    return model;
}

MassSpringModel buildModel(const mesh::SurfaceMesh& mesh, const mesh::io::ThesisPhysics& physics) {
    MassSpringModel model = modelWithNodes(mesh);
    const std::size_t count = mesh.positions.size();
    for (std::size_t i = 0; i < count; ++i) {
        setMass(model.nodes, i, physics.mass / static_cast<double>(count));
        model.nodes.anchorStiffness[i] = physics.positioningStiffness;
        model.nodes.anchorDamping[i] = physics.positioningDamping;
    }
    model.springs.stiffness.assign(model.springs.size(), physics.structuralStiffness);
    model.springs.damping.assign(model.springs.size(), physics.structuralDamping);
    return model;
}

mesh::io::ThesisPhysics thesisPhysicsFor(const mesh::SurfaceMesh& mesh, const Material& material) {
    const MassSpringModel model = buildModel(mesh, material);
    mesh::io::ThesisPhysics p;
    p.mass = material.totalMass_kg;
    auto mean = [](const std::vector<double>& v) {
        double sum = 0;
        for (double x : v) sum += x;
        return v.empty() ? 0.0 : sum / static_cast<double>(v.size());
    };
    p.structuralStiffness = mean(model.springs.stiffness);
    p.structuralDamping = mean(model.springs.damping);
    p.positioningStiffness = mean(model.nodes.anchorStiffness);
    p.positioningDamping = mean(model.nodes.anchorDamping);
    return p;
}

void applyMaterialField(MassSpringModel& model, const MaterialField& field) {
    if (!field) return;
    Nodes& n = model.nodes;
    for (std::size_t i = 0; i < n.size(); ++i) {
        const MaterialScale s = field(n.restPosition[i]);
        n.anchorStiffness[i] *= s.stiffness;
        n.anchorDamping[i] *= s.damping;
    }
    Springs& springs = model.springs;
    for (std::size_t k = 0; k < springs.size(); ++k) {
        const MaterialScale s = field(0.5 * (n.restPosition[springs.a[k]] + n.restPosition[springs.b[k]]));
        springs.stiffness[k] *= s.stiffness;
        springs.damping[k] *= s.damping;
    }
}

}  // namespace hapticut::physics
