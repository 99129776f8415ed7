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
    double structuralStiffness_N = 0.024;          // k·L; at 5.6 mm edges (1,619 heart), 4.3 N/m per spring
    double structuralDamping_Ns = 2.7e-5;          // d·L; k_d/k_s = 1.1 ms, see below
    double positioningStiffness_N_per_m3 = 2.2e6;  // per m² of surface; ω = 400 rad/s for a node on its anchor
    double positioningDamping_Ns_per_m3 = 5600;    // per m² of surface; about half of critical damping
    // Why these: explicit Euler needs c > ω² dt in every mode and symplectic Euler ω²dt² + 2c·dt <= 4,
    // so on the stiffest node of the 1,619-triangle heart (ω²dt² ≈ 0.7 at dt = 1 ms) the damping ratio
    // k_d/k_s must sit near 1.1 ms for all four integrators to run at 1 ms without substeps (the
    // estimates are 1.25 ms for Euler, 2.1 midpoint, 2.6 RK4 and 1.07 symplectic Euler). Finer
    // meshes are stiffer per node and get substeps automatically (see Stepper).
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
