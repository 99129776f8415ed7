// Wavefront OBJ reader and writer. Vertex indices are kept as written: Assimp-style importers split
// vertices per corner, which would merge or lose the coincident vertices an opened cut creates.
#include "hapticut/mesh/io/obj_format.h"

#include "hapticut/common/line_reader.h"

namespace hapticut::mesh::io {

namespace {

/// OBJ indices are 1-based, or negative counting back from the latest element.
std::size_t resolveIndex(const LineReader& r, std::string_view token, std::size_t count, std::string_view what) {
    const bool negative = !token.empty() && token.front() == '-';
    std::uint64_t v = 0;
    if (!parseUnsigned(negative ? token.substr(1) : token, v) || v == 0)
        r.fail("expected a " + std::string(what) + " index (1-based, or negative), found '" + std::string(token) + "'");
    if (v > count)
        r.fail(std::string(what) + " index " + std::string(token) + " is out of range: " + std::to_string(count) +
               " defined so far");
    return negative ? count - v : v - 1;
}

}  // namespace

Result<ImportedMesh, Error> parseObj(std::string_view text, const std::filesystem::path& file) {
    try {
        LineReader r(text);
        ImportedMeshBuilder out;
        SurfaceMesh& m = out.mesh();
        std::vector<Vec2> texcoords;
        std::vector<std::size_t> vi, ti;
        while (r.next()) {
            const std::string_view key = r.token(0);
            if (key == "v") {
                if (r.tokens().size() < 4) r.expectTokens(4, "'v <x> <y> <z>'");
                m.positions.emplace_back(r.number(1, "x"), r.number(2, "y"), r.number(3, "z"));
            } else if (key == "vt") {
                if (r.tokens().size() < 3) r.expectTokens(3, "'vt <u> <v>'");
                texcoords.emplace_back(r.number(1, "u"), r.number(2, "v"));
            } else if (key == "f") {
                if (r.tokens().size() < 4)
                    r.fail("a face needs at least 3 corners, found " + std::to_string(r.tokens().size() - 1));
                vi.clear();
                ti.clear();
                for (std::size_t c = 1; c < r.tokens().size(); ++c) {
                    const std::string_view corner = r.token(c);
                    const std::size_t slash = corner.find('/');
                    vi.push_back(resolveIndex(r, corner.substr(0, slash), m.positions.size(), "vertex"));
                    if (slash != std::string_view::npos) {
                        const std::string_view rest = corner.substr(slash + 1);
                        const std::string_view t = rest.substr(0, rest.find('/'));
                        if (!t.empty()) ti.push_back(resolveIndex(r, t, texcoords.size(), "texture coordinate"));
                    }
                }
                if (!ti.empty() && ti.size() != vi.size())
                    r.fail("some corners of this face have texture coordinates and some do not");
                for (std::size_t c = 1; c + 1 < vi.size(); ++c) {  // fan triangulation of polygons
                    const Face f{static_cast<std::uint32_t>(vi[0]), static_cast<std::uint32_t>(vi[c]),
                                 static_cast<std::uint32_t>(vi[c + 1])};
                    if (ti.empty())
                        out.addFace(f, {Vec2::Zero(), Vec2::Zero(), Vec2::Zero()});
                    else
                        out.addFace(f, {texcoords[ti[0]], texcoords[ti[c]], texcoords[ti[c + 1]]});
                }
            } else if (key == "o" && r.tokens().size() > 1) {
                // An object's name is the rest of the line, spaces and all ("left ventricle").
                std::string_view name =
                    r.rawLine().substr(static_cast<std::size_t>(r.token(1).data() - r.rawLine().data()));
                name = name.substr(0, name.find_last_not_of(" \t\r") + 1);
                out.beginPart(std::string(name));
            } else if (key == "g" || key == "o") {
                // A group line may list several groups; the first names the part.
                out.beginPart(r.tokens().size() > 1 ? std::string(r.token(1)) : std::string());
            }
            // vn, s, usemtl, mtllib, l and the rest carry nothing the simulation uses.
        }
        return out.finish(file, "'f' lines with at least 3 vertex indices");
    } catch (const ParseFailure& failure) {
        return unexpected(Error{file, failure.line, failure.message});
    }
}

std::string formatObj(const SurfaceMesh& mesh) {
    std::string out = "# Hapticut mesh: " + std::to_string(mesh.positions.size()) + " vertices, " +
                      std::to_string(mesh.faces.size()) + " faces\n";
    for (const Vec3& p : mesh.positions)
        out += "v " + formatDouble(p.x()) + " " + formatDouble(p.y()) + " " + formatDouble(p.z()) + "\n";
    const bool hasUvs = mesh.uvs.size() == mesh.faces.size();
    if (hasUvs)
        for (const FaceUvs& uv : mesh.uvs)
            for (const Vec2& t : uv) out += "vt " + formatDouble(t.x()) + " " + formatDouble(t.y()) + "\n";
    const bool parts = mesh.hasParts() && mesh.faceParts.size() == mesh.faces.size();
    for (std::size_t i = 0; i < mesh.faces.size(); ++i) {
        // A named part is an object, opened where its faces begin (cuts append faces to every part); an
        // object's name may have spaces, where a group line would read them as several groups.
        if (parts && (i == 0 || mesh.faceParts[i] != mesh.faceParts[i - 1]))
            out += "o " + mesh.partNames[mesh.faceParts[i]] + "\n";
        out += "f";
        for (int k = 0; k < 3; ++k) {
            out += " " + std::to_string(mesh.faces[i][k] + 1);
            if (hasUvs) out += "/" + std::to_string(3 * i + k + 1);
        }
        out += "\n";
    }
    return out;
}

}  // namespace hapticut::mesh::io
