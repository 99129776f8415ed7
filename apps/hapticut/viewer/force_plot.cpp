// Force plot drawn straight into ImGui's draw list.
#include "viewer/force_plot.h"

#include <imgui.h>

#include <algorithm>
#include <cstdio>

namespace hapticut::viewer {

void ForcePlot::add(double t_s, const Vec3& force_N) {
    samples_[next_] = {t_s, force_N};
    next_ = (next_ + 1) % kSamples;
    count_ = std::min(count_ + 1, kSamples);
}

void ForcePlot::draw(double maxForce_N, float width, float height) const {
    ImDrawList* draw = ImGui::GetWindowDrawList();
    const ImVec2 origin = ImGui::GetCursorScreenPos();
    const ImVec2 corner(origin.x + width, origin.y + height);
    draw->AddRectFilled(origin, corner, IM_COL32(20, 22, 28, 255));
    const float zeroY = origin.y + height / 2;
    draw->AddLine(ImVec2(origin.x, zeroY), ImVec2(corner.x, zeroY), IM_COL32(70, 70, 80, 255));
    double shown_s = 0;
    if (count_ >= 2) {
        const auto at = [&](std::size_t i) -> const Sample& {
            return samples_[(next_ + kSamples - count_ + i) % kSamples];
        };
        // The time axis: the last kWindow_s seconds, now at the right edge, whatever the frame rate.
        const double t1 = at(count_ - 1).t_s, t0 = t1 - kWindow_s;
        std::size_t first = 0;
        while (first + 2 < count_ && at(first + 1).t_s <= t0) ++first;
        shown_s = t1 - std::max(at(first).t_s, t0);
        const auto x = [&](double t) {
            return origin.x + static_cast<float>(std::clamp((t - t0) / kWindow_s, 0.0, 1.0)) * width;
        };
        for (int second = 1; second < static_cast<int>(kWindow_s); ++second) {
            const float tickX = x(t1 - second);
            draw->AddLine(ImVec2(tickX, corner.y - 5), ImVec2(tickX, corner.y), IM_COL32(90, 90, 100, 255));
        }
        const auto y = [&](double f) {
            return zeroY - static_cast<float>(std::clamp(f / maxForce_N, -1.0, 1.0)) * (height / 2 - 2);
        };
        const ImU32 colours[4] = {IM_COL32(235, 90, 80, 255), IM_COL32(110, 210, 110, 255),
                                  IM_COL32(100, 150, 255, 255), IM_COL32(240, 240, 240, 255)};
        for (int c = 0; c < 4; ++c)
            for (std::size_t i = first + 1; i < count_; ++i) {
                const Sample &a = at(i - 1), &b = at(i);
                const double fa = c < 3 ? a.force_N[c] : a.force_N.norm(), fb = c < 3 ? b.force_N[c] : b.force_N.norm();
                draw->AddLine(ImVec2(x(a.t_s), y(fa)), ImVec2(x(b.t_s), y(fb)), colours[c], c == 3 ? 2.0f : 1.0f);
            }
    }
    char label[64];
    std::snprintf(label, sizeof label, "+%.1f N", maxForce_N);
    draw->AddText(ImVec2(origin.x + 3, origin.y + 1), IM_COL32(160, 160, 170, 255), label);
    ImGui::Dummy(ImVec2(width, height));
    ImGui::TextColored(ImVec4(0.95f, 0.95f, 0.95f, 1), "|F|");
    ImGui::SameLine();
    ImGui::TextColored(ImVec4(0.92f, 0.35f, 0.31f, 1), "x");
    ImGui::SameLine();
    ImGui::TextColored(ImVec4(0.43f, 0.82f, 0.43f, 1), "y");
    ImGui::SameLine();
    ImGui::TextColored(ImVec4(0.39f, 0.59f, 1.0f, 1), "z");
    ImGui::SameLine();
    ImGui::TextDisabled("over the last %.0f s (a tick a second)", shown_s);
}

}  // namespace hapticut::viewer
