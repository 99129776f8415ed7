// Stanford PLY reader (ASCII, binary little and big endian) and ASCII writer.
#include "hapticut/mesh/io/ply_format.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>

#include "hapticut/common/line_reader.h"

namespace hapticut::mesh::io {

namespace {

enum class Format { Ascii, BinaryLittle, BinaryBig };

struct Property {
    std::string name;
    std::string type;       // scalar type, or the item type of a list
    std::string countType;  // non-empty for list properties
};

struct Element {
    std::string name;
    std::size_t count = 0;
    std::vector<Property> properties;
};

std::size_t typeSize(std::string_view t) {
    if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
    if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
    if (t == "int" || t == "uint" || t == "int32" || t == "uint32" || t == "float" || t == "float32") return 4;
    if (t == "double" || t == "float64") return 8;
    return 0;
}

/// Reads values of one element's properties from ASCII tokens or binary bytes.
class ValueSource {
public:
    ValueSource(std::string_view body, Format format, int header_lines)
        : body_(body), format_(format), lines_(body), line_(header_lines) {}

    // ASCII: one element per line.
    void beginElement(std::string_view what) {
        if (format_ != Format::Ascii) return;
        if (!lines_.next())
            throw ParseFailure{line_ + lines_.line(), "unexpected end of file: expected " + std::string(what)};
        token_ = 0;
    }
    double read(std::string_view type, std::string_view what) {
        if (format_ == Format::Ascii) {
            if (token_ >= lines_.tokens().size())
                throw ParseFailure{line_ + lines_.line(), "too few values on this line: missing " + std::string(what)};
            double v = 0;
            if (!parseFiniteDouble(lines_.token(token_), v))
                throw ParseFailure{line_ + lines_.line(), "expected a finite number for " + std::string(what) +
                                                              ", found '" + std::string(lines_.token(token_)) + "'"};
            ++token_;
            return v;
        }
        const std::size_t n = typeSize(type);
        if (pos_ + n > body_.size())
            throw ParseFailure{0, "unexpected end of binary data while reading " + std::string(what)};
        unsigned char b[8];
        std::memcpy(b, body_.data() + pos_, n);
        pos_ += n;
        const bool swap = (format_ == Format::BinaryBig) == (std::endian::native == std::endian::little);
        if (swap) std::reverse(b, b + n);
        auto as = [&]<class T>(T) {
            T v;
            std::memcpy(&v, b, sizeof v);
            return static_cast<double>(v);
        };
        double v = 0;
        if (type == "char" || type == "int8")
            v = as(std::int8_t{});
        else if (type == "uchar" || type == "uint8")
            v = as(std::uint8_t{});
        else if (type == "short" || type == "int16")
            v = as(std::int16_t{});
        else if (type == "ushort" || type == "uint16")
            v = as(std::uint16_t{});
        else if (type == "int" || type == "int32")
            v = as(std::int32_t{});
        else if (type == "uint" || type == "uint32")
            v = as(std::uint32_t{});
        else if (type == "float" || type == "float32")
            v = as(float{});
        else
            v = as(double{});
        if (!std::isfinite(v)) throw ParseFailure{0, "non-finite value for " + std::string(what) + " in binary data"};
        return v;
    }
    void endElement() {
        if (format_ == Format::Ascii && token_ != lines_.tokens().size())
            throw ParseFailure{line_ + lines_.line(), "expected " + std::to_string(token_) +
                                                          " values on this line, found " +
                                                          std::to_string(lines_.tokens().size())};
    }
    int line() const { return format_ == Format::Ascii ? line_ + lines_.line() : 0; }

private:
    std::string_view body_;
    Format format_;
    LineReader lines_;
    int line_;
    std::size_t pos_ = 0, token_ = 0;
};

std::uint32_t asIndex(double v, std::size_t vertex_count, int line) {
    if (v < 0 || v != std::floor(v) || v >= static_cast<double>(vertex_count))
        throw ParseFailure{line, "vertex index " + formatDouble(v) + " is out of range: there are " +
                                     std::to_string(vertex_count) + " vertices"};
    return static_cast<std::uint32_t>(v);
}

}  // namespace

Result<ImportedMesh, Error> parsePly(std::string_view bytes, const std::filesystem::path& file) {
    try {
        const std::size_t headerEnd = bytes.find("end_header");
        if (bytes.substr(0, 3) != "ply") throw ParseFailure{1, "expected 'ply' as the first line"};
        if (headerEnd == std::string_view::npos) throw ParseFailure{0, "no 'end_header' line found"};
        std::size_t bodyStart = bytes.find('\n', headerEnd);
        bodyStart = bodyStart == std::string_view::npos ? bytes.size() : bodyStart + 1;

        LineReader header(bytes.substr(0, bodyStart));
        Format format = Format::Ascii;
        std::vector<Element> elements;
        bool sawFormat = false;
        header.next();  // "ply"
        while (header.next()) {
            const std::string_view key = header.token(0);
            if (key == "format") {
                header.expectTokens(3, "'format <ascii|binary_little_endian|binary_big_endian> 1.0'");
                const std::string_view f = header.token(1);
                if (f == "ascii")
                    format = Format::Ascii;
                else if (f == "binary_little_endian")
                    format = Format::BinaryLittle;
                else if (f == "binary_big_endian")
                    format = Format::BinaryBig;
                else
                    header.fail("unknown PLY format '" + std::string(f) + "'");
                sawFormat = true;
            } else if (key == "element") {
                header.expectTokens(3, "'element <name> <count>'");
                const std::uint64_t n = header.count(2, "element count");
                // Every element takes at least one byte in any format: a larger count is a lie.
                if (n > bytes.size() - bodyStart)
                    header.fail("element count " + std::to_string(n) + " is larger than the file could hold");
                elements.push_back({std::string(header.token(1)), static_cast<std::size_t>(n), {}});
            } else if (key == "property") {
                if (elements.empty()) header.fail("'property' before any 'element'");
                if (header.tokens().size() == 5 && header.token(1) == "list") {
                    if (typeSize(header.token(2)) == 0 || typeSize(header.token(3)) == 0)
                        header.fail("unknown type in list property");
                    elements.back().properties.push_back(
                        {std::string(header.token(4)), std::string(header.token(3)), std::string(header.token(2))});
                } else {
                    header.expectTokens(3, "'property <type> <name>'");
                    if (typeSize(header.token(1)) == 0)
                        header.fail("unknown property type '" + std::string(header.token(1)) + "'");
                    elements.back().properties.push_back(
                        {std::string(header.token(2)), std::string(header.token(1)), ""});
                }
            } else if (key == "end_header") {
                break;
            } else if (key != "comment" && key != "obj_info") {
                header.fail("unexpected header line '" + std::string(key) + "'");
            }
        }
        if (!sawFormat) throw ParseFailure{0, "no 'format' line in the header"};
        for (const Element& el : elements) {
            if (el.name != "face") continue;
            bool hasIndices = false;
            for (const Property& p : el.properties)
                hasIndices |= !p.countType.empty() && (p.name == "vertex_indices" || p.name == "vertex_index");
            if (!hasIndices) throw ParseFailure{0, "the face element needs a list property 'vertex_indices'"};
        }

        ImportedMeshBuilder out;
        SurfaceMesh& m = out.mesh();
        ValueSource src(bytes.substr(bodyStart), format, header.line());
        for (const Element& el : elements) {
            const bool isVertex = el.name == "vertex", isFace = el.name == "face";
            if (isVertex) {
                bool hasX = false, hasY = false, hasZ = false;
                for (const Property& p : el.properties)
                    hasX |= p.name == "x", hasY |= p.name == "y", hasZ |= p.name == "z";
                if (!hasX || !hasY || !hasZ) throw ParseFailure{0, "the vertex element needs x, y and z properties"};
                m.positions.reserve(el.count);
            }
            for (std::size_t i = 0; i < el.count; ++i) {
                src.beginElement(el.name + " " + std::to_string(i));
                Vec3 p = Vec3::Zero();
                Face f{};
                FaceUvs uv{Vec2::Zero(), Vec2::Zero(), Vec2::Zero()};
                for (const Property& prop : el.properties) {
                    if (prop.countType.empty()) {
                        const double v = src.read(prop.type, prop.name);
                        if (isVertex && prop.name == "x") p.x() = v;
                        if (isVertex && prop.name == "y") p.y() = v;
                        if (isVertex && prop.name == "z") p.z() = v;
                        continue;
                    }
                    const double n = src.read(prop.countType, prop.name + " count");
                    if (n < 0 || n > 1024)
                        throw ParseFailure{src.line(),
                                           "list length " + formatDouble(n) + " for " + prop.name + " is out of range"};
                    const auto len = static_cast<std::size_t>(n);
                    const bool indices = isFace && (prop.name == "vertex_indices" || prop.name == "vertex_index");
                    if (indices && len != 3)
                        throw ParseFailure{src.line(), "face " + std::to_string(i) + " has " + std::to_string(len) +
                                                           " corners; only triangles are read from PLY"};
                    if (isFace && prop.name == "texcoord" && len != 6)
                        throw ParseFailure{src.line(), "texcoord of face " + std::to_string(i) +
                                                           " needs 6 values, found " + std::to_string(len)};
                    for (std::size_t k = 0; k < len; ++k) {
                        const double v = src.read(prop.type, prop.name);
                        if (indices) f[k] = asIndex(v, m.positions.size(), src.line());
                        if (isFace && prop.name == "texcoord") uv[k / 2][static_cast<Eigen::Index>(k % 2)] = v;
                    }
                }
                src.endElement();
                if (isVertex) m.positions.push_back(p);
                if (isFace) out.addFace(f, uv);
            }
        }
        return out.finish(file, "a 'face' element with vertex_indices");
    } catch (const ParseFailure& failure) {
        return unexpected(Error{file, failure.line, failure.message});
    }
}

std::string formatPly(const SurfaceMesh& mesh) {
    const bool hasUvs = mesh.uvs.size() == mesh.faces.size();
    std::string out = "ply\nformat ascii 1.0\ncomment Hapticut mesh\nelement vertex " +
                      std::to_string(mesh.positions.size()) +
                      "\nproperty double x\nproperty double y\nproperty double z\nelement face " +
                      std::to_string(mesh.faces.size()) + "\nproperty list uchar int vertex_indices\n" +
                      (hasUvs ? "property list uchar double texcoord\n" : "") + "end_header\n";
    for (const Vec3& p : mesh.positions)
        out += formatDouble(p.x()) + " " + formatDouble(p.y()) + " " + formatDouble(p.z()) + "\n";
    for (std::size_t i = 0; i < mesh.faces.size(); ++i) {
        const Face& f = mesh.faces[i];
        out += "3 " + std::to_string(f[0]) + " " + std::to_string(f[1]) + " " + std::to_string(f[2]);
        if (hasUvs) {
            out += " 6";
            for (const Vec2& t : mesh.uvs[i]) out += " " + formatDouble(t.x()) + " " + formatDouble(t.y());
        }
        out += "\n";
    }
    return out;
}

}  // namespace hapticut::mesh::io
