#include "mesh/MeshReaders.h"

#include <algorithm>
#include <bit>
#include <cfloat>
#include <cmath>
#include <cstring>
#include <map>

#include "base/Error.h"
#include "mesh/MeshText.h"

namespace sightline::meshio {

namespace {

struct PlyTypeInfo {
    const char* name;
    std::size_t size;
    double min, max;
    bool real;
};
constexpr PlyTypeInfo kPlyTypes[] = {
    {"char", 1, -128.0, 127.0, false},        {"uchar", 1, 0.0, 255.0, false},
    {"short", 2, -32768.0, 32767.0, false},   {"ushort", 2, 0.0, 65535.0, false},
    {"int", 4, -2147483648.0, 2147483647.0, false}, {"uint", 4, 0.0, 4294967295.0, false},
    {"float", 4, -FLT_MAX, FLT_MAX, true},    {"double", 8, -DBL_MAX, DBL_MAX, true}};

/// Index into kPlyTypes of the type named `name` (both spellings of the spec); -1 if unknown.
int plyType(const std::string& name)
{
    static const std::map<std::string, int> types = {
        {"char", 0},  {"int8", 0},  {"uchar", 1}, {"uint8", 1},   {"short", 2}, {"int16", 2},
        {"ushort", 3}, {"uint16", 3}, {"int", 4},  {"int32", 4},   {"uint", 5},  {"uint32", 5},
        {"float", 6}, {"float32", 6}, {"double", 7}, {"float64", 7}};
    const auto it = types.find(name);
    return it == types.end() ? -1 : it->second;
}

enum class PlyRole { None, X, Y, Z, Corners };

struct PlyProperty {
    std::string name;
    int type = 0;       ///< of the value, or of a list's items
    int countType = -1; ///< of a list's count; -1 for a scalar
    PlyRole role = PlyRole::None;
};

struct PlyElement {
    std::string name;
    unsigned long long count = 0;
    std::vector<PlyProperty> properties;
};

struct PlyHeader {
    std::string format;
    std::vector<PlyElement> elements;
    std::size_t bodyOffset = 0; ///< bytes
    std::size_t lines = 0;      ///< header lines, end_header included
};

/// At most the first `most` tokens of a header line (a hostile one may be very long).
std::vector<std::string> headerTokens(std::string_view line, std::size_t most = 6)
{
    std::vector<std::string> out;
    Tokens t(line);
    for (std::string_view token; out.size() < most && t.next(token);)
        out.emplace_back(token);
    return out;
}

/// What the reader needs from the elements: x, y, z of "vertex" and the index list of "face".
void assignPlyRoles(PlyHeader& h, const std::string& what)
{
    for (PlyElement& e : h.elements) {
        if (e.count > 0 && e.properties.empty())
            throw Error(what + ": PLY element '" + e.name + "' has no properties");
        if (e.name == "tristrips")
            throw Error(what + ": PLY triangle strips ('tristrips') are not supported; save the mesh with faces");
        for (PlyProperty& p : e.properties) {
            if (e.name == "vertex" && p.countType < 0)
                p.role = p.name == "x" ? PlyRole::X : p.name == "y" ? PlyRole::Y : p.name == "z" ? PlyRole::Z : PlyRole::None;
            if (e.name == "face" && p.countType >= 0 && (p.name == "vertex_indices" || p.name == "vertex_index")) {
                if (kPlyTypes[p.type].real)
                    throw Error(what + ": PLY face vertex indices must be integers, not " + kPlyTypes[p.type].name);
                p.role = PlyRole::Corners;
            }
        }
        const auto has = [&](PlyRole r) {
            return std::any_of(e.properties.begin(), e.properties.end(), [&](const PlyProperty& p) { return p.role == r; });
        };
        if (e.name == "vertex" && !(has(PlyRole::X) && has(PlyRole::Y) && has(PlyRole::Z)))
            throw Error(what + ": PLY vertex element has no x, y and z properties");
        if (e.name == "face" && !has(PlyRole::Corners))
            throw Error(what + ": PLY face element has no vertex_indices list");
    }
}

/// The header, validated strictly: OpenMesh's reader crashed or hung on malformed ones.
PlyHeader plyHeader(std::string_view text, const std::string& what)
{
    Lines lines(text);
    std::string_view line;
    if (!lines.next(line) || headerTokens(line) != std::vector<std::string>{"ply"})
        throw Error(what + ": not a PLY file (no 'ply' magic line)");
    PlyHeader h;
    for (;;) {
        if (!lines.next(line))
            throw Error(what + ": truncated PLY header (no end_header)");
        const std::vector<std::string> t = headerTokens(line);
        const std::string bad = what + ": line " + std::to_string(lines.number()) + ": malformed PLY header line " + quote(line);
        if (t.empty() || t[0] == "comment" || t[0] == "obj_info")
            continue;
        if (t[0] == "end_header" && t.size() == 1)
            break;
        if (t[0] == "format") {
            if (t.size() != 3 || t[2] != "1.0" ||
                (t[1] != "ascii" && t[1] != "binary_little_endian" && t[1] != "binary_big_endian") || !h.format.empty())
                throw Error(bad);
            h.format = t[1];
        } else if (t[0] == "element") {
            long long count = -1;
            if (t.size() != 3 || !readInteger(t[2], count).empty() || count < 0 || count > 0xffffffffll)
                throw Error(bad);
            for (const PlyElement& e : h.elements)
                if (e.name == t[1])
                    throw Error(what + ": line " + std::to_string(lines.number()) + ": PLY element '" + t[1] + "' declared twice");
            h.elements.push_back({t[1], static_cast<unsigned long long>(count), {}});
        } else if (t[0] == "property" && !h.elements.empty()) {
            PlyProperty p;
            if (t.size() == 5 && t[1] == "list" && plyType(t[2]) >= 0 && !kPlyTypes[plyType(t[2])].real && plyType(t[3]) >= 0)
                p = {t[4], plyType(t[3]), plyType(t[2])};
            else if (t.size() == 3 && plyType(t[1]) >= 0)
                p = {t[2], plyType(t[1])};
            else
                throw Error(bad);
            h.elements.back().properties.push_back(p);
        } else {
            throw Error(bad);
        }
    }
    if (h.format.empty())
        throw Error(what + ": PLY header has no format line");
    h.bodyOffset = lines.offset();
    h.lines = lines.number();
    assignPlyRoles(h, what);
    return h;
}

/// Refuses counts the data cannot hold before anything is allocated: in binary, every element needs
/// at least its scalars and list counts; in ASCII, a value and a separator per property.
void checkPlySize(const PlyHeader& h, std::size_t bodyBytes, const std::string& what)
{
    const bool ascii = h.format == "ascii";
    unsigned long long left = bodyBytes + (ascii ? 1 : 0); // the last line may lack its line end
    for (const PlyElement& e : h.elements) {
        unsigned long long each = 0;
        for (const PlyProperty& p : e.properties)
            each += ascii ? 2 : kPlyTypes[p.countType >= 0 ? p.countType : p.type].size;
        if (each > 0 && e.count > left / each)
            throw Error(what + ": the PLY header declares " + plural(e.count, e.name) + ", more than the " +
                        std::to_string(bodyBytes) + " bytes of data can hold");
        left -= e.count * each;
    }
}

/// ASCII PLY data: one element per line, every token checked against its declared type.
class PlyAsciiBody {
public:
    PlyAsciiBody(std::string_view body, std::size_t headerLines, const std::string& what)
        : lines_(body, headerLines + 1), what_(what)
    {
    }

    /// Starts element `index` of `e` on the next non-blank line.
    void begin(const PlyElement& e, unsigned long long index)
    {
        element_ = &e;
        index_ = index;
        values_ = 0;
        for (std::string_view line;;) {
            if (!lines_.next(line))
                fail("truncated: the header declares " + plural(e.count, e.name) + ", the data holds " + std::to_string(index), false);
            tokens_ = Tokens(line);
            if (std::string_view token; Tokens(line).next(token))
                return;
        }
    }

    double value(int type)
    {
        std::string_view token;
        if (!tokens_.next(token))
            fail(where() + " has " + std::to_string(values_) + " values, fewer than the header declares");
        ++values_;
        const PlyTypeInfo& info = kPlyTypes[type];
        std::string why;
        double v = 0.0;
        if (info.real) {
            why = readReal(token, v, info.max);
        } else {
            long long k = 0;
            why = readInteger(token, k);
            v = static_cast<double>(k);
            if (why.empty() && (v < info.min || v > info.max))
                why = quote(token) + " is out of range for " + info.name;
        }
        if (!why.empty())
            fail(where() + ": " + why);
        return v;
    }

    /// ASCII lists are read token by token, so nothing is allocated from a count.
    void list(double count, int)
    {
        if (count < 0)
            fail(where() + ": a list count of " + std::to_string(static_cast<long long>(count)) + " is negative");
    }

    void end()
    {
        if (std::string_view token; tokens_.next(token))
            fail(where() + " has more values than the header declares");
    }

    void finish()
    {
        for (std::string_view line; lines_.next(line);)
            if (std::string_view token; Tokens(line).next(token))
                fail("the data continues past the elements the header declares");
    }

    std::string where() const { return element_->name + " " + std::to_string(index_); }

    [[noreturn]] void fail(const std::string& why, bool withLine = true) const
    {
        throw Error(what_ + ": " + (withLine ? "line " + std::to_string(lines_.number()) + ": " : std::string()) + why);
    }

private:
    Lines lines_;
    Tokens tokens_;
    const std::string& what_;
    const PlyElement* element_ = nullptr;
    unsigned long long index_ = 0;
    std::size_t values_ = 0;
};

template <class T>
double loadAs(const unsigned char* bytes)
{
    T v;
    std::memcpy(&v, bytes, sizeof v);
    return static_cast<double>(v);
}

/// Binary PLY data: values of the declared types, in either byte order, and exactly as many bytes
/// as the elements need.
class PlyBinaryBody {
public:
    PlyBinaryBody(std::string_view body, bool bigEndian, const std::string& what)
        : data_(body), swap_(bigEndian != (std::endian::native == std::endian::big)), what_(what)
    {
    }

    void begin(const PlyElement& e, unsigned long long index)
    {
        element_ = &e;
        index_ = index;
    }

    double value(int type)
    {
        const std::size_t size = kPlyTypes[type].size;
        if (data_.size() - pos_ < size)
            truncated();
        unsigned char b[8];
        std::memcpy(b, data_.data() + pos_, size);
        pos_ += size;
        if (swap_)
            std::reverse(b, b + size);
        switch (type) {
        case 0: return loadAs<std::int8_t>(b);
        case 1: return loadAs<std::uint8_t>(b);
        case 2: return loadAs<std::int16_t>(b);
        case 3: return loadAs<std::uint16_t>(b);
        case 4: return loadAs<std::int32_t>(b);
        case 5: return loadAs<std::uint32_t>(b);
        case 6: return loadAs<float>(b);
        default: return loadAs<double>(b);
        }
    }

    /// A list of `count` items of `type` must fit in the data left, before any of it is read.
    void list(double count, int type)
    {
        if (count < 0 || count > static_cast<double>((data_.size() - pos_) / kPlyTypes[type].size))
            fail("truncated or corrupt: " + where() + " lists " + std::to_string(static_cast<long long>(count)) +
                 " values, more than the " + std::to_string(data_.size() - pos_) + " bytes left hold");
    }

    void end() {}

    void finish()
    {
        if (pos_ != data_.size())
            fail("the data continues " + std::to_string(data_.size() - pos_) + " bytes past the " +
                 (element_ ? plural(element_->count, element_->name) : std::string("elements")) + " the header declares");
    }

    std::string where() const { return element_->name + " " + std::to_string(index_); }
    [[noreturn]] void fail(const std::string& why) const { throw Error(what_ + ": " + why); }

private:
    [[noreturn]] void truncated() const
    {
        fail("truncated: the header declares " + plural(element_->count, element_->name) + ", the data holds " +
             std::to_string(index_));
    }

    std::string_view data_;
    bool swap_;
    std::size_t pos_ = 0;
    const std::string& what_;
    const PlyElement* element_ = nullptr;
    unsigned long long index_ = 0;
};

/// A vertex coordinate must be a finite float, whatever type the file stores it in.
template <class Body>
float plyCoordinate(double v, const PlyProperty& p, const Body& body)
{
    if (!std::isfinite(v))
        body.fail(body.where() + ": " + p.name + " is not finite");
    if (std::abs(v) > FLT_MAX)
        body.fail(body.where() + ": " + p.name + " is beyond the float range");
    return static_cast<float>(v);
}

/// Every element of the data, in header order; other elements than vertex and face are read and
/// checked, then dropped (they carry no geometry).
template <class Body>
Mesh readPlyElements(Body& body, const PlyHeader& h)
{
    unsigned long long vertices = 0;
    for (const PlyElement& e : h.elements)
        vertices = e.name == "vertex" ? e.count : vertices;
    Mesh mesh;
    std::vector<std::uint32_t> polygon;
    for (const PlyElement& e : h.elements) {
        if (e.name == "vertex")
            mesh.positions.reserve(e.count); // bounded by the file's size (checkPlySize)
        for (unsigned long long i = 0; i < e.count; ++i) {
            body.begin(e, i);
            glm::vec3 p(0.0f);
            for (const PlyProperty& prop : e.properties) {
                if (prop.countType < 0) {
                    const double v = body.value(prop.type);
                    if (prop.role != PlyRole::None)
                        p[static_cast<int>(prop.role) - 1] = plyCoordinate(v, prop, body);
                    continue;
                }
                const double count = body.value(prop.countType);
                body.list(count, prop.type);
                polygon.clear();
                for (double k = 0; k < count; ++k) {
                    const double v = body.value(prop.type);
                    if (prop.role != PlyRole::Corners)
                        continue;
                    if (v < 0 || v >= static_cast<double>(vertices))
                        body.fail(body.where() + ": vertex index " + std::to_string(static_cast<long long>(v)) +
                                  " is out of range (" + plural(vertices, "vertex") + ")");
                    polygon.push_back(static_cast<std::uint32_t>(v));
                }
                if (prop.role == PlyRole::Corners && polygon.size() < 3)
                    body.fail(body.where() + " " + polygonTooSmall(polygon.size()));
                if (prop.role == PlyRole::Corners)
                    addFan(mesh, polygon);
            }
            body.end();
            if (e.name == "vertex")
                mesh.positions.push_back(p);
        }
    }
    body.finish();
    return mesh;
}

/// PLY read here entirely (see the file comment): header, size check, then the data.

} // namespace

Mesh readPly(std::string_view text, const std::string& what)
{
    const PlyHeader h = plyHeader(text, what);
    const std::string_view body = text.substr(h.bodyOffset);
    checkPlySize(h, body.size(), what);
    if (h.format == "ascii") {
        PlyAsciiBody ascii(body, h.lines, what);
        return readPlyElements(ascii, h);
    }
    PlyBinaryBody binary(body, h.format == "binary_big_endian", what);
    return readPlyElements(binary, h);
}

} // namespace sightline::meshio
