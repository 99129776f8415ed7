// One failure convention at the library's boundary: each public entry point that can fail on what a user
// gives it (a file, a name, a device, a loop's hands) returns an Error naming the problem, and none
// throws. Each case here is bad input a user could bring.
#include <gtest/gtest.h>

#include <chrono>
#include <fstream>
#include <thread>

#include "hapticut/common/text_file.h"
#include "hapticut/haptics/device_name.h"
#include "hapticut/haptics/haptic_loop.h"
#include "hapticut/haptics/openhaptics_device.h"
#include "hapticut/haptics/trajectory.h"
#include "hapticut/haptics/virtual_device.h"
#include "hapticut/mesh/io/mesh_file.h"
#include "hapticut/mesh/io/thesis_format.h"
#include "hapticut/mesh/procedural/heart.h"
#include "hapticut/physics/material.h"
#include "hapticut/scene/haptic_run.h"
#include "hapticut/scene/open_device.h"
#include "hapticut/scene/scene.h"
#include "hapticut/scene/simulation.h"
#include "test_support.h"

namespace hapticut {
namespace {

void write(const std::filesystem::path& file, const std::string& text) { std::ofstream(file) << text; }

/// Expects an error that mentions `needle` (a file name, a key, a number), reached without a throw.
template <class R>
void expectError(const R& result, const std::string& needle) {
    ASSERT_FALSE(result.has_value()) << "expected an error mentioning " << needle;
    EXPECT_NE(result.error().toString().find(needle), std::string::npos) << result.error().toString();
}

TEST(LibraryBoundary, FilesThatAreMissingOrMalformedAreErrorsNamingTheFileAndLine) {
    test::ScratchDir dir;
    const auto missing = dir / "missing.obj";
    EXPECT_NO_THROW(expectError(readTextFile(dir.path()), "is a directory"));
    EXPECT_NO_THROW(expectError(mesh::io::loadMesh(missing), "missing.obj"));
    write(dir / "bad.obj", "v 0 0 0\nv 1 0 0\nf 1 2 7\n");
    EXPECT_NO_THROW(expectError(mesh::io::loadMesh(dir / "bad.obj"), "bad.obj:3"));
    write(dir / "bad.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nend_header\n0\n");
    EXPECT_NO_THROW(expectError(mesh::io::loadMesh(dir / "bad.ply"), "bad.ply"));
    write(dir / "bad.txt", "physics\n1 2 3\n");
    EXPECT_NO_THROW(expectError(mesh::io::readModelFile(dir / "bad.txt"), "bad.txt:2"));
    EXPECT_NO_THROW(expectError(mesh::io::readToolFile(dir / "bad.txt"), "bad.txt"));
    write(dir / "bad.csv", "t,x,y,z,button\n0,0,0,zero,0\n");
    EXPECT_NO_THROW(expectError(haptics::readTrajectory(dir / "bad.csv"), "bad.csv:2"));
    write(dir / "bad.toml", "[model]\ntriangels = 5\n");
    EXPECT_NO_THROW(expectError(scene::readScene(dir / "bad.toml"), "bad.toml:2"));
    EXPECT_NO_THROW(expectError(mesh::io::loadMesh(dir / "mesh.xyz-unknown"), "unknown mesh format"));
    const auto status = mesh::io::saveMesh(dir / "no" / "such" / "folder.obj", test::tetrahedron(), {});
    ASSERT_TRUE(status.has_value());
    EXPECT_NE(status->toString().find("folder.obj"), std::string::npos) << status->toString();
}

TEST(LibraryBoundary, ScenesWithAMissingModelToolOrNameAreErrors) {
    test::ScratchDir dir;
    scene::SceneRequest request;
    request.file = dir / "nowhere.toml";
    EXPECT_NO_THROW(expectError(scene::loadScene(request), "nowhere.toml"));
    write(dir / "scene.toml", "[model]\nsource = \"organ.stl\"\n");
    request.file = dir / "scene.toml";
    EXPECT_NO_THROW(expectError(scene::loadScene(request), "organ.stl"));
    scene::SceneRequest model;
    model.overrides.model = (dir / "liver.obj").string();
    EXPECT_NO_THROW(expectError(scene::loadScene(model), "liver.obj"));
    const scene::SceneFile settings = scene::defaultScene();
    EXPECT_NO_THROW(expectError(scene::toolTip(settings, "chisel"), "unknown tool 'chisel'"));
    EXPECT_NO_THROW(expectError(scene::toolTip(settings, (dir / "knife.txt").string()), "knife.txt"));
    EXPECT_NO_THROW(expectError(scene::loadModelSource((dir / "heart.ply").string(), 1619), "heart.ply"));
}

TEST(LibraryBoundary, DevicesThatCannotOpenAreErrorsSayingWhy) {
    test::ScratchDir dir;
    EXPECT_NO_THROW(expectError(haptics::parseDeviceName("phantom"), "unknown kind 'phantom'"));
    scene::DeviceSetup setup;
    EXPECT_NO_THROW(
        expectError(scene::openDevice({haptics::DeviceKind::Replay, (dir / "path.csv").string()}, setup), "path.csv"));
    haptics::OpenHapticsOptions hd;
    hd.libraryNames = {"libHD-not-here.so"};
    hd.searchFolders = {(dir / "lib").string()};
    EXPECT_NO_THROW(expectError(haptics::OpenHapticsDevice::open(hd), "libHD-not-here.so"));
    EXPECT_NO_THROW(expectError(haptics::OpenHapticsDevice::probeLibrary(hd), "libHD-not-here.so"));
}

TEST(LibraryBoundary, LoopsAndRunsThatCannotWorkAreErrors) {
    const mesh::SurfaceMesh heart = mesh::procedural::makeHeart({});
    cutting::CutModel organ(heart, physics::buildModel(heart, physics::Material{}));
    haptics::VirtualDevice device;
    const std::array<haptics::Hand, 3> three{haptics::Hand{&device}, haptics::Hand{&device}, haptics::Hand{&device}};
    EXPECT_NO_THROW(expectError(haptics::HapticLoop::create(organ, three), "not 3"));
    const std::array<haptics::Hand, 1> one{haptics::Hand{&device}};
    scene::HapticRunConfig openEnded;  // no step count, simulated time: it would never end
    EXPECT_NO_THROW(expectError(scene::runHaptic(organ, one, openEnded), "open-ended"));
}

TEST(LibraryBoundary, ASimulationRefusesWhatDoesNotLoadAndKeepsRunning) {
    test::ScratchDir dir;
    auto scene = scene::loadScene({});
    ASSERT_TRUE(scene.has_value());
    scene::Simulation simulation(std::move(*scene));
    Status status;
    EXPECT_NO_THROW(status = simulation.replay((dir / "path.csv").string()));
    ASSERT_TRUE(status);
    EXPECT_NE(status->toString().find("path.csv"), std::string::npos);
    EXPECT_NO_THROW(status = simulation.loadModel((dir / "kidney.stl").string()));
    ASSERT_TRUE(status);
    EXPECT_NE(status->toString().find("kidney.stl"), std::string::npos);
    EXPECT_NO_THROW(status = simulation.loadTool((dir / "knife.txt").string()));
    ASSERT_TRUE(status);
    EXPECT_EQ(simulation.scene().source.name, "heart") << "the organ it had is kept";
    long step = 0;
    for (int i = 0; i < 200 && step == 0; ++i) {
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
        step = simulation.loop().snapshots().readLatest().step;
    }
    EXPECT_GT(step, 0) << "and its loop goes on";
}

}  // namespace
}  // namespace hapticut
