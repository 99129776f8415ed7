// The thesis's text formats for models and tools (SPEC R21).
#include "hapticut/mesh/io/thesis_format.h"

#include <algorithm>
#include <cstdio>

#include "hapticut/common/line_reader.h"
#include "hapticut/geometry/triangle.h"

namespace hapticut::mesh::io {

namespace {

std::string str(std::uint64_t n) { return std::to_string(n); }

/// Rejects binary data early, with the line of the first offending byte.
void requireText(std::string_view text) {
    int line = 1;
    for (unsigned char c : text) {
        if (c == '\n')
            ++line;
        else if (c == 0 || (c < 32 && c != '\t' && c != '\r' && c != '\f' && c != '\v'))
            throw ParseFailure{line, "not a text file: found binary byte " + std::to_string(c)};
    }
}

/// Reads the next line and requires it to start with `keyword` (e.g. "vertices").
void expectKeyword(LineReader& r, std::string_view keyword, std::string_view context) {
    if (!r.next())
        throw ParseFailure{r.line(),
                           "unexpected end of file, expected '" + std::string(keyword) + "'" + std::string(context)};
    if (r.token(0) != keyword)
        r.fail("expected '" + std::string(keyword) + "'" + std::string(context) + ", found '" +
               std::string(r.token(0)) + "'");
}

/// `keyword N`; refuses counts that the rest of the file cannot hold, so no huge allocation happens.
std::size_t readCount(LineReader& r, std::string_view keyword, std::size_t lines_per_record, std::string_view context) {
    expectKeyword(r, keyword, context);
    r.expectTokens(2, "'" + std::string(keyword) + " <count>'");
    const std::uint64_t n = r.count(1, std::string(keyword) + " count");
    if (n > r.linesLeft() / lines_per_record)
        r.fail(std::string(keyword) + " count " + str(n) + " is larger than the " + str(r.linesLeft()) +
               " lines left in the file could hold");
    if (n >= std::uint64_t{1} << 31) r.fail(std::string(keyword) + " count " + str(n) + " is too large");
    return static_cast<std::size_t>(n);
}

void nextRecord(LineReader& r, std::string_view what, std::size_t index, std::size_t count) {
    if (!r.next())
        throw ParseFailure{r.line(), "unexpected end of file: expected " + std::string(what) + " " + str(index + 1) +
                                         " of " + str(count)};
}

std::uint32_t vertexIndex(const LineReader& r, std::size_t i, std::size_t vertex_count, std::string_view owner) {
    const std::uint64_t v = r.count(i, "a vertex index of " + std::string(owner));
    if (v >= vertex_count)
        r.fail("vertex index " + str(v) + " of " + std::string(owner) + " is out of range: there are " +
               str(vertex_count) + " vertices (indices are 0-based)");
    return static_cast<std::uint32_t>(v);
}

void readGeometry(LineReader& r, SurfaceMesh& mesh, std::vector<Warning>& warnings, const std::filesystem::path& file) {
    const std::size_t nv = readCount(r, "vertices", 1, "");
    mesh.positions.resize(nv);
    for (std::size_t i = 0; i < nv; ++i) {
        nextRecord(r, "vertex", i, nv);
        r.expectTokens(3, "vertex " + str(i) + " as '<x> <y> <z>'");
        mesh.positions[i] = Vec3(r.number(0, "x"), r.number(1, "y"), r.number(2, "z"));
    }

    const std::size_t nf = readCount(r, "faces", 2, " after the vertices");
    mesh.faces.resize(nf);
    mesh.uvs.resize(nf);
    for (std::size_t i = 0; i < nf; ++i) {
        const std::string owner = "face " + str(i);
        nextRecord(r, "face", i, nf);
        r.expectTokens(3, owner + " as 3 vertex indices '<i> <j> <k>'");
        Face& f = mesh.faces[i];
        for (std::size_t k = 0; k < 3; ++k) f[k] = vertexIndex(r, k, nv, owner);
        if (f[0] == f[1] || f[1] == f[2] || f[0] == f[2]) r.fail(owner + " is degenerate: it repeats a vertex index");
        if (geometry::areaNormal(mesh.positions[f[0]], mesh.positions[f[1]], mesh.positions[f[2]]).squaredNorm() == 0)
            r.fail(owner + " is degenerate: its corners are collinear (zero area)");
        nextRecord(r, "texture coordinates of face", i, nf);
        r.expectTokens(6, "texture coordinates of " + owner + " as '<u0> <v0> <u1> <v1> <u2> <v2>'");
        for (std::size_t k = 0; k < 3; ++k) mesh.uvs[i][k] = Vec2(r.number(2 * k, "u"), r.number(2 * k + 1, "v"));
    }

    const std::size_t nn = readCount(r, "normals", 1, " after the faces");
    if (nn != nf)
        r.fail("normals count " + str(nn) + " differs from the faces count " + str(nf) + " (one normal per face)");
    mesh.normals.resize(nn);
    for (std::size_t i = 0; i < nn; ++i) {
        nextRecord(r, "normal", i, nn);
        r.expectTokens(3, "normal " + str(i) + " as '<nx> <ny> <nz>'");
        mesh.normals[i] = Vec3(r.number(0, "nx"), r.number(1, "ny"), r.number(2, "nz"));
    }

    const std::size_t ne = readCount(r, "edges", 1, " after the normals");
    mesh.edges.resize(ne);
    std::vector<Edge> sorted(ne);
    std::vector<int> lineOf(ne);
    for (std::size_t i = 0; i < ne; ++i) {
        const std::string owner = "edge " + str(i);
        nextRecord(r, "edge", i, ne);
        r.expectTokens(2, owner + " as '<i> <j>'");
        const std::uint32_t a = vertexIndex(r, 0, nv, owner), b = vertexIndex(r, 1, nv, owner);
        if (a == b) r.fail(owner + " joins vertex " + str(a) + " to itself");
        mesh.edges[i] = {a, b};
        sorted[i] = {std::min(a, b), std::max(a, b)};
        lineOf[i] = r.line();
    }
    if (r.next()) r.fail("unexpected content after the last edge: '" + std::string(r.token(0)) + "'");

    // The edges are the structural springs; a duplicate would double a spring, so it is an error.
    std::vector<std::size_t> order(ne);
    for (std::size_t i = 0; i < ne; ++i) order[i] = i;
    std::sort(order.begin(), order.end(),
              [&](std::size_t x, std::size_t y) { return sorted[x] < sorted[y] || (sorted[x] == sorted[y] && x < y); });
    for (std::size_t i = 1; i < ne; ++i)
        if (sorted[order[i]] == sorted[order[i - 1]])
            throw ParseFailure{lineOf[order[i]], "edge " + str(order[i]) + " (" + str(sorted[order[i]][0]) + ", " +
                                                     str(sorted[order[i]][1]) + ") repeats edge " + str(order[i - 1])};

    // Disagreement with the faces is legal but worth saying: springs then do not match the surface.
    const std::vector<Edge> faceEdges = edgesOfFaces(mesh.faces);
    std::sort(sorted.begin(), sorted.end());
    std::size_t extra = 0, missing = 0;
    std::string firstExtra, firstMissing;
    for (const Edge& e : sorted)
        if (!std::binary_search(faceEdges.begin(), faceEdges.end(), e) && extra++ == 0)
            firstExtra = "(" + str(e[0]) + ", " + str(e[1]) + ")";
    for (const Edge& e : faceEdges)
        if (!std::binary_search(sorted.begin(), sorted.end(), e) && missing++ == 0)
            firstMissing = "(" + str(e[0]) + ", " + str(e[1]) + ")";
    if (extra > 0)
        warnings.push_back({file, 0,
                            "edges block lists " + str(extra) + " edge(s) that no face has, first " + firstExtra +
                                "; they stay as springs"});
    if (missing > 0)
        warnings.push_back({file, 0,
                            "edges block lacks " + str(missing) + " of the faces' " + str(faceEdges.size()) +
                                " edges, first " + firstMissing + "; those edges get no spring"});
}

template <class Parse>
auto guarded(const std::filesystem::path& file, Parse&& parse) -> decltype(parse()) {
    try {
        return parse();
    } catch (const ParseFailure& failure) {
        return unexpected(Error{file, failure.line, failure.message});
    } catch (const std::bad_alloc&) {
        return unexpected(Error{file, 0, "out of memory while reading"});
    }
}

void appendMesh(std::string& out, const SurfaceMesh& mesh) {
    out += "vertices " + str(mesh.positions.size()) + "\n";
    for (const Vec3& p : mesh.positions)
        out += formatDouble(p.x()) + " " + formatDouble(p.y()) + " " + formatDouble(p.z()) + "\n";
    out += "faces " + str(mesh.faces.size()) + "\n";
    for (std::size_t i = 0; i < mesh.faces.size(); ++i) {
        const Face& f = mesh.faces[i];
        out += str(f[0]) + " " + str(f[1]) + " " + str(f[2]) + "\n";
        const FaceUvs& uv = mesh.uvs[i];
        out += formatDouble(uv[0].x()) + " " + formatDouble(uv[0].y()) + " " + formatDouble(uv[1].x()) + " " +
               formatDouble(uv[1].y()) + " " + formatDouble(uv[2].x()) + " " + formatDouble(uv[2].y()) + "\n";
    }
    out += "normals " + str(mesh.normals.size()) + "\n";
    for (const Vec3& n : mesh.normals)
        out += formatDouble(n.x()) + " " + formatDouble(n.y()) + " " + formatDouble(n.z()) + "\n";
    out += "edges " + str(mesh.edges.size()) + "\n";
    for (const Edge& e : mesh.edges) out += str(e[0]) + " " + str(e[1]) + "\n";
}

SurfaceMesh completed(SurfaceMesh mesh) {
    completeMesh(mesh);
    return mesh;
}

}  // namespace

Result<ModelFile, Error> parseModel(std::string_view text, const std::filesystem::path& file) {
    return guarded(file, [&]() -> Result<ModelFile, Error> {
        requireText(text);
        LineReader r(text);
        ModelFile model;
        if (!r.next()) throw ParseFailure{0, "file is empty, expected a model starting with 'physics'"};
        if (r.token(0) != "physics")
            r.fail("expected 'physics' at the start of a model file, found '" + std::string(r.token(0)) + "'" +
                   (r.token(0) == "threshold" ? " (this looks like a tool file)" : ""));
        if (r.tokens().size() == 1 && !r.next()) throw ParseFailure{r.line(), "unexpected end of file after 'physics'"};
        const std::size_t first = r.tokens().size() == 6 && r.token(0) == "physics" ? 1 : 0;
        r.expectTokens(first + 5, "physics values '<mass> <k_s> <k_d> <k_s positioning> <k_d positioning>'");
        ThesisPhysics& p = model.physics;
        p.mass = r.number(first + 0, "mass");
        p.structuralStiffness = r.number(first + 1, "structural k_s");
        p.structuralDamping = r.number(first + 2, "structural k_d");
        p.positioningStiffness = r.number(first + 3, "positioning k_s");
        p.positioningDamping = r.number(first + 4, "positioning k_d");
        if (p.mass <= 0) r.fail("mass must be positive, found " + formatDouble(p.mass));
        if (p.structuralStiffness < 0 || p.structuralDamping < 0 || p.positioningStiffness < 0 ||
            p.positioningDamping < 0)
            r.fail("spring constants must not be negative");
        readGeometry(r, model.mesh, model.warnings, file);
        return model;
    });
}

Result<ToolFile, Error> parseTool(std::string_view text, const std::filesystem::path& file) {
    return guarded(file, [&]() -> Result<ToolFile, Error> {
        requireText(text);
        LineReader r(text);
        ToolFile tool;
        if (!r.next()) throw ParseFailure{0, "file is empty, expected a tool starting with 'threshold <value>'"};
        if (r.token(0) != "threshold")
            r.fail("expected 'threshold <value>' at the start of a tool file, found '" + std::string(r.token(0)) + "'" +
                   (r.token(0) == "physics" ? " (this looks like a model file)" : ""));
        r.expectTokens(2, "'threshold <value>'");
        tool.threshold_N = r.number(1, "the threshold");
        if (tool.threshold_N < 0) r.fail("threshold must not be negative, found " + formatDouble(tool.threshold_N));
        readGeometry(r, tool.mesh, tool.warnings, file);
        return tool;
    });
}

Result<ModelFile, Error> readModelFile(const std::filesystem::path& file) {
    const auto text = readTextFile(file);
    if (!text) return unexpected(text.error());
    return parseModel(*text, file);
}

Result<ToolFile, Error> readToolFile(const std::filesystem::path& file) {
    const auto text = readTextFile(file);
    if (!text) return unexpected(text.error());
    return parseTool(*text, file);
}

std::string formatModel(const SurfaceMesh& mesh, const ThesisPhysics& p) {
    std::string out = "physics\n" + formatDouble(p.mass) + " " + formatDouble(p.structuralStiffness) + " " +
                      formatDouble(p.structuralDamping) + " " + formatDouble(p.positioningStiffness) + " " +
                      formatDouble(p.positioningDamping) + "\n";
    appendMesh(out, completed(mesh));
    return out;
}

std::string formatTool(const SurfaceMesh& mesh, double threshold_N) {
    std::string out = "threshold " + formatDouble(threshold_N) + "\n";
    appendMesh(out, completed(mesh));
    return out;
}

WriteStatus writeModelFile(const std::filesystem::path& file, const SurfaceMesh& mesh, const ThesisPhysics& physics) {
    return writeTextFileAtomically(file, formatModel(mesh, physics));
}

WriteStatus writeToolFile(const std::filesystem::path& file, const SurfaceMesh& mesh, double threshold_N) {
    return writeTextFileAtomically(file, formatTool(mesh, threshold_N));
}

}  // namespace hapticut::mesh::io
