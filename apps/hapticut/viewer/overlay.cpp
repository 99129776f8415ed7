// The hint, the notice and the force marks drawn over the scene.
#include "viewer/overlay.h"

#include <imgui.h>

#include <algorithm>
#include <cstdio>

namespace hapticut::viewer {

void Notice::say(std::string what, bool isError) {
    text = std::move(what);
    error = isError;
    since_s = ImGui::GetTime();
}

namespace {

/// A borderless, click-through box at the bottom of the window, `lift` pixels up, centred right of `left`
/// where there is room for it beside the panel and in the window where there is not.
bool beginBottomBox(const char* id, float lift, float left) {
    const ImVec2 display = ImGui::GetIO().DisplaySize;
    if (display.x - left < 0.5f * display.x) left = 0;
    ImGui::SetNextWindowPos(ImVec2(0.5f * (left + display.x), display.y - lift), ImGuiCond_Always, ImVec2(0.5f, 1.0f));
    ImGui::SetNextWindowSizeConstraints(ImVec2(0, 0), ImVec2(0.95f * (display.x - left), display.y * 0.5f));
    ImGui::SetNextWindowBgAlpha(0.75f);
    return ImGui::Begin(id, nullptr,
                        ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoInputs |
                            ImGuiWindowFlags_NoFocusOnAppearing | ImGuiWindowFlags_NoNav);
}

ImU32 forceColour(double force_N, double maxForce_N, float alpha) {
    const float t = static_cast<float>(std::clamp(force_N / std::max(maxForce_N, 1e-9), 0.0, 1.0));
    return ImGui::GetColorU32(ImVec4(0.2f + 0.8f * t, 0.9f - 0.7f * t, 0.2f, alpha));
}

}  // namespace

void drawNotice(const Notice& notice, double now_s, float left_px) {
    if (!notice.visibleAt(now_s)) return;
    if (beginBottomBox("##notice", 12, left_px)) {
        ImGui::PushTextWrapPos(0.9f * (ImGui::GetIO().DisplaySize.x - left_px));
        if (notice.error)
            ImGui::TextColored(ImVec4(1, 0.45f, 0.4f, 1), "%s", notice.text.c_str());
        else
            ImGui::TextUnformatted(notice.text.c_str());
        ImGui::PopTextWrapPos();
    }
    ImGui::End();
}

void drawStartHint(bool twoHands, float left_px) {
    if (beginBottomBox("##start", 64, left_px)) {
        ImGui::TextColored(ImVec4(1, 0.85f, 0.4f, 1), "Hold the left button on the organ to touch it;");
        ImGui::TextColored(ImVec4(1, 0.85f, 0.4f, 1), "drag to stroke, turn the wheel to push in.");
        ImGui::Text("2: the scalpel   right drag: orbit   %sh: keys", twoHands ? "Tab: the other hand   " : "");
    }
    ImGui::End();
}

ScreenPoints toWindow(const render::OrbitCamera& camera, render::StereoMode mode, const Vec3& point, double width,
                      double height) {
    ScreenPoints out;
    const int views = mode == render::StereoMode::SideBySide ? 2 : 1;
    const double viewWidth = width / views;
    for (int v = 0; v < views; ++v) {
        const auto ndc = render::projectToNdc(camera, point, viewWidth / std::max(height, 1.0));
        if (!ndc) continue;
        out.at[static_cast<std::size_t>(v)] =
            Vec2(v * viewWidth + (ndc->x() + 1) * 0.5 * viewWidth, (1 - ndc->y()) * 0.5 * height);
    }
    return out;
}

void drawForceMarks(std::span<const HandMark> hands, double maxForce_N, const render::OrbitCamera& camera,
                    render::StereoMode mode, double width, double height) {
    ImDrawList* draw = ImGui::GetBackgroundDrawList();
    const auto px = [](const Vec2& p) { return ImVec2(static_cast<float>(p.x()), static_cast<float>(p.y())); };
    for (const HandMark& hand : hands) {
        if (!hand.contact && hand.force_N < 0.05) continue;
        const ScreenPoints proxy = toWindow(camera, mode, hand.proxy_m, width, height);
        const float ring = 8.0f + 28.0f * static_cast<float>(std::clamp(hand.force_N / maxForce_N, 0.0, 1.0));
        char label[32];
        std::snprintf(label, sizeof label, "%.2f N", hand.force_N);
        for (std::size_t v = 0; v < proxy.at.size(); ++v) {
            if (!proxy.at[v]) continue;
            const ImVec2 p = px(*proxy.at[v]);
            draw->AddCircle(p, ring, forceColour(hand.force_N, maxForce_N, 0.9f), 40, 2.0f);
            const ImVec2 at(p.x + ring + 6, p.y - ImGui::GetFontSize() * 0.5f);
            draw->AddText(ImVec2(at.x + 1, at.y + 1), IM_COL32(0, 0, 0, 200), label);
            draw->AddText(at, forceColour(hand.force_N, maxForce_N, 1.0f), label);
        }
    }
}

}  // namespace hapticut::viewer
