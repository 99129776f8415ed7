// Materials, and building a mass-spring model from a mesh with them.
#pragma once

#include "hapticut/mesh/io/thesis_format.h"
#include "hapticut/mesh/surface_mesh.h"
#include "hapticut/physics/mass_spring_model.h"

namespace hapticut::physics {

/// Resolution-independent tissue: the same organ meshed finer feels the same. A spring of rest length
/// L gets stiffness k/L and damping d/L; a node gets mass, anchor stiffness and anchor damping in
/// proportion to its share of the surface area (a third of each adjacent face).
struct Material {
    double totalMass_kg = 0.3;
    double structuralStiffness_N = 0.12;          // k·L; at 7 mm edges, 17 N/m per spring
    double structuralDamping_Ns = 2.4e-4;         // d·L; k_d/k_s = 2 ms, enough for explicit Euler at 1 ms
    double positioningStiffness_N_per_m3 = 1.4e5;  // per m² of surface: 1 N on 7 cm² of tissue moves it ~1 cm
    double positioningDamping_Ns_per_m3 = 660;    // per m² of surface: about 0.3 of critical damping
};

/// Builds the model with the material spread by edge length and area. Springs come from mesh.edges.
MassSpringModel buildModel(const mesh::SurfaceMesh& mesh, const Material& material);

/// Builds the model as the thesis did: one k_s, k_d for every edge spring, one positioning k_s, k_d
/// for every node, the total mass spread evenly over the nodes.
MassSpringModel buildModel(const mesh::SurfaceMesh& mesh, const mesh::io::ThesisPhysics& physics);

/// The thesis-format constants that best stand for `material` on this mesh (means over springs and
/// nodes), for writing a model file.
mesh::io::ThesisPhysics thesisPhysicsFor(const mesh::SurfaceMesh& mesh, const Material& material);

}  // namespace hapticut::physics
