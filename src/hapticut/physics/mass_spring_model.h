// The mass-spring model (SPEC R2-R4): nodes and springs in flat parallel arrays.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "hapticut/geometry/vec.h"
#include "hapticut/physics/point_spring.h"

namespace hapticut::physics {

struct Nodes {                            // index i is the same node in every array
    std::vector<Vec3> position;           // m
    std::vector<Vec3> velocity;           // m/s
    std::vector<Vec3> restPosition;       // m, anchor of the positioning spring
    std::vector<Vec3> externalForce;      // N, set by the caller (tool contact), held over a step
    std::vector<double> mass;             // kg, lumped
    std::vector<double> inverseMass;      // 1/kg
    std::vector<double> anchorStiffness;  // N/m, positioning spring (zero rest length)
    std::vector<double> anchorDamping;    // N·s/m, positioning spring

    std::size_t size() const { return position.size(); }
};

struct Springs {                      // structural springs along the mesh edges
    std::vector<std::uint32_t> a, b;  // node indices
    std::vector<double> restLength;   // m
    std::vector<double> stiffness;    // N/m
    std::vector<double> damping;      // N·s/m

    std::size_t size() const { return a.size(); }
};

struct MassSpringModel {
    Nodes nodes;
    Springs springs;
    Vec3 gravity_m_per_s2 = Vec3::Zero();  // the thesis had none
    /// The haptic tools' contacts, one per hand, set by the haptic loop each step (inactive when free).
    std::array<PointSpring, kMaxTools> tools;
    // Thesis rule (R4): a node closer to its rest position than this and slower than the speed below
    // is put back at rest, which stops tiny residual motion.
    double snapDistance_m = 1e-7;
    double snapSpeed_m_per_s = 1e-5;
};

double totalMass(const MassSpringModel& model);
double kineticEnergy(const MassSpringModel& model);    // J
double potentialEnergy(const MassSpringModel& model);  // J, springs and positioning springs
Vec3 linearMomentum(const MassSpringModel& model);     // kg·m/s
double maxDisplacement(const MassSpringModel& model);  // m, largest |x - rest|
/// The same over `nodes` only (the ones a step moved: the rest sleep exactly at rest).
double maxDisplacement(const MassSpringModel& model, std::span<const std::uint32_t> nodes);
/// The largest |length / rest length - 1| over structural springs [first, last): how far the tissue is
/// stretched or squeezed (Provot's 10% is a common limit for cloth and membranes).
double maxStrain(const MassSpringModel& model, std::size_t first, std::size_t last);
bool allFinite(const MassSpringModel& model);

}  // namespace hapticut::physics
