// Real OpenGL (Mesa under Xvfb in CI): what the renderer draws, judged from the pixels.
#include <gtest/gtest.h>

#include <algorithm>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "hapticut/cutting/cut_model.h"
#include "hapticut/haptics/trajectory.h"
#include "hapticut/mesh/procedural/heart.h"
#include "hapticut/mesh/procedural/tools.h"
#include "hapticut/physics/material.h"
#include "hapticut/scene/haptic_run.h"
#include "render/gl_context.h"
#include "render/offscreen.h"
#include "render/renderer.h"
#include "test_support.h"

namespace hapticut::render {
namespace {

constexpr int kWidth = 400, kHeight = 320;

/// One hidden GL context for the whole suite: opening one per test would start a server per test.
class Rendering : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        std::string& error = setupError_;
        WindowOptions options;
        options.width = 64;
        options.height = 64;
        options.visible = false;
        window_ = GlWindow::open(options, error).release();
        if (!window_) return;
        const std::vector<mesh::SurfaceMesh> tools = {mesh::procedural::makeProbe(), mesh::procedural::makeScalpel()};
        renderer_ = Renderer::create(tools, error, 256).release();
        if (renderer_) target_ = OffscreenTarget::create(kWidth, kHeight, 4, error).release();
    }
    // Every test needs the context: without a display (or Xvfb) they fail, saying why.
    void SetUp() override { ASSERT_NE(target_, nullptr) << setupError_; }
    static void TearDownTestSuite() {
        delete target_;
        delete renderer_;
        delete window_;
    }

    static mesh::SurfaceMesh heart() { return mesh::procedural::makeHeart({}); }

    static ViewSettings frontView(const mesh::SurfaceMesh& organ) {
        ViewSettings view;
        view.frameOrgan(organ.positions);
        return view;
    }

    static Image draw(const SceneFrame& frame, const ViewSettings& view) {
        target_->bind();
        renderer_->draw(frame, view, kWidth, kHeight);
        return target_->read();
    }

    static SceneFrame restFrame(const mesh::SurfaceMesh& organ, long version) {
        SceneFrame frame;
        frame.organPositions = organ.positions;
        frame.faces = organ.faces;
        frame.uvs = organ.uvs;
        frame.topologyVersion = version;
        frame.showDevice = false;
        return frame;
    }

    /// Pixels that are not the background (the clear colour is dark blue-grey).
    static bool isObject(const std::uint8_t* p) {
        return std::abs(p[0] - 26) + std::abs(p[1] - 28) + std::abs(p[2] - 36) > 30;
    }

    static std::string setupError_;
    static GlWindow* window_;
    static Renderer* renderer_;
    static OffscreenTarget* target_;
};

std::string Rendering::setupError_;
GlWindow* Rendering::window_ = nullptr;
Renderer* Rendering::renderer_ = nullptr;
OffscreenTarget* Rendering::target_ = nullptr;

TEST_F(Rendering, TheDefaultHeartFillsAPlausibleShareAndIsRedWithSpecularHighlights) {
    const mesh::SurfaceMesh organ = heart();
    const Image image = draw(restFrame(organ, 1), frontView(organ));
    long object = 0, highlights = 0;
    double r = 0, g = 0, b = 0;
    for (int y = 0; y < kHeight; ++y)
        for (int x = 0; x < kWidth; ++x) {
            const std::uint8_t* p = image.at(x, y);
            if (!isObject(p)) continue;
            ++object;
            r += p[0];
            g += p[1];
            b += p[2];
            // A highlight: much brighter in green and blue than the muscle's own colour allows.
            highlights += p[1] > 110 && p[0] > 200;
        }
    const double share = static_cast<double>(object) / (kWidth * kHeight);
    EXPECT_GT(share, 0.2) << "the heart is too small or missing";
    EXPECT_LT(share, 0.8) << "the heart overflows the view";
    EXPECT_GT(r, 2.5 * g) << "predominantly red";
    EXPECT_GT(r, 2.5 * b);
    EXPECT_GT(highlights, object / 200) << "no specular highlights (the wet look)";
    EXPECT_LT(highlights, object / 3) << "everything is a highlight";
    // The heart is in the middle of the frame.
    EXPECT_TRUE(isObject(image.at(kWidth / 2, kHeight / 2)));
    EXPECT_FALSE(isObject(image.at(2, 2)));
}

TEST_F(Rendering, WireframeShowsEdgesNotShading) {
    const mesh::SurfaceMesh organ = heart();
    ViewSettings view = frontView(organ);
    const Image shaded = draw(restFrame(organ, 1), view);
    view.wireframe = true;
    const Image wire = draw(restFrame(organ, 1), view);
    long differ = 0, objectShaded = 0, objectWire = 0;
    for (int y = 0; y < kHeight; ++y)
        for (int x = 0; x < kWidth; ++x) {
            differ +=
                std::abs(shaded.at(x, y)[0] - wire.at(x, y)[0]) + std::abs(shaded.at(x, y)[1] - wire.at(x, y)[1]) > 40;
            objectShaded += isObject(shaded.at(x, y));
            objectWire += isObject(wire.at(x, y));
        }
    EXPECT_GT(differ, objectShaded / 4);
    // Lines cover less than filled triangles, but the outline is the same size.
    EXPECT_LT(objectWire, objectShaded);
    EXPECT_GT(objectWire, objectShaded / 10);
}

TEST_F(Rendering, AScalpelStrokeChangesTheImageAlongTheCut) {
    const mesh::SurfaceMesh organ = heart();
    const ViewSettings view = frontView(organ);
    const Image before = draw(restFrame(organ, 1), view);

    cutting::CutModel cut(organ, physics::buildModel(organ, physics::Material{}));
    const auto trajectory =
        haptics::readTrajectory(std::string(HAPTICUT_SOURCE_DIR) + "/assets/trajectories/cut-front.csv");
    ASSERT_TRUE(trajectory);
    scene::HapticRunConfig config;
    config.loop.cutThreshold_N = mesh::procedural::kScalpelThreshold_N;
    const auto run = scene::runHaptic(cut, *trajectory, config);
    ASSERT_TRUE(run.has_value()) << run.error().toString();
    const scene::HapticRunResult& r = *run;
    ASSERT_TRUE(r.cut.opened);
    SceneFrame frame;
    frame.organPositions = cut.model().nodes.position;
    frame.faces = cut.mesh().faces;
    frame.uvs = cut.mesh().uvs;
    frame.topologyVersion = 2;
    frame.showDevice = false;
    const Image after = draw(frame, view);

    // Where the cut line (y = -1 cm on the front, x from -2 to +2 cm) lands in the image.
    Lens lens;
    lens.fovY_rad = view.camera.fovY_rad;
    lens.aspect = static_cast<double>(kWidth) / kHeight;
    lens.near_m = view.camera.distance_m * 0.05;
    lens.far_m = view.camera.distance_m * 20;
    const Eigen::Matrix4d toClip = projectionMatrix(eyeFrustum(lens, Eye::Centre)) * view.camera.view();
    const auto pixelOf = [&](const Vec3& p) {
        const Eigen::Vector4d c = toClip * p.homogeneous();
        return Eigen::Vector2d((c.x() / c.w() + 1) / 2 * kWidth, (1 - c.y() / c.w()) / 2 * kHeight);
    };
    const Eigen::Vector2d from = pixelOf(Vec3(-0.02, -0.01, 0.045)), to = pixelOf(Vec3(0.02, -0.01, 0.045));
    double nearCut = 0, elsewhere = 0, nearPixels = 0, otherPixels = 0;
    for (int y = 0; y < kHeight; ++y)
        for (int x = 0; x < kWidth; ++x) {
            const bool changed = std::abs(before.at(x, y)[0] - after.at(x, y)[0]) +
                                     std::abs(before.at(x, y)[1] - after.at(x, y)[1]) +
                                     std::abs(before.at(x, y)[2] - after.at(x, y)[2]) >
                                 60;
            const bool inBand = x > std::min(from.x(), to.x()) - 10 && x < std::max(from.x(), to.x()) + 10 &&
                                std::abs(y - (from.y() + to.y()) / 2) < 15;
            (inBand ? nearPixels : otherPixels) += 1;
            if (changed) (inBand ? nearCut : elsewhere) += 1;
        }
    const double nearShare = nearCut / nearPixels, otherShare = elsewhere / otherPixels;
    EXPECT_GT(nearShare, 0.05) << "the wound does not show where the scalpel went";
    EXPECT_GT(nearShare, 10 * otherShare) << "the image changed everywhere, not along the cut";
}

TEST_F(Rendering, AnaglyphOffsetsTheRedAndCyanImages) {
    const mesh::SurfaceMesh organ = heart();
    ViewSettings view = frontView(organ);
    view.stereo = StereoMode::Anaglyph;
    // The focal plane far behind the heart: the whole heart is nearer, so the left (red) image lies to
    // the right of the right (cyan) one.
    view.focalLength_m = 3 * view.camera.distance_m;
    view.eyeSeparation_m = view.camera.distance_m / 15;
    const Image image = draw(restFrame(organ, 1), view);
    double redX = 0, cyanX = 0, red = 0, cyan = 0;
    long greenBlueDiffer = 0;
    for (int y = 0; y < kHeight; ++y)
        for (int x = 0; x < kWidth; ++x) {
            const std::uint8_t* p = image.at(x, y);
            if (p[0] > 30) redX += x, red += 1;
            if (p[1] > 30) cyanX += x, cyan += 1;
            greenBlueDiffer += std::abs(p[1] - p[2]) > 2;
        }
    ASSERT_GT(red, 1000);
    ASSERT_GT(cyan, 1000);
    EXPECT_GT(redX / red - cyanX / cyan, 3.0) << "red at " << redX / red << ", cyan at " << cyanX / cyan;
    EXPECT_LT(greenBlueDiffer, kWidth * kHeight / 100) << "the right eye's image is grey through a cyan filter";
}

TEST_F(Rendering, SideBySideDrawsTheHeartInBothHalves) {
    const mesh::SurfaceMesh organ = heart();
    ViewSettings view = frontView(organ);
    view.stereo = StereoMode::SideBySide;
    const Image image = draw(restFrame(organ, 1), view);
    EXPECT_TRUE(isObject(image.at(kWidth / 4, kHeight / 2)));
    EXPECT_TRUE(isObject(image.at(3 * kWidth / 4, kHeight / 2)));
    EXPECT_FALSE(isObject(image.at(kWidth / 2, kHeight / 2))) << "the halves' borders run through the middle";
}

TEST_F(Rendering, TheToolAndTheForceArrowAppearAtTheProxy) {
    const mesh::SurfaceMesh organ = heart();
    const ViewSettings view = frontView(organ);
    SceneFrame frame = restFrame(organ, 1);
    const Image bare = draw(frame, view);
    frame.showDevice = true;
    frame.hands[0].tool = 1;
    frame.hands[0].proxy_m = Vec3(0.06, 0.0, 0.03);
    frame.hands[0].device_m = Vec3(0.055, 0.0, 0.025);
    frame.hands[0].force_N = Vec3(2, 0, 1);
    const Image withTool = draw(frame, view);
    long grey = 0;
    for (int y = 0; y < kHeight; ++y)
        for (int x = 0; x < kWidth; ++x) {
            const std::uint8_t* p = withTool.at(x, y);
            const std::uint8_t* q = bare.at(x, y);
            // The tool is metal: grey where the bare scene was not.
            grey += std::abs(p[0] - q[0]) > 20 && std::abs(p[0] - p[1]) < 40 && std::abs(p[1] - p[2]) < 40 && p[1] > 60;
        }
    EXPECT_GT(grey, 200);
}

/// Runs the hapticut executable with a display (this suite runs under Xvfb); its exit code.
int runHapticut(const std::string& args, const test::ScratchDir& dir) {
    const std::string cmd =
        std::string(HAPTICUT_EXE) + " " + args + " >" + (dir / "out").string() + " 2>" + (dir / "err").string();
    const int status = std::system(cmd.c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::string readAll(const std::filesystem::path& file) {
    std::ifstream in(file);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

TEST(ScreenshotCommand, WritesAPngOfTheCutHeartThatLooksLikeTheInProcessRender) {
    test::ScratchDir dir;
    ASSERT_EQ(runHapticut("screenshot --trajectory " + std::string(HAPTICUT_SOURCE_DIR) +
                              "/assets/trajectories/cut-front.csv --tool scalpel --at 2.0 --size 320x240 --out " +
                              (dir / "cut.png").string(),
                          dir),
              0)
        << readAll(dir / "err");
    std::string error;
    const auto image = loadPng(dir / "cut.png", error);
    ASSERT_TRUE(image) << error;
    EXPECT_EQ(image->width, 320);
    EXPECT_EQ(image->height, 240);
    EXPECT_NE(readAll(dir / "err").find("which cut the organ"), std::string::npos) << readAll(dir / "err");
}

TEST(ScreenshotCommand, RefusesBadArgumentsWithAClearMessage) {
    test::ScratchDir dir;
    EXPECT_EQ(runHapticut("screenshot --size 12by4 --out " + (dir / "a.png").string(), dir), 2);
    EXPECT_NE(readAll(dir / "err").find("WIDTHxHEIGHT"), std::string::npos);
    EXPECT_EQ(runHapticut("screenshot --at 1 --out " + (dir / "a.png").string(), dir), 2);
    EXPECT_NE(readAll(dir / "err").find("--at needs --trajectory"), std::string::npos);
    EXPECT_EQ(runHapticut("screenshot --tool scissors --trajectory " + std::string(HAPTICUT_SOURCE_DIR) +
                              "/assets/trajectories/cut-front.csv --out " + (dir / "a.png").string(),
                          dir),
              2);
    EXPECT_NE(readAll(dir / "err").find("probe scalpel"), std::string::npos) << readAll(dir / "err");
    EXPECT_FALSE(std::filesystem::exists(dir / "a.png"));
}

TEST(ViewCommand, StartsRendersFramesWithTheLoopRunningAndQuitsCleanly) {
    test::ScratchDir dir;
    ASSERT_EQ(runHapticut("view --frames 12 --size 640x480 --report " + (dir / "view.json").string() +
                              " --screenshot " + (dir / "view.png").string(),
                          dir),
              0)
        << readAll(dir / "err");
    const auto report = nlohmann::json::parse(readAll(dir / "view.json"));
    EXPECT_EQ(report["frames"], 12);
    EXPECT_GT(report["fps"].get<double>(), 0);
    EXPECT_GT(report["haptic_steps"].get<long>(), 0) << "the haptic loop ran beside the window";
    EXPECT_EQ(report["size"][0], 640);
    EXPECT_NE(report["provenance"]["command"].get<std::string>().find("view --frames 12"), std::string::npos)
        << "the viewer's report says what made it, like the other commands'";
    EXPECT_FALSE(report["provenance"]["simd_target"].get<std::string>().empty());
    // The driver's threads yield to the haptic loop: Mesa's software renderer runs a worker per core.
    const auto& yielding = report["renderer_threads_yielding"];
    ASSERT_TRUE(yielding.is_array());
    if (report["renderer"].get<std::string>().find("llvmpipe") != std::string::npos) {
        EXPECT_TRUE(std::any_of(yielding.begin(), yielding.end(), [](const auto& name) {
            return name.template get<std::string>().rfind("llvmpipe", 0) == 0;
        })) << yielding;
    }
    std::string error;
    const auto image = loadPng(dir / "view.png", error);
    ASSERT_TRUE(image) << error;
    EXPECT_EQ(image->width, 640);
}

TEST(ViewCommand, APhantomThroughOpenHapticsDrivesTheLoopFromItsServo) {
    test::ScratchDir dir;
    // The HD API's emulation stands in for the vendor's libHD.so.
    const std::string hd = std::string("HAPTICUT_HD_LIBRARY=") + HD_EMULATION_LIBRARY + " ";
    const std::string cmd = hd + HAPTICUT_EXE + " view --device openhaptics --quit-after 0.5 --size 320x240 --report " +
                            (dir / "hd.json").string() + " >" + (dir / "out").string() + " 2>" + (dir / "err").string();
    ASSERT_EQ(std::system(cmd.c_str()), 0) << readAll(dir / "err");
    EXPECT_NE(readAll(dir / "err").find("Emulated Touch"), std::string::npos) << readAll(dir / "err");
    const auto report = nlohmann::json::parse(readAll(dir / "hd.json"));
    // Half a second of wall clock at the servo's 1 kHz, however fast the frames come on a busy machine.
    EXPECT_GT(report["haptic_steps"].get<long>(), 100);
    // Without the library: which one, where it looked, and a failure, not a window with no device.
    EXPECT_EQ(runHapticut("view --device openhaptics:left --frames 10 --size 320x240", dir), 1);
    EXPECT_NE(readAll(dir / "err").find("Install the OpenHaptics runtime"), std::string::npos) << readAll(dir / "err");
    EXPECT_EQ(runHapticut("view --device joystick --frames 1", dir), 2);
    EXPECT_NE(readAll(dir / "err").find("hapticut devices"), std::string::npos) << readAll(dir / "err");
}

// A scene with an exercise opens in its exercise mode: the target is drawn on the organ (amber dashes),
// the exercise's scalpel is in hand, and the session is recorded from the start with the tool in hand.
TEST(ViewCommand, AnExerciseShowsItsTargetAndRecordsTheSessionWithItsTool) {
    test::ScratchDir dir;
    const std::string assets = std::string(HAPTICUT_SOURCE_DIR) + "/assets/";
    ASSERT_EQ(runHapticut("view --scene " + assets + "scenes/incision-front.toml --trajectory " + assets +
                              "sessions/incision-front.csv --quit-after 1.0 --no-panel --screenshot " +
                              (dir / "exercise.png").string() + " --record " + (dir / "session.csv").string(),
                          dir),
              0)
        << readAll(dir / "err");
    std::string error;
    const auto image = loadPng(dir / "exercise.png", error);
    ASSERT_TRUE(image) << error;
    long amber = 0;
    for (int y = 0; y < image->height; ++y)
        for (int x = 0; x < image->width; ++x) {
            const std::uint8_t* p = image->at(x, y);
            amber += std::abs(p[0] - 240) < 12 && std::abs(p[1] - 192) < 12 && p[2] < 30;
        }
    EXPECT_GT(amber, 100) << "the target's dashes";
    const std::string recorded = readAll(dir / "session.csv");
    ASSERT_EQ(recorded.rfind("t,x,y,z,button,qw,qx,qy,qz,tool,fx,fy,fz\n", 0), 0u) << recorded.substr(0, 80);
    const std::size_t rowStart = recorded.find('\n') + 1;
    const std::string firstRow = recorded.substr(rowStart, recorded.find('\n', rowStart) - rowStart);
    EXPECT_NE(firstRow.find(",1,0,0,0"), std::string::npos)
        << "the scalpel (tool 1) in hand, no force yet: " << firstRow;

    // At the time limit the attempt ends and is scored: the card shows, and the terminal keeps its score.
    std::ofstream(dir / "timed.toml") << "[model]\ntriangles = 4000\n[exercise]\nkind = \"incision\"\n"
                                         "path_m = [[-0.015, -0.01, 0.0304], [0.015, -0.01, 0.0275]]\n"
                                         "time_limit_s = 0.5\n";
    ASSERT_EQ(runHapticut("view --scene " + (dir / "timed.toml").string() + " --trajectory " + assets +
                              "sessions/incision-front.csv --quit-after 1.5 --no-panel --record " +
                              (dir / "timed.csv").string(),
                          dir),
              0)
        << readAll(dir / "err");
    EXPECT_NE(readAll(dir / "out").find("exercise: score 0 of 100 (the time ran out); session"), std::string::npos)
        << readAll(dir / "out") << readAll(dir / "err");
}

// Without --size the window fits the screen (Xvfb's here is 1280x1024, the default size), so an ordinary
// laptop's screen shows all of it; --quit-after ends a run that --screenshot captures the last frame of;
// --record writes the device path at the loop's rate.
TEST(ViewCommand, FitsTheScreenQuitsAfterATimeWithItsLastFrameAndRecordsEveryStep) {
    test::ScratchDir dir;
    ASSERT_EQ(runHapticut("view --quit-after 0.8 --no-panel --screenshot " + (dir / "last.png").string() +
                              " --record " + (dir / "path.csv").string(),
                          dir),
              0)
        << readAll(dir / "err");
    std::string error;
    const auto image = loadPng(dir / "last.png", error);
    ASSERT_TRUE(image) << error;
    EXPECT_LE(image->width, 1280 * 95 / 100);
    EXPECT_LE(image->height, 1024 * 90 / 100);
    const std::string recorded = readAll(dir / "path.csv");
    EXPECT_EQ(recorded.rfind("t,x,y,z,button,qw,qx,qy,qz,tool,fx,fy,fz\n0,", 0), 0u) << recorded.substr(0, 80);
    const long rows = static_cast<long>(std::count(recorded.begin(), recorded.end(), '\n')) - 1;
    EXPECT_GT(rows, 200) << "every step of a 1 kHz loop over 0.8 s, not one a frame";
    EXPECT_EQ(runHapticut("view --record " + (dir / "missing" / "p.csv").string() + " --frames 1", dir), 2);
}

TEST(ViewCommand, ReplaysATrajectoryThatCutsTheHeart) {
    test::ScratchDir dir;
    ASSERT_EQ(runHapticut("view --frames 2000000 --tool scalpel --trajectory " + std::string(HAPTICUT_SOURCE_DIR) +
                              "/assets/trajectories/cut-front.csv --size 160x120 --no-panel --report " +
                              (dir / "view.json").string() + " --quit-after 2.6",
                          dir),
              0)
        << readAll(dir / "err");
    const auto report = nlohmann::json::parse(readAll(dir / "view.json"));
    EXPECT_GT(report["cut_events"].get<long>(), 0) << "the scalpel's replayed stroke did not cut in the viewer";
    // What it cut, as `run` reports it: a cut across the front (in one piece in `run`; the viewer's loop
    // runs in real time beside the renderer, whose stalls may ease the press), every opening closed.
    EXPECT_EQ(report["model_resets"].get<long>(), 0);
    EXPECT_GE(report["cuts"].get<long>(), 1);
    EXPECT_LE(report["cuts"].get<long>(), 3);
    EXPECT_GT(report["cut_length_m"].get<double>(), 0.02);
    EXPECT_GT(report["cut_points"].get<long>(), 5);
    EXPECT_EQ(report["wounds_crossed"].get<long>(), 0);
    EXPECT_EQ(report["walls_closed"].get<long>(), report["openings"].get<long>());
}

}  // namespace
}  // namespace hapticut::render
