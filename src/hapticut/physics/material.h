// Materials, and building a mass-spring model from a mesh with them.
#pragma once

#include <functional>

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
    double positioningStiffness_N_per_m3 = 8.8e6;  // per m² of surface; ω = 790 rad/s for a node on its anchor
    double positioningDamping_Ns_per_m3 = 1.2e4;   // per m² of surface; about half of critical damping
    // Why these: the positioning springs carry a probe's point load (edge springs resist a push normal
    // to the surface only to second order), so they are stiff: 230 N/m per node of the 1,619 heart, a
    // 4 mm press gives about 0.6 N through the default 400 N/m coupling. Explicit Euler needs c > ω² dt
    // in every mode and symplectic Euler ω²dt² + 2c·dt <= 4; with k_d/k_s = 1.1 ms for the edge springs
    // the stable steps of the 1,619-triangle heart are 1.1 ms (Euler), 1.7 (midpoint), 2.1 (RK4) and
    // 0.81 (symplectic Euler, so two substeps at 1 ms). Finer meshes are stiffer per node and get
    // substeps automatically (see Stepper).
};

/// Builds the model with the material spread by edge length and area. Springs come from mesh.edges.
MassSpringModel buildModel(const mesh::SurfaceMesh& mesh, const Material& material);

/// Builds the model as the thesis did: one k_s, k_d for every edge spring, one positioning k_s, k_d
/// for every node, the total mass spread evenly over the nodes.
MassSpringModel buildModel(const mesh::SurfaceMesh& mesh, const mesh::io::ThesisPhysics& physics);

/// How a region of tissue differs from the organ's material (a scene's [[regions]]): the stiffness and
/// damping of its springs and anchors multiplied, and the fracture toughness a blade meets there.
struct MaterialScale {
    double stiffness = 1;
    double damping = 1;
    double toughness = 1;
};

/// The scale at a point of the rest shape (m); empty: the tissue is uniform.
using MaterialField = std::function<MaterialScale(const Vec3& rest_m)>;

/// Multiplies each node's anchor by the scale at its rest position and each spring by the scale at its
/// rest midpoint. Nothing changes for an empty field.
void applyMaterialField(MassSpringModel& model, const MaterialField& field);

/// The thesis-format constants that best stand for `material` on this mesh (means over springs and
/// nodes), for writing a model file.
mesh::io::ThesisPhysics thesisPhysicsFor(const mesh::SurfaceMesh& mesh, const Material& material);

}  // namespace hapticut::physics
