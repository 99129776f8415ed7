// When the blade opens tissue ahead of it: the fracture-mechanics rule of Mahvash & Hayward (2004),
// "Haptic rendering of cutting: a fracture mechanics approach", for a blade held by a haptic coupling.
#pragma once

#include <optional>

#include <Eigen/Geometry>

#include "hapticut/geometry/vec.h"

namespace hapticut::cutting {

/// A cut advances only while the work the blade does pays for the new cut surface: pushing the blade
/// on by dx opens depth x dx of cut, which costs J x depth x dx, so the blade must push with J x depth
/// along its way. Below that the tissue ahead only deforms and the force rises; at it the cut runs on
/// and the force holds there, whether the blade moves on or stops (it never drops to zero while the
/// blade is in the tissue).
struct FractureParams {
    double toughness_J_per_m2 = 200;  // J, the energy to open one square metre of cut
    double minDepth_m = 0.001;        // a blade at the surface still opens a crack this deep
    double maxDepth_m = 0.01;         // the blade's cutting edge: a crack no deeper than it
};

/// A tool's cut threshold (the press that starts a cut, SPEC R14) as a toughness: a blade cutting
/// kToughnessDepth_m deep (the scalpel's whole edge) cuts with that same force, so tool files from
/// before keep their feel.
inline constexpr double kToughnessDepth_m = 0.01;
inline double toughnessFromThreshold(double threshold_N) { return threshold_N / kToughnessDepth_m; }

/// The blade at `blade_m`, `depth_m` under the rest surface whose outward normal is `normal`, is held
/// by a coupling of stiffness k from the proxy at `proxy_m` (the force on the hand is k (proxy - blade)).
/// Along the surface the tissue pulls it back toward the crack; when that pull exceeds J x depth the
/// crack advances to where the pull is exactly J x depth: the returned crack tip, through which the
/// cut must run. Nothing while the pull is below it (or the blade is not pulling at all).
std::optional<Vec3> advancedCrackTip(const Vec3& blade_m, const Vec3& proxy_m, const Vec3& normal, double depth_m,
                                     double stiffness_N_per_m, const FractureParams& params);

/// A blade whose cutting edge faces `edge` (along the surface, unit): only its stretch along the edge opens
/// tissue, so the crack runs that way alone; across it the blade's flat pushes tissue aside uncut.
std::optional<Vec3> advancedCrackTipAlongEdge(const Vec3& blade_m, const Vec3& tip_m, const Vec3& edge, double depth_m,
                                              double stiffness_N_per_m, const FractureParams& params);

/// The scalpel's edge faces +x of its own frame (procedural::makeScalpel: the blade in the x-z plane, its
/// handle along +z): a device's orientation turns it into the way the blade cuts.
inline Vec3 bladeEdge(const Eigen::Quaterniond& orientation) { return orientation * Vec3::UnitX(); }
/// ...and its handle, +z: the blade's axis, from its tip toward the handle.
inline Vec3 bladeAxis(const Eigen::Quaterniond& orientation) { return orientation * Vec3::UnitZ(); }

/// The force J x depth the blade needs to cut at `depth_m` (within its edge).
inline double cuttingForce_N(double depth_m, const FractureParams& params) {
    const double d = depth_m < params.minDepth_m   ? params.minDepth_m
                     : depth_m > params.maxDepth_m ? params.maxDepth_m
                                                   : depth_m;
    return params.toughness_J_per_m2 * d;
}

}  // namespace hapticut::cutting
