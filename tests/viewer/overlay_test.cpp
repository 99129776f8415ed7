// The overlay over the scene: notices that stay in view, and the force at each tool placed where it shows.
#include <gtest/gtest.h>

#include <imgui.h>

#include "render/camera.h"
#include "viewer/overlay.h"

namespace hapticut::viewer {
namespace {

/// A Dear ImGui context without a window or GPU: enough to lay out and record what a frame draws.
class HeadlessImGui {
public:
    HeadlessImGui() {
        ImGui::CreateContext();
        ImGuiIO& io = ImGui::GetIO();
        io.IniFilename = nullptr;
        io.DisplaySize = ImVec2(1280, 720);
        unsigned char* pixels = nullptr;
        int w = 0, h = 0;
        io.Fonts->GetTexDataAsRGBA32(&pixels, &w, &h);
    }
    ~HeadlessImGui() { ImGui::DestroyContext(); }
    HeadlessImGui(const HeadlessImGui&) = delete;
    HeadlessImGui& operator=(const HeadlessImGui&) = delete;

    /// Advances the clock by `dt_s` and runs one frame of `draw`; the vertices it drew.
    template <class Draw>
    int frame(double dt_s, Draw&& draw) {
        ImGui::GetIO().DeltaTime = static_cast<float>(dt_s);
        ImGui::NewFrame();
        draw();
        ImGui::Render();
        return ImGui::GetDrawData()->TotalVtxCount;
    }
};

TEST(Overlay, NewsFadesAfterTenSecondsAndAnErrorStaysUntilTheNextMessage) {
    HeadlessImGui ui;
    Notice notice;
    ui.frame(0.1, [&] { notice.say("wrote heart-cut.obj", false); });
    EXPECT_TRUE(notice.visibleAt(ImGui::GetTime()));
    ui.frame(0.1, [&] { drawNotice(notice, ImGui::GetTime(), 0); });  // a new window measures itself first
    EXPECT_GT(ui.frame(0.1, [&] { drawNotice(notice, ImGui::GetTime(), 0); }), 0) << "the notice is drawn";
    ui.frame(Notice::kNewsSeconds, [] {});
    EXPECT_FALSE(notice.visibleAt(ImGui::GetTime()));
    EXPECT_EQ(ui.frame(0.1, [&] { drawNotice(notice, ImGui::GetTime(), 0); }), 0) << "and gone ten seconds on";

    ui.frame(0.1, [&] { notice.say("organ.obj:3: expected 3 coordinates after 'v', found 2", true); });
    ui.frame(1000, [] {});
    EXPECT_TRUE(notice.visibleAt(ImGui::GetTime())) << "an error is not missed by looking away";
    ui.frame(0.1, [&] { notice.say("loaded heart.obj", false); });
    EXPECT_FALSE(notice.error);
}

// The ring and the newtons sit on the tool's proxy as the camera sees it, in each half of side-by-side
// stereo, and only while the tool touches or pushes.
TEST(Overlay, TheForceMarkSitsOnTheProxyInEachViewAndOnlyInContact) {
    HeadlessImGui ui;
    render::OrbitCamera camera;
    camera.yaw_rad = 0.55;
    camera.pitch_rad = 0.3;
    const Vec3 proxy(0.01, 0.02, 0.04);
    const auto mono = toWindow(camera, render::StereoMode::Off, proxy, 1280, 720);
    ASSERT_TRUE(mono.at[0]);
    EXPECT_FALSE(mono.at[1]);
    // The cursor's ray through that pixel passes through the proxy.
    const Vec2 px = *mono.at[0];
    const render::Ray ray = render::rayThrough(camera, 2 * px.x() / 1280 - 1, 1 - 2 * px.y() / 720, 1280.0 / 720);
    EXPECT_LT((proxy - ray.origin).cross(ray.direction).norm(), 1e-9);

    const auto pair = toWindow(camera, render::StereoMode::SideBySide, proxy, 1280, 720);
    ASSERT_TRUE(pair.at[0] && pair.at[1]);
    EXPECT_NEAR(pair.at[1]->x() - pair.at[0]->x(), 640, 1e-9);
    EXPECT_LT(pair.at[0]->x(), 640);
    EXPECT_FALSE(toWindow(camera, render::StereoMode::Off, camera.eye() - camera.forward(), 1280, 720).at[0])
        << "behind the eye";

    HandMark pressing{proxy, 1.3, true};
    HandMark free{proxy, 0.0, false};
    const int none = ui.frame(0.1, [&] { drawForceMarks(std::span(&free, 1), 3.3, camera, {}, 1280, 720); });
    const int one = ui.frame(0.1, [&] { drawForceMarks(std::span(&pressing, 1), 3.3, camera, {}, 1280, 720); });
    const int two = ui.frame(
        0.1, [&] { drawForceMarks(std::span(&pressing, 1), 3.3, camera, render::StereoMode::SideBySide, 1280, 720); });
    EXPECT_EQ(none, 0);
    EXPECT_GT(one, 0);
    EXPECT_EQ(two, 2 * one);
}

}  // namespace
}  // namespace hapticut::viewer
