// Terminal helpers: progress line, vector arguments, JSON files.
#include "terminal.h"

#include <unistd.h>

#include <charconv>
#include <cstdio>
#include <iostream>
#include <sstream>

#include "hapticut/common/line_reader.h"
#include "hapticut/common/text_file.h"

namespace hapticut::app {

Progress::Progress(std::string label) : label_(std::move(label)), terminal_(isatty(STDERR_FILENO) != 0) {}

namespace {

/// "42 s", "3 min 10 s", "2 h 05 min".
std::string duration(double s) {
    char text[32];
    const long t = static_cast<long>(s + 0.5);
    if (t < 60)
        std::snprintf(text, sizeof text, "%ld s", t);
    else if (t < 3600)
        std::snprintf(text, sizeof text, "%ld min %02ld s", t / 60, t % 60);
    else
        std::snprintf(text, sizeof text, "%ld h %02ld min", t / 3600, t / 60 % 60);
    return text;
}

}  // namespace

void Progress::update(long done, long total) {
    const auto now = Clock::now();
    const double since = std::chrono::duration<double>(now - lastLine_).count();
    const long tenth = total > 0 ? 10 * done / total : 0;
    const double elapsed = std::chrono::duration<double>(now - start_).count();
    // A log gets lines only from runs long enough to wonder about.
    if (terminal_ ? since < 0.2 && done < total : elapsed < 5 || (drawn_ && since < 30 && tenth == lastTenth_)) return;
    lastLine_ = now;
    lastTenth_ = tenth;
    std::string left;
    if (done > 0 && done < total && elapsed > 2)
        left = ", about " + duration(elapsed * static_cast<double>(total - done) / static_cast<double>(done)) + " left";
    std::fputs(terminal_ ? "\r" : "", stderr);
    if (total > 0)
        std::fprintf(stderr, "%s %3ld%%  (%ld/%ld)  %s%s", label_.c_str(), 100 * done / total, done, total,
                     duration(elapsed).c_str(), left.c_str());
    else
        std::fprintf(stderr, "%s %ld  %s", label_.c_str(), done, duration(elapsed).c_str());
    std::fputs(terminal_ ? "\033[K" : "\n", stderr);
    std::fflush(stderr);
    drawn_ = true;
}

void Progress::finish() {
    if (terminal_ && drawn_) std::fprintf(stderr, "\r\033[K");
}

std::optional<Vec3> parseVec3(const std::string& text) {
    Vec3 v;
    std::size_t start = 0;
    for (int k = 0; k < 3; ++k) {
        const std::size_t comma = text.find(',', start);
        if ((k < 2) == (comma == std::string::npos)) return std::nullopt;
        const std::string part = text.substr(start, k < 2 ? comma - start : std::string::npos);
        if (!parseFiniteDouble(part, v[k])) return std::nullopt;
        start = comma + 1;
    }
    return v;
}

std::optional<std::pair<int, int>> parseSize(const std::string& text, int min, int max) {
    const auto x = text.find('x');
    if (x == std::string::npos) return std::nullopt;
    int width = 0, height = 0;
    const auto parse = [](const std::string& part, int& value) {
        const auto [end, ec] = std::from_chars(part.data(), part.data() + part.size(), value);
        return ec == std::errc() && end == part.data() + part.size();
    };
    if (!parse(text.substr(0, x), width) || !parse(text.substr(x + 1), height)) return std::nullopt;
    if (width < min || height < min || width > max || height > max) return std::nullopt;
    return std::pair{width, height};
}

std::string solverLine(physics::Scheme scheme, const physics::SolverStats& stats) {
    if (scheme != physics::Scheme::BackwardEuler || stats.solves == 0) return "";
    const Summary iterations = stats.iterations.summary();
    std::ostringstream s;
    s << "implicit steps: " << iterations.p50 << " CG iterations p50, " << iterations.p99 << " p99, " << iterations.max
      << " max; " << stats.unconverged << " of " << stats.solves
      << " solves stopped at the cap (largest relative residual " << stats.maxRelativeResidual << "); "
      << stats.corrected << " steps needed Newton corrections (at most " << stats.maxNewtonIterations
      << " iterations)\n";
    return s.str();
}

bool writeJson(const std::filesystem::path& file, const nlohmann::ordered_json& json) {
    if (const auto error = writeTextFileAtomically(file, json.dump(2) + "\n")) {
        std::cerr << error->toString() << "\n";
        return false;
    }
    return true;
}

namespace {
template <class T>
std::optional<T> printed(Result<T, Error> loaded, const std::vector<Warning>& (*warnings)(const T&)) {
    if (!loaded) {
        std::cerr << loaded.error().toString() << "\n";
        return std::nullopt;
    }
    for (const Warning& w : warnings(*loaded)) std::cerr << "warning: " << w.toString() << "\n";
    return std::move(*loaded);
}
}  // namespace

std::optional<scene::ModelSource> loadModelSource(const std::string& model, int triangles,
                                                  std::span<const std::string> parts) {
    return printed<scene::ModelSource>(
        scene::loadModelSource(model, triangles, parts),
        [](const scene::ModelSource& s) -> const std::vector<Warning>& { return s.warnings; });
}

namespace {
const std::vector<Warning>& sceneWarnings(const scene::Scene& s) { return s.source.warnings; }
}  // namespace

std::optional<scene::Scene> loadScene(const scene::SceneRequest& request) {
    return printed<scene::Scene>(scene::loadScene(request), sceneWarnings);
}

std::optional<scene::Scene> assembleScene(const std::filesystem::path& file, scene::SceneFile settings) {
    return printed<scene::Scene>(scene::assembleScene(file, std::move(settings)), sceneWarnings);
}

}  // namespace hapticut::app
