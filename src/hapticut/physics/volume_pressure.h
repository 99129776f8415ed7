// The organ as a body that keeps its volume: a pressure from the enclosed volume of the closed surface
// (SPEC beyond; thesis 2.2 asks for volume). Chosen over support springs to a centre or medial axis
// (Vassilev & Spanlang 2001) because a pressure acts on the whole surface, so the organ bulges away from
// a press as a fluid-filled or incompressible body does, needs no medial axis of an irregular organ,
// and is resolution-independent (a bulk modulus in pascals, forces from area normals). It needs a closed
// surface, which the walls of cuts keep (cutting/cut_model.h, closeOpening).
#pragma once

#include <span>

#include "hapticut/mesh/surface_mesh.h"

namespace hapticut::physics {

/// The volume the faces enclose (divergence theorem over outward-wound triangles), m^3.
double enclosedVolume(std::span<const Vec3> x, std::span<const mesh::Face> faces);

/// Adds to `f` the pressure forces p dV/dx_i of p = bulk (V0 - V) / V0, the gradient of the energy
/// bulk (V - V0)^2 / (2 V0): squeezed, the organ pushes out everywhere; stretched, it pulls in.
/// Returns V. Never allocates.
double addPressureForces(std::span<const Vec3> x, std::span<const mesh::Face> faces, double bulk_Pa,
                         double restVolume_m3, std::span<Vec3> f);

}  // namespace hapticut::physics
