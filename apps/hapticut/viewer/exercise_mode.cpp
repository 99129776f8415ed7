// The exercise's target, instructions, clock and score card, drawn with Dear ImGui over the scene.
#include "viewer/exercise_mode.h"

#include <imgui.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "hapticut/haptics/trajectory.h"
#include "viewer/overlay.h"

namespace hapticut::viewer {

namespace {

/// A dash and a gap, each this many of the target's half-millimetre samples.
constexpr std::size_t kDashSamples = 4;

std::string minutesAndSeconds(double s) {
    char text[16];
    const int whole = static_cast<int>(std::max(s, 0.0));
    std::snprintf(text, sizeof text, "%d:%02d", whole / 60, whole % 60);
    return text;
}

}  // namespace

ExerciseMode::ExerciseMode(const scene::Scene& scene, const std::string& recordTo) {
    if (!scene.settings.exercise) return;
    exercise_ = scene.settings.exercise;
    target_ = scene::targetLine(scene);
    file_ = !recordTo.empty() ? recordTo
                              : (std::filesystem::temp_directory_path() / "hapticut-exercise-session.csv").string();
}

void ExerciseMode::start(scene::Simulation& session, PanelState& panel, double now_s) {
    if (!active()) return;
    finishRecording(session, panel);
    session.resetModel();
    if (const auto tool = session.scene().toolIndex(scene::exerciseTool(*exercise_))) session.setTool(*tool);
    scored_.reset();
    failure_.clear();
    timedOut_ = false;
    if (const Status failed = session.startRecording(file_)) {
        failure_ = failed->toString();
        running_ = false;
        return;
    }
    started_s_ = now_s;
    running_ = true;
}

void ExerciseMode::update(scene::Simulation& session, PanelState& panel, double now_s) {
    if (running_ && exercise_->timeLimit_s > 0 && now_s - started_s_ >= exercise_->timeLimit_s) {
        timedOut_ = true;
        finish(session, panel);
    }
}

void ExerciseMode::finish(scene::Simulation& session, PanelState& panel) {
    running_ = false;
    finishRecording(session, panel);
    // Scored as `hapticut assess` scores it: the recording replayed on a fresh organ, which takes a moment
    // for a session of a minute.
    const auto recorded = haptics::readTrajectory(file_);
    if (!recorded) {
        failure_ = recorded.error().toString();
        return;
    }
    auto a = scene::assess(session.scene(), *recorded, file_);
    if (!a) {
        failure_ = a.error().toString();
        std::cerr << "hapticut view: could not score the exercise: " << failure_ << "\n";
        return;
    }
    scored_ = std::move(*a);
    // The terminal keeps what the card shows once the window is gone.
    std::cout << "exercise: score " << std::lround(scored_->score) << " of 100"
              << (timedOut_ ? " (the time ran out)" : "") << "; session " << file_ << "\n";
}

void ExerciseMode::draw(scene::Simulation& session, PanelState& panel, const render::OrbitCamera& camera,
                        render::StereoMode mode, float left_px, double now_s) {
    if (!active()) return;
    drawTarget(camera, mode);
    if (scored_ || !failure_.empty())
        drawScoreCard(session, panel, left_px, now_s);
    else
        drawInstructions(session, panel, left_px, now_s);
}

void ExerciseMode::drawTarget(const render::OrbitCamera& camera, render::StereoMode mode) const {
    if (target_.points.size() < 2) return;
    ImDrawList* draw = ImGui::GetBackgroundDrawList();
    const ImVec2 display = ImGui::GetIO().DisplaySize;
    const Vec3 eye = camera.eye();
    for (std::size_t i = 0; i + 1 < target_.points.size(); ++i) {
        if ((i / kDashSamples) % 2 == 1) continue;  // the gap between dashes
        const Vec3 &a = target_.points[i], &b = target_.points[i + 1];
        if (target_.normals[i].dot(eye - a) <= 0) continue;  // on the far side of the organ
        const ScreenPoints pa = toWindow(camera, mode, a, display.x, display.y);
        const ScreenPoints pb = toWindow(camera, mode, b, display.x, display.y);
        for (std::size_t v = 0; v < pa.at.size(); ++v) {
            if (!pa.at[v] || !pb.at[v]) continue;
            const ImVec2 from(static_cast<float>(pa.at[v]->x()), static_cast<float>(pa.at[v]->y()));
            const ImVec2 to(static_cast<float>(pb.at[v]->x()), static_cast<float>(pb.at[v]->y()));
            draw->AddLine(from, to, IM_COL32(20, 20, 20, 200), 5.0f);
            draw->AddLine(from, to, IM_COL32(240, 192, 0, 255), 3.0f);
        }
    }
}

void ExerciseMode::drawInstructions(scene::Simulation& session, PanelState& panel, float left_px, double now_s) {
    const ImVec2 display = ImGui::GetIO().DisplaySize;
    ImGui::SetNextWindowPos(ImVec2(0.5f * (left_px + display.x), 10), ImGuiCond_Always, ImVec2(0.5f, 0));
    ImGui::SetNextWindowSizeConstraints(ImVec2(0, 0), ImVec2(0.9f * (display.x - left_px), display.y * 0.4f));
    ImGui::SetNextWindowBgAlpha(0.8f);
    ImGui::Begin("##exercise", nullptr, ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_AlwaysAutoResize);
    const bool incision = exercise_->kind == scene::SceneExercise::Kind::Incision;
    ImGui::TextColored(ImVec4(1, 0.85f, 0.4f, 1), "%s", incision ? "Exercise: incision" : "Exercise: palpation");
    ImGui::PushTextWrapPos(0.6f * display.x);
    if (!exercise_->instructions.empty()) ImGui::TextUnformatted(exercise_->instructions.c_str());
    if (!incision) ImGui::TextUnformatted("Mark a lump with m (or the stylus's second button) where you feel it.");
    ImGui::PopTextWrapPos();
    const double elapsed = running_ ? now_s - started_s_ : 0;
    if (exercise_->timeLimit_s > 0)
        ImGui::Text("%s of %s", minutesAndSeconds(elapsed).c_str(), minutesAndSeconds(exercise_->timeLimit_s).c_str());
    else
        ImGui::Text("%s", minutesAndSeconds(elapsed).c_str());
    ImGui::SameLine();
    if (ImGui::Button(running_ ? "Finish and score" : "Start")) {
        if (running_)
            finish(session, panel);
        else
            start(session, panel, now_s);
    }
    ImGui::End();
}

void ExerciseMode::drawScoreCard(scene::Simulation& session, PanelState& panel, float left_px, double now_s) {
    const ImVec2 display = ImGui::GetIO().DisplaySize;
    ImGui::SetNextWindowPos(ImVec2(0.5f * (left_px + display.x), 0.5f * display.y), ImGuiCond_Always,
                            ImVec2(0.5f, 0.5f));
    ImGui::SetNextWindowBgAlpha(0.9f);
    ImGui::Begin("Score", nullptr, ImGuiWindowFlags_NoCollapse | ImGuiWindowFlags_AlwaysAutoResize);
    if (!failure_.empty()) {
        ImGui::TextColored(ImVec4(1, 0.45f, 0.4f, 1), "Could not score the session: %s", failure_.c_str());
    } else {
        const scene::Assessment& a = *scored_;
        ImGui::Text("Score: %.0f of 100", a.score);
        if (ImGui::BeginTable("parts", 4, ImGuiTableFlags_RowBg | ImGuiTableFlags_SizingFixedFit)) {
            for (const char* heading : {"part", "yours", "asked", "points"}) ImGui::TableSetupColumn(heading);
            ImGui::TableHeadersRow();
            for (const scene::ScorePart& p : a.parts) {
                ImGui::TableNextRow();
                ImGui::TableNextColumn();
                ImGui::TextUnformatted(p.metric.c_str());
                ImGui::TableNextColumn();
                ImGui::Text("%.2f", p.value);
                ImGui::TableNextColumn();
                ImGui::Text("%.2f", p.threshold);
                ImGui::TableNextColumn();
                ImGui::Text("%.1f of %.0f", p.points, p.weight);
                if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", p.rule.c_str());
            }
            ImGui::EndTable();
        }
        if (timedOut_ || a.timeLimitReached) ImGui::TextUnformatted("The time ran out.");
        ImGui::Text("Session: %s", file_.c_str());
        ImGui::TextDisabled("hapticut assess --scene SCENE --session that file --png card.png draws it");
    }
    if (ImGui::Button("Try again")) start(session, panel, now_s);
    ImGui::SameLine();
    if (ImGui::Button("Close")) scored_.reset(), failure_.clear();
    ImGui::End();
}

}  // namespace hapticut::viewer
