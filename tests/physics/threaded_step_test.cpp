// The implicit step shared out on a pool of threads gives the same bits as on one. Its own binary, so that
// ThreadSanitizer watches it (scripts/test-sanitizers) without the rest of the physics tests.
#include <gtest/gtest.h>

#include <array>

#include "hapticut/mesh/procedural/heart.h"
#include "hapticut/physics/integrators.h"
#include "hapticut/physics/material.h"
#include "test_support.h"

namespace hapticut::physics {
namespace {

// The solve's passes and the assembly shared out on threads (worker_pool.h) sum in chunks fixed by the
// size of the system, not by the threads: the whole organ and the active region, pressed by the tool and
// a point load that needs Newton's corrections, step to the same bits on one thread as on two or three,
// with either preconditioner.
#ifdef HAPTICUT_SANITIZED
// ThreadSanitizer took 76 s over the release build's runs: there the steps through the press's ramp and
// the point load and ten after, on one thread against three (a chunk of rows each).
constexpr int kSteps = 70;
constexpr std::array kThreads{3u};
#else
// The press ramps in over 50 steps and the point load lasts 60: 120 steps cover both and the region's
// settling after.
constexpr int kSteps = 120;
constexpr std::array kThreads{2u, 3u};
#endif

TEST(BackwardEuler, StepsToTheSameBitsOnAnyNumberOfThreads) {
    mesh::procedural::HeartOptions options;
    options.triangles = 9714;  // 4,860 unknowns: three chunks of rows
    const mesh::SurfaceMesh mesh = mesh::procedural::makeHeart(options);
    const MassSpringModel start = buildModel(mesh, Material{});
    for (Preconditioner preconditioner : {Preconditioner::BlockJacobi, Preconditioner::Multilevel})
        for (bool activeRegion : {false, true}) {
            auto run = [&](unsigned threads) {
                MassSpringModel model = start;
                Stepper stepper(Scheme::BackwardEuler);
                stepper.setActiveRegion(activeRegion);
                stepper.setSolverSettings({.threads = threads, .preconditioner = preconditioner});
                int corrected = 0;
                for (int step = 0; step < kSteps; ++step) {
                    test::pressFrontWithTool(model, mesh, step);
                    // A point load at 5 ms steps needs Newton's corrections (the test below).
                    model.nodes.externalForce[4330] = step < 60 ? Vec3(0, 0, -1) : Vec3::Zero();
                    if (step < 60) stepper.wake(4330);
                    const StepResult r = stepper.step(model, 5e-3);
                    EXPECT_TRUE(r.finite);
                    corrected += r.solve.newtonIterations > 1;
                }
                EXPECT_GT(corrected, 0) << "no step needed a Newton correction";
                return model;
            };
            const MassSpringModel one = run(1);
            EXPECT_GT(maxDisplacement(one), 1e-3);
            for (unsigned threads : kThreads) {
                const MassSpringModel many = run(threads);
                for (std::size_t i = 0; i < one.nodes.size(); ++i) {
                    ASSERT_EQ(many.nodes.position[i], one.nodes.position[i])
                        << threads << " threads, node " << i << (activeRegion ? ", active region" : "") << ", "
                        << preconditionerName(preconditioner);
                    ASSERT_EQ(many.nodes.velocity[i], one.nodes.velocity[i]) << threads << " threads, node " << i;
                }
            }
        }
}

}  // namespace
}  // namespace hapticut::physics
