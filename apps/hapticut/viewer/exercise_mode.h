// The viewer's exercise mode, for a scene with an [exercise]: the target drawn on the organ, the
// instructions and a clock, the session recorded from the start, and a score card at the end (on
// Finish or at the time limit) with a button to try again.
#pragma once

#include <optional>
#include <string>

#include "hapticut/scene/assessment.h"
#include "hapticut/scene/simulation.h"
#include "render/camera.h"
#include "render/stereo.h"
#include "viewer/panel.h"

namespace hapticut::viewer {

class ExerciseMode {
public:
    /// Inactive for a scene without an exercise. The session goes to `recordTo`, or else to a file in
    /// the system's temporary folder, which the score card names.
    ExerciseMode(const scene::Scene& scene, const std::string& recordTo);
    bool active() const { return exercise_.has_value(); }

    /// Starts the first attempt: a fresh organ, the recording and the clock.
    void start(scene::Simulation& session, PanelState& panel, double now_s);
    /// Ends the attempt at the time limit.
    void update(scene::Simulation& session, PanelState& panel, double now_s);
    /// The target line (dashed, hidden where the organ turns away), and the instructions with the clock
    /// and a Finish button, or the score card with Try again.
    void draw(scene::Simulation& session, PanelState& panel, const render::OrbitCamera& camera, render::StereoMode mode,
              float left_px, double now_s);
    /// The attempt's score, once one was scored.
    const std::optional<scene::Assessment>& scored() const { return scored_; }
    const std::string& sessionFile() const { return file_; }

private:
    void finish(scene::Simulation& session, PanelState& panel);
    void drawTarget(const render::OrbitCamera& camera, render::StereoMode mode) const;
    void drawInstructions(scene::Simulation& session, PanelState& panel, float left_px, double now_s);
    void drawScoreCard(scene::Simulation& session, PanelState& panel, float left_px, double now_s);

    std::optional<scene::SceneExercise> exercise_;
    scene::TargetLine target_;
    std::string file_;
    double started_s_ = 0;
    bool running_ = false, timedOut_ = false;
    std::optional<scene::Assessment> scored_;
    std::string failure_;  // why the last attempt could not be scored
};

}  // namespace hapticut::viewer
