// The thesis model and tool formats: lossless round trips, and a clear file:line error for every
// kind of malformed input.
#include <gtest/gtest.h>

#include <clocale>
#include <filesystem>
#include <fstream>
#include <locale>
#include <sstream>

#include "hapticut/mesh/io/thesis_format.h"
#include "hapticut/mesh/procedural/heart.h"
#include "hapticut/mesh/procedural/tools.h"
#include "test_support.h"

namespace hapticut::mesh::io {
namespace {

const ThesisPhysics kThesisHeart{
    .mass = 200, .structuralStiffness = 20, .structuralDamping = 2, .positioningStiffness = 5, .positioningDamping = 1};

// Lines of the tetrahedron model: 1 physics, 2 values, 3 "vertices 4", 4-7 vertices, 8 "faces 4",
// 9-16 faces and their UVs, 17 "normals 4", 18-21 normals, 22 "edges 6", 23-28 edges.
std::string tetraText() { return formatModel(test::tetrahedron(), kThesisHeart); }

std::string replaceLine(const std::string& text, int line, const std::string& replacement) {
    std::istringstream in(text);
    std::string out, l;
    for (int i = 1; std::getline(in, l); ++i) out += (i == line ? replacement : l) + "\n";
    return out;
}

std::string firstLines(const std::string& text, int lines) {
    std::istringstream in(text);
    std::string out, l;
    for (int i = 0; i < lines && std::getline(in, l); ++i) out += l + "\n";
    return out;
}

void expectError(const std::string& text, int line, const std::string& fragment) {
    const auto r = parseModel(text, "organ.txt");
    test::expectError(r, line, fragment);
    if (!r.has_value()) {
        EXPECT_EQ(r.error().file, "organ.txt");
    }
}

bool sameMesh(const SurfaceMesh& a, const SurfaceMesh& b) {
    return a.positions == b.positions && a.faces == b.faces && a.uvs == b.uvs && a.normals == b.normals &&
           a.edges == b.edges;
}

TEST(ThesisFormat, ModelRoundTripIsBitExact) {
    const SurfaceMesh heart = procedural::makeHeart({});
    const ThesisPhysics physics{.mass = 0.3,
                                .structuralStiffness = 1.0 / 3,
                                .structuralDamping = 0.1,
                                .positioningStiffness = 2e-7,
                                .positioningDamping = 1e300};
    const std::string text = formatModel(heart, physics);
    const auto parsed = parseModel(text, "heart.txt");
    ASSERT_TRUE(parsed.has_value()) << parsed.error().toString();
    EXPECT_TRUE(sameMesh(parsed->mesh, heart));
    EXPECT_EQ(parsed->physics.structuralStiffness, 1.0 / 3);
    EXPECT_EQ(parsed->physics.positioningDamping, 1e300);
    EXPECT_TRUE(parsed->warnings.empty());
    EXPECT_EQ(formatModel(parsed->mesh, parsed->physics), text);
}

TEST(ThesisFormat, ToolRoundTripKeepsTheThreshold) {
    const SurfaceMesh scalpel = procedural::makeScalpel();
    const auto parsed = parseTool(formatTool(scalpel, 2.5), "scalpel.txt");
    ASSERT_TRUE(parsed.has_value()) << parsed.error().toString();
    EXPECT_EQ(parsed->threshold_N, 2.5);
    EXPECT_TRUE(sameMesh(parsed->mesh, scalpel));
}

TEST(ThesisFormat, ReadsTheThesisLayoutWithCommentsBlankLinesAndCrLf) {
    std::string text = tetraText();
    std::string crlf;
    for (char c : text) crlf += c == '\n' ? std::string("\r\n") : std::string(1, c);
    const auto parsed = parseModel("# exported by hand\n\n" + crlf, "organ.txt");
    ASSERT_TRUE(parsed.has_value()) << parsed.error().toString();
    EXPECT_EQ(parsed->physics.mass, 200);
    EXPECT_EQ(parsed->mesh.faces.size(), 4u);
    EXPECT_EQ(parsed->mesh.edges.size(), 6u);
}

TEST(ThesisFormat, PhysicsValuesMayShareTheKeywordLine) {
    const auto parsed =
        parseModel(replaceLine(replaceLine(tetraText(), 1, "physics 200 20 2 5 1"), 2, "# moved up"), "organ.txt");
    ASSERT_TRUE(parsed.has_value()) << parsed.error().toString();
    EXPECT_EQ(parsed->physics.positioningDamping, 1);
}

TEST(ThesisFormat, NumbersIgnoreTheUsersLocale) {
    // A comma-decimal locale must not change how "0.5" reads. Try the C library locale when the
    // machine has one, and always a C++ global locale whose decimal point is a comma.
    struct Comma : std::numpunct<char> {
        char do_decimal_point() const override { return ','; }
    };
    const std::locale previous = std::locale::global(std::locale(std::locale::classic(), new Comma));
    const std::string saved = std::setlocale(LC_NUMERIC, nullptr);
    for (const char* name : {"de_DE.UTF-8", "de_DE.utf8", "fr_FR.UTF-8", "nb_NO.UTF-8"})
        if (std::setlocale(LC_NUMERIC, name)) break;
    const auto parsed = parseModel(replaceLine(tetraText(), 2, "0.5 20.25 2 5 1"), "organ.txt");
    const std::string written = formatModel(test::tetrahedron(), {.mass = 0.5, .structuralStiffness = 20.25});
    std::setlocale(LC_NUMERIC, saved.c_str());
    std::locale::global(previous);
    ASSERT_TRUE(parsed.has_value()) << parsed.error().toString();
    EXPECT_EQ(parsed->physics.mass, 0.5);
    EXPECT_EQ(parsed->physics.structuralStiffness, 20.25);
    EXPECT_NE(written.find("0.5 20.25 0 0 0"), std::string::npos);
}

TEST(ThesisFormat, WarnsWhenEdgesDisagreeWithFaces) {
    std::string text = replaceLine(tetraText(), 28, "");  // drop one face edge
    text = replaceLine(text, 22, "edges 5");
    auto parsed = parseModel(text, "organ.txt");
    ASSERT_TRUE(parsed.has_value()) << parsed.error().toString();
    ASSERT_EQ(parsed->warnings.size(), 1u);
    EXPECT_NE(parsed->warnings[0].message.find("lacks 1 of the faces' 6 edges"), std::string::npos)
        << parsed->warnings[0].message;
}

// One test per class of malformed input, each asserting the line and what was expected.
TEST(ThesisFormatErrors, EmptyFile) {
    expectError("", 0, "file is empty");
    expectError("\n\n   \n", 0, "file is empty");
}
TEST(ThesisFormatErrors, MissingOrMisspelledKeyword) {
    expectError(replaceLine(tetraText(), 1, "physic"), 1, "expected 'physics'");
    expectError(replaceLine(tetraText(), 3, "vertexes 4"), 3, "expected 'vertices'");
    expectError(replaceLine(tetraText(), 8, "face 4"), 8, "expected 'faces' after the vertices");
    expectError(replaceLine(tetraText(), 17, "edges 4"), 17, "expected 'normals' after the faces");
}
TEST(ThesisFormatErrors, WrongValueCountOnALine) {
    expectError(replaceLine(tetraText(), 2, "200 20 2 5"), 2, "expected physics values");
    expectError(replaceLine(tetraText(), 5, "1 -1"), 5,
                "expected vertex 1 as '<x> <y> <z>' (3 values), found 2 values");
    expectError(replaceLine(tetraText(), 11, "0 3 1 2"), 11, "face 1 as 3 vertex indices");
    expectError(replaceLine(tetraText(), 12, "0 0 1 0 0"), 12, "texture coordinates of face 1");
    expectError(replaceLine(tetraText(), 24, "0 1 2"), 24, "expected edge 1 as '<i> <j>'");
}
TEST(ThesisFormatErrors, CountsThatDisagreeWithTheRecords) {
    expectError(replaceLine(tetraText(), 3, "vertices 5"), 8,
                "expected vertex 4 as '<x> <y> <z>' (3 values), found 2 values: 'faces 4'");
    expectError(replaceLine(tetraText(), 3, "vertices 3"), 7, "expected 'faces' after the vertices, found '-1'");
    expectError(replaceLine(tetraText(), 17, "normals 3"), 17, "normals count 3 differs from the faces count 4");
    expectError(replaceLine(tetraText(), 22, "edges 5"), 28, "unexpected content after the last edge");
}
TEST(ThesisFormatErrors, NotANumber) {
    expectError(replaceLine(tetraText(), 4, "1 one 1"), 4, "expected a finite number for y, found 'one'");
    expectError(replaceLine(tetraText(), 4, "1 1,5 1"), 4, "found '1,5'");
    expectError(replaceLine(tetraText(), 9, "0 1 2.5"), 9, "expected a non-negative whole number");
    expectError(replaceLine(tetraText(), 9, "0 -1 2"), 9, "expected a non-negative whole number");
    expectError(replaceLine(tetraText(), 3, "vertices four"), 3,
                "expected a non-negative whole number for vertices count");
}
TEST(ThesisFormatErrors, NanAndInfinity) {
    expectError(replaceLine(tetraText(), 2, "nan 20 2 5 1"), 2, "expected a finite number for mass, found 'nan'");
    expectError(replaceLine(tetraText(), 6, "inf 1 -1"), 6, "found 'inf'");
    expectError(replaceLine(tetraText(), 19, "0 1e999 0"), 19, "found '1e999'");
}
TEST(ThesisFormatErrors, IndexOutOfRange) {
    expectError(replaceLine(tetraText(), 13, "0 2 4"), 13,
                "vertex index 4 of face 2 is out of range: there are 4 vertices");
    expectError(replaceLine(tetraText(), 23, "0 99"), 23, "vertex index 99 of edge 0 is out of range");
    expectError(replaceLine(tetraText(), 9, "0 1 18446744073709551616"), 9, "expected a non-negative whole number");
}
TEST(ThesisFormatErrors, DegenerateFacesAndEdges) {
    expectError(replaceLine(tetraText(), 9, "0 1 1"), 9, "face 0 is degenerate: it repeats a vertex index");
    std::string collinear = replaceLine(tetraText(), 6, "3 3 3");  // vertex 2 on the line through 0 and 1... at (3,3,3)
    collinear = replaceLine(collinear, 5, "2 2 2");
    expectError(collinear, 9, "face 0 is degenerate: its corners are collinear");
    expectError(replaceLine(tetraText(), 25, "3 3"), 25, "edge 2 joins vertex 3 to itself");
    expectError(replaceLine(tetraText(), 26, "1 0"), 26, "edge 3 (0, 1) repeats edge 0");
}
TEST(ThesisFormatErrors, TruncatedFile) {
    // A count the rest of the file cannot hold is caught at the count's own line.
    expectError(firstLines(tetraText(), 14), 8, "faces count 4 is larger than the 7 lines left in the file could hold");
    // With enough (comment) lines after the cut, the reader meets the end where the record should be.
    expectError(firstLines(tetraText(), 14) + "#\n#\n#\n", 17, "unexpected end of file: expected face 4 of 4");
    expectError(firstLines(tetraText(), 15) + "#\n#\n#\n", 18,
                "unexpected end of file: expected texture coordinates of face 4 of 4");
    expectError(firstLines(tetraText(), 21), 21, "unexpected end of file, expected 'edges'");
    expectError(firstLines(tetraText(), 1), 1, "unexpected end of file after 'physics'");
    std::string cut = tetraText();
    expectError(cut.substr(0, cut.find("0 1 2\n") + 3), 8, "faces count 4 is larger than the 1 lines left");
    expectError(cut.substr(0, cut.find("0 1 2\n") + 3) + "\n#\n#\n#\n#\n#\n#\n#\n", 9,
                "expected face 0 as 3 vertex indices");
}
TEST(ThesisFormatErrors, BinaryGarbage) {
    std::string garbage = "physics\n";
    for (int i = 0; i < 64; ++i) garbage += static_cast<char>((i * 37) % 256);
    expectError(garbage, 2, "not a text file");
    expectError(std::string("\x7f"
                            "ELF\x02\x01\x01\0\0",
                            9),
                1, "not a text file");
}
TEST(ThesisFormatErrors, HugeCountsFailWithoutAllocating) {
    expectError(replaceLine(tetraText(), 3, "vertices 4000000000"), 3, "is larger than the 26 lines left");
    expectError(replaceLine(tetraText(), 8, "faces 99999999999999"), 8, "faces count 99999999999999 is larger");
    expectError(replaceLine(tetraText(), 22, "edges 18446744073709551615"), 22,
                "edges count 18446744073709551615 is larger");
}
TEST(ThesisFormatErrors, NegativeOrImpossiblePhysics) {
    expectError(replaceLine(tetraText(), 2, "0 20 2 5 1"), 2, "mass must be positive");
    expectError(replaceLine(tetraText(), 2, "1 -20 2 5 1"), 2, "must not be negative");
}
TEST(ThesisFormatErrors, ToolAndModelAreToldApart) {
    expectError(formatTool(test::tetrahedron(), 4), 1, "this looks like a tool file");
    const auto tool = parseTool(tetraText(), "scalpel.txt");
    ASSERT_FALSE(tool.has_value());
    EXPECT_NE(tool.error().message.find("this looks like a model file"), std::string::npos);
    const auto negative = parseTool(replaceLine(formatTool(test::tetrahedron(), 4), 1, "threshold -1"), "scalpel.txt");
    ASSERT_FALSE(negative.has_value());
    EXPECT_EQ(negative.error().line, 1);
}
TEST(ThesisFormatErrors, VeryLongLine) {
    expectError(replaceLine(tetraText(), 4, std::string(100'000, '1')), 4, "line is longer than");
}
TEST(ThesisFormatErrors, MissingFileAndDirectory) {
    const auto missing = readModelFile("/nonexistent/heart.txt");
    ASSERT_FALSE(missing.has_value());
    EXPECT_NE(missing.error().message.find("cannot open"), std::string::npos);
    const auto dir = readModelFile(std::filesystem::temp_directory_path());
    ASSERT_FALSE(dir.has_value());
    EXPECT_NE(dir.error().message.find("is a directory"), std::string::npos);
}

TEST(ThesisFormat, FailedWriteKeepsTheExistingFile) {
    const test::ScratchDir dir;
    const auto file = dir / "heart.txt";
    ASSERT_FALSE(writeModelFile(file, test::tetrahedron(), kThesisHeart).has_value());
    const auto before = readModelFile(file);
    ASSERT_TRUE(before.has_value());
    // A directory where the temporary file would go makes the write fail before the rename.
    std::filesystem::create_directories(dir / "heart.txt.tmp-hapticut");
    const auto error = writeModelFile(file, procedural::makeHeart({}), kThesisHeart);
    EXPECT_TRUE(error.has_value());
    const auto after = readModelFile(file);
    ASSERT_TRUE(after.has_value());
    EXPECT_EQ(after->mesh.faces.size(), 4u);
}

}  // namespace
}  // namespace hapticut::mesh::io
