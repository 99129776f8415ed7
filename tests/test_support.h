// Small models and meshes shared by the tests.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "hapticut/common/error.h"
#include "hapticut/common/result.h"
#include "hapticut/mesh/surface_mesh.h"
#include "hapticut/physics/mass_spring_model.h"

namespace hapticut::test {

/// The value, or an empty one with `error` holding the message: for tests that go on to read the message.
template <class T>
T valueOrMessage(Result<T, Error> result, std::string& error) {
    if (!result) {
        error = result.error().message;
        return T{};
    }
    return std::move(*result);
}

/// One node of mass m on a positioning spring (k, c) at the origin, started at (x0, 0, 0) at rest.
/// The snap-back rule is off, so it is exactly the damped oscillator x'' = -k/m x - c/m x'.
physics::MassSpringModel oscillator(double m_kg, double k_N_per_m, double c_Ns_per_m, double x0_m);

/// A tool pressing the front of `mesh` (its model), 3 mm deep after 50 ms (a device approaching) through
/// a 400 N/m coupling clamped at 3.3 N, held until 0.3 s, then lifted; `step` counts milliseconds.
void pressFrontWithTool(physics::MassSpringModel& model, const mesh::SurfaceMesh& mesh, int step);

/// A regular tetrahedron with outward faces (closed, 4 vertices, 6 edges).
mesh::SurfaceMesh tetrahedron();

/// A deterministic, irregular offset of the given size for node i (repeatable "random" perturbations).
Vec3 wobble(std::size_t i, double size_m);

/// The mean length of a mesh's edges, each counted once per face it borders.
double meanEdgeOf(const mesh::SurfaceMesh& mesh);

/// Every vertex moved at random by up to `amount` along each axis, as a noisy segmentation leaves it.
mesh::SurfaceMesh jitteredBy(const mesh::SurfaceMesh& smooth, double amount, unsigned seed);

/// The signed volume enclosed by a closed mesh: positive when the faces point outward.
double signedVolume(const mesh::SurfaceMesh& mesh);

/// A file's bytes as a string; empty when it cannot be read.
std::string slurp(const std::filesystem::path& file);

/// A fresh folder of the test's own, named after the running test and the process, removed again at the end.
/// ctest runs tests in parallel processes, so a folder shared between tests would be deleted under another's feet.
class ScratchDir {
public:
    ScratchDir();
    ~ScratchDir();
    ScratchDir(const ScratchDir&) = delete;
    ScratchDir& operator=(const ScratchDir&) = delete;
    const std::filesystem::path& path() const { return path_; }
    std::filesystem::path operator/(const std::string& name) const { return path_ / name; }

private:
    std::filesystem::path path_;
};

/// Expects a failed parse at `line` (1-based; 0 for none) whose message contains `fragment`.
template <class ParseResult>
void expectError(const ParseResult& result, int line, const std::string& fragment) {
    ASSERT_FALSE(result.has_value()) << "accepted malformed input; expected: " << fragment;
    EXPECT_EQ(result.error().line, line) << result.error().toString();
    EXPECT_NE(result.error().message.find(fragment), std::string::npos) << result.error().toString();
}

}  // namespace hapticut::test
