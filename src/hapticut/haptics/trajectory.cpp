// Device trajectories as CSV.
#include "hapticut/haptics/trajectory.h"

#include <cmath>

#include "hapticut/common/line_reader.h"

namespace hapticut::haptics {

namespace {

std::vector<std::string_view> splitCsv(std::string_view line) {
    std::vector<std::string_view> fields;
    std::size_t start = 0;
    while (true) {
        const std::size_t comma = line.find(',', start);
        std::string_view f =
            line.substr(start, comma == std::string_view::npos ? std::string_view::npos : comma - start);
        while (!f.empty() && (f.front() == ' ' || f.front() == '\t')) f.remove_prefix(1);
        while (!f.empty() && (f.back() == ' ' || f.back() == '\t' || f.back() == '\r')) f.remove_suffix(1);
        fields.push_back(f);
        if (comma == std::string_view::npos) return fields;
        start = comma + 1;
    }
}
}  // namespace

Result<Trajectory, Error> parseTrajectory(std::string_view text, const std::filesystem::path& file) {
    try {
        LineReader r(text);
        if (!r.next()) throw ParseFailure{0, "file is empty, expected the header 't,x,y,z,button'"};
        // t,x,y,z,button, then optionally qw,qx,qy,qz (the stylus's orientation; 0,0,0,0 in a sample without), tool (a
        // session's: which of the scene's tools the hand held) and fx,fy,fz (a recording's forces, which are ignored).
        const auto header = splitCsv(r.rawLine());
        static constexpr std::string_view kNames[] = {"t", "x", "y", "z", "button", "qw", "qx", "qy", "qz"};
        static constexpr std::string_view kForces[] = {"fx", "fy", "fz"};
        const auto expected = [&] {
            r.fail(
                "expected the header 't,x,y,z,button', optionally followed by 'qw,qx,qy,qz', then by 'tool' "
                "and then by 'fx,fy,fz'");
        };
        if (header.size() < 5) expected();
        for (std::size_t i = 0; i < 5; ++i)
            if (header[i] != kNames[i])
                r.fail("header column " + std::to_string(i + 1) + " should be '" + std::string(kNames[i]) +
                       "', found '" + std::string(header[i]) + "'");
        std::size_t next = 5;
        const bool hasOrientation = header.size() >= 9 && header[5] == "qw";
        for (std::size_t i = 5; hasOrientation && i < 9; ++i, ++next)
            if (header[i] != kNames[i])
                r.fail("header column " + std::to_string(i + 1) + " should be '" + std::string(kNames[i]) +
                       "', found '" + std::string(header[i]) + "'");
        const std::size_t toolColumn = next < header.size() && header[next] == "tool" ? next++ : 0;
        const bool recorded = next < header.size() && header[next] == "fx";
        for (std::size_t i = 0; recorded && i < 3; ++i, ++next)
            if (next >= header.size() || header[next] != kForces[i])
                r.fail("header column " + std::to_string(next + 1) + " should be '" + std::string(kForces[i]) + "'");
        if (next != header.size()) expected();
        Trajectory out;
        while (r.next()) {
            const auto fields = splitCsv(r.rawLine());
            if (fields.size() != header.size())
                r.fail("expected " + std::to_string(header.size()) + " comma-separated values, found " +
                       std::to_string(fields.size()));
            double v[13];
            for (std::size_t i = 0; i < fields.size(); ++i)
                if (!parseFiniteDouble(fields[i], v[i]))
                    r.fail("expected a finite number for " + std::string(header[i]) + ", found '" +
                           std::string(fields[i]) + "'");
            if (v[4] != 0 && v[4] != 1 && v[4] != 2 && v[4] != 3)
                r.fail("button must be 0 or 1, or 2 and 3 with the second button (a mark) held, found '" +
                       std::string(fields[4]) + "'");
            if (toolColumn && (v[toolColumn] < 0 || v[toolColumn] > 255 || v[toolColumn] != std::floor(v[toolColumn])))
                r.fail("tool must be the index of one of the scene's tools (0, 1, ...), found '" +
                       std::string(fields[toolColumn]) + "'");
            if (!out.points.empty() && v[0] <= out.points.back().t_s)
                r.fail("time must increase: " + std::string(fields[0]) + " s follows " +
                       formatDouble(out.points.back().t_s) + " s");
            TrajectoryPoint p;
            p.t_s = v[0];
            p.sample.position_m = Vec3(v[1], v[2], v[3]);
            p.sample.buttons = static_cast<std::uint32_t>(v[4]);
            // 0,0,0,0: no orientation in this sample (a session's, before its blade was turned).
            if (hasOrientation && (v[5] != 0 || v[6] != 0 || v[7] != 0 || v[8] != 0)) {
                const Eigen::Quaterniond q(v[5], v[6], v[7], v[8]);
                if (q.norm() < 1e-9) r.fail("orientation quaternion has zero length (0,0,0,0 says there is none)");
                p.sample.orientation = q.normalized();
                p.sample.oriented = true;
            }
            if (toolColumn) p.tool = static_cast<int>(v[toolColumn]);
            out.points.push_back(p);
        }
        if (out.points.size() < 2) throw ParseFailure{r.line(), "a trajectory needs at least two samples"};
        return out;
    } catch (const ParseFailure& failure) {
        return unexpected(Error{file, failure.line, failure.message});
    }
}

Result<Trajectory, Error> readTrajectory(const std::filesystem::path& file) {
    const auto text = readTextFile(file, std::size_t{1} << 30);
    if (!text) return unexpected(text.error());
    return parseTrajectory(*text, file);
}

std::string formatTrajectory(const Trajectory& trajectory) {
    // The orientation columns only for a device that reported one: read back, they turn a blade.
    const bool oriented = std::any_of(trajectory.points.begin(), trajectory.points.end(),
                                      [](const TrajectoryPoint& p) { return p.sample.oriented; });
    const bool tools = std::any_of(trajectory.points.begin(), trajectory.points.end(),
                                   [](const TrajectoryPoint& p) { return p.tool >= 0; });
    std::string out =
        std::string(oriented ? "t,x,y,z,button,qw,qx,qy,qz" : "t,x,y,z,button") + (tools ? ",tool\n" : "\n");
    for (const TrajectoryPoint& p : trajectory.points) {
        const Vec3& x = p.sample.position_m;
        const Eigen::Quaterniond& q = p.sample.orientation;
        out += formatDouble(p.t_s) + "," + formatDouble(x.x()) + "," + formatDouble(x.y()) + "," + formatDouble(x.z()) +
               "," + std::to_string(p.sample.buttons);
        if (oriented && !p.sample.oriented) out += ",0,0,0,0";
        if (oriented && p.sample.oriented)
            out += "," + formatDouble(q.w()) + "," + formatDouble(q.x()) + "," + formatDouble(q.y()) + "," +
                   formatDouble(q.z());
        if (tools) out += "," + std::to_string(std::max(p.tool, 0));
        out += "\n";
    }
    return out;
}

}  // namespace hapticut::haptics
