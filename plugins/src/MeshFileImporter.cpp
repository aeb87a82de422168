// OBJ, PLY (ASCII and binary), OFF and STL import, each format read by a small strict reader here.
//
// Which reader, and why:
//  - OBJ, PLY and OFF went through OpenMesh's readers behind guards until bad input showed that
//    guarding them meant re-reading every token anyway: they turn values they cannot parse
//    ("nan", "1e39", "abc") into zeros or skip them, drop faces with unreadable or huge indices and
//    faces of 1-2 vertices, read a CR-only OBJ as empty, take a UTF-8 BOM as part of the first
//    statement, trust a PLY list count read from garbage (allocating gigabytes), load truncated
//    binary PLY partly, and their halfedge importer drops non-manifold faces. Visibility needs only
//    positions and polygons, so a strict reader of those few statements is smaller and safer than
//    the guards. No C or C++ PLY library is packaged for Debian, so PLY is read here too.
//  - STL is a trivial format (OpenMesh's reader dropped degenerate facets and accepted truncated
//    files as empty).
//
// Rules every reader follows:
//  - the file is checked (regular file, size limit; base/InputFile.h) before a byte is read,
//    then read whole; what is allocated grows with the data actually read, never with a count a
//    header declares, so memory stays a small multiple of the file's size;
//  - numbers are decimal, read by std::from_chars (locale-independent: a Qt program runs under the
//    user's LC_NUMERIC, where strtod may read "1,5"), finite and within float range. Hexadecimal
//    floats ("0x1p3") are refused: none of these formats defines them, and readers that accept
//    them (strtod) and readers that do not (streams) would see different geometry in one file;
//  - a text line ends at "\n", "\r\n" or a lone "\r"; a UTF-8 byte order mark at the start is
//    skipped;
//  - every polygon of 3 or more vertices is fan-triangulated and kept (degenerate and non-manifold
//    ones too: every triangle blocks rays); polygons of 1-2 vertices and anything unreadable are
//    refused with one line naming the file, the line (text) or element (binary), and the problem.

#include <algorithm>
#include <new>
#include <bit>
#include <cctype>
#include <cfloat>
#include <charconv>
#include <cmath>
#include <cstring>
#include <map>
#include <string_view>

#include "BuiltinFormats.h"
#include "plugins/MeshTopology.h"
#include "base/Error.h"
#include "base/InputFile.h"
#include "visibility/Scene.h"

namespace sightline {

namespace {

constexpr std::string_view::size_type npos = std::string_view::npos;

bool isSpace(char c) { return c == ' ' || c == '\t' || c == '\v' || c == '\f'; }

/// The lines of a text, one at a time; see the rules above for line ends and the BOM.
class Lines {
public:
    explicit Lines(std::string_view text, std::size_t firstNumber = 1) : text_(text), number_(firstNumber - 1)
    {
        if (text_.substr(0, 3) == "\xEF\xBB\xBF")
            pos_ = 3;
    }

    bool next(std::string_view& line)
    {
        if (pos_ >= text_.size())
            return false;
        const std::size_t end = text_.find_first_of("\r\n", pos_);
        line = text_.substr(pos_, end == npos ? npos : end - pos_);
        if (end == npos)
            pos_ = text_.size();
        else
            pos_ = end + (text_[end] == '\r' && end + 1 < text_.size() && text_[end + 1] == '\n' ? 2 : 1);
        ++number_;
        return true;
    }

    std::size_t number() const { return number_; } ///< of the line last returned
    std::size_t offset() const { return pos_; }    ///< just past the line last returned and its end

private:
    std::string_view text_;
    std::size_t pos_ = 0;
    std::size_t number_;
};

/// Whitespace-separated tokens of one line, one at a time (never collected: a line may be huge).
class Tokens {
public:
    explicit Tokens(std::string_view line = {}) : line_(line) {}

    bool next(std::string_view& token)
    {
        while (pos_ < line_.size() && isSpace(line_[pos_]))
            ++pos_;
        if (pos_ >= line_.size())
            return false;
        const std::size_t begin = pos_;
        while (pos_ < line_.size() && !isSpace(line_[pos_]))
            ++pos_;
        token = line_.substr(begin, pos_ - begin);
        return true;
    }

private:
    std::string_view line_;
    std::size_t pos_ = 0;
};

/// Tokens across lines, for formats whose statements may span lines (ASCII STL).
class TextTokens {
public:
    explicit TextTokens(std::string_view text) : lines_(text) {}

    bool next(std::string_view& token)
    {
        for (std::string_view line; !tokens_.next(token);) {
            if (!lines_.next(line))
                return false;
            tokens_ = Tokens(line);
        }
        return true;
    }
    std::size_t line() const { return lines_.number(); }

private:
    Lines lines_;
    Tokens tokens_;
};

/// A token as an error message shows it: quoted, shortened, control bytes replaced.
std::string quote(std::string_view token)
{
    if (token.empty())
        return "an empty value";
    std::string out = "'";
    for (const char c : token.substr(0, 40))
        out += std::isprint(static_cast<unsigned char>(c)) ? c : '?';
    return out + (token.size() > 40 ? "...'" : "'");
}

/// C's "+1.5" is common in exported files; from_chars takes no sign but '-'.
std::string_view withoutPlus(std::string_view token)
{
    if (token.size() > 1 && token[0] == '+' && token[1] != '-' && token[1] != '+')
        token.remove_prefix(1);
    return token;
}

/// Why `token` is not a finite decimal number of magnitude at most `limit`; empty when it is one.
std::string readReal(std::string_view token, double& value, double limit)
{
    const std::string_view digits = withoutPlus(token);
    double d = 0.0;
    const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), d);
    if (ec == std::errc::invalid_argument || end != digits.data() + digits.size()) {
        if (digits.size() > 2 && (digits[1] == 'x' || digits[1] == 'X' || digits[2] == 'x' || digits[2] == 'X'))
            return quote(token) + " is hexadecimal; only decimal numbers are accepted";
        return quote(token) + " is not a number";
    }
    if (ec == std::errc::result_out_of_range)
        return quote(token) + " is out of range";
    if (!std::isfinite(d))
        return quote(token) + " is not finite";
    if (std::abs(d) > limit)
        return quote(token) + " is beyond the float range";
    value = d;
    return {};
}

std::string readFloat(std::string_view token, float& value)
{
    double d = 0.0;
    std::string why = readReal(token, d, FLT_MAX);
    value = static_cast<float>(d);
    return why;
}

/// Why `token` is not a decimal integer fitting in a long long; empty when it is one.
std::string readInteger(std::string_view token, long long& value)
{
    const std::string_view digits = withoutPlus(token);
    const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
    if (ec == std::errc::invalid_argument || end != digits.data() + digits.size())
        return quote(token) + " is not an integer";
    if (ec == std::errc::result_out_of_range)
        return quote(token) + " is out of range";
    return {};
}

std::string plural(unsigned long long count, const std::string& noun)
{
    const std::string many = noun == "vertex" ? "vertices" : noun + "s";
    return std::to_string(count) + " " + (count == 1 ? noun : many);
}

/// Appends polygon `p` (3 or more vertex indices) as a fan: a quad gives 2 triangles.
void addFan(Mesh& mesh, const std::vector<std::uint32_t>& p)
{
    for (std::size_t k = 1; k + 1 < p.size(); ++k)
        mesh.indices.insert(mesh.indices.end(), {p[0], p[k], p[k + 1]});
}

std::string polygonTooSmall(std::size_t vertices)
{
    return "has " + plural(vertices, "vertex") + "; 3 or more are needed";
}

// ---- OBJ ---------------------------------------------------------------------------------------

/// An error at line `line` of a text file.
[[noreturn]] void failAt(const std::string& what, std::size_t line, const std::string& why)
{
    throw Error(what + ": line " + std::to_string(line) + ": " + why);
}

/// "v x y z [w | r g b [a]]": every value must be a number; only x, y, z are kept.
glm::vec3 objVertex(Tokens& t, const std::string& what, std::size_t line)
{
    glm::vec3 p(0.0f);
    int n = 0;
    for (std::string_view token; t.next(token); ++n) {
        float value = 0.0f;
        if (const std::string why = readFloat(token, value); !why.empty())
            failAt(what, line, "vertex value " + why);
        if (n < 3)
            p[n] = value;
    }
    if (n < 3)
        failAt(what, line, "vertex has " + std::to_string(n) + " coordinates, 3 are needed");
    if (n > 7)
        failAt(what, line, "vertex has " + std::to_string(n) + " values (x y z, then at most w or r g b [a])");
    return p;
}

/// One face corner "v", "v/vt", "v//vn" or "v/vt/vn" as a 0-based position index. Positive
/// indices count from 1, negative ones back from the last vertex so far; both must name a vertex
/// already read (OBJ defines them that way). vt and vn are not needed but must be integers.
std::uint32_t objCorner(std::string_view token, std::size_t vertices, const std::string& what, std::size_t line)
{
    const std::string_view index = token.substr(0, token.find('/'));
    if (index.empty())
        failAt(what, line, "face index is empty in " + quote(token));
    for (std::size_t at = token.find('/'), parts = 1; at != npos; at = token.find('/', at + 1), ++parts) {
        const std::size_t end = token.find('/', at + 1);
        const std::string_view part = token.substr(at + 1, end == npos ? npos : end - at - 1);
        long long ignored = 0;
        if (parts >= 3)
            failAt(what, line, "face corner " + quote(token) + " has more than v/vt/vn");
        if (!part.empty())
            if (const std::string why = readInteger(part, ignored); !why.empty())
                failAt(what, line, "face corner " + quote(token) + ": " + why);
    }
    long long k = 0;
    if (const std::string why = readInteger(index, k); !why.empty())
        failAt(what, line, "face index " + why);
    const auto count = static_cast<long long>(vertices);
    if (k == 0)
        failAt(what, line, "face index 0 is invalid (OBJ counts from 1, or back from -1)");
    const long long resolved = k > 0 ? k - 1 : count + k;
    if (resolved < 0 || resolved >= count)
        failAt(what, line, "face index " + std::string(index) + " is out of range (" + plural(vertices, "vertex") + ")");
    return static_cast<std::uint32_t>(resolved);
}

/// Statements that carry no surface geometry (attributes, grouping, materials, curve settings).
bool objIgnorable(std::string_view keyword)
{
    static const char* const kIgnored[] = {"vt", "vn", "vp", "o", "g", "s", "mg", "usemtl", "mtllib", "maplib",
                                           "usemap", "lod", "shadow_obj", "trace_obj", "ctech", "stech", "bevel",
                                           "c_interp", "d_interp", "cstype", "deg", "bmat", "step", "parm",
                                           "trim", "hole", "scrv", "sp", "end", "con", "call", "csh"};
    return std::find(std::begin(kIgnored), std::end(kIgnored), keyword) != std::end(kIgnored);
}

/// OBJ read by a strict line scanner: v and f (fo) make the mesh; points and lines block no rays and
/// are counted in a warning; free-form curves and surfaces would be geometry lost, so they are
/// refused; unknown statements are warned about, and a line that starts with no keyword is refused.
Mesh readObj(std::string_view text, const std::string& what, std::vector<std::string>& warnings)
{
    Mesh mesh;
    Lines lines(text);
    std::vector<std::uint32_t> polygon;
    std::size_t pointsAndLines = 0, unknown = 0, firstUnknown = 0;
    std::string unknownKeyword;
    for (std::string_view line; lines.next(line);) {
        const std::size_t number = lines.number();
        if (line.find('\0') != npos)
            failAt(what, number, "contains a NUL byte (binary data, not OBJ text)");
        Tokens t(line.substr(0, line.find('#')));
        std::string_view keyword;
        if (!t.next(keyword))
            continue;
        if (keyword == "v") {
            mesh.positions.push_back(objVertex(t, what, number));
        } else if (keyword == "f" || keyword == "fo") {
            polygon.clear();
            for (std::string_view token; t.next(token);)
                polygon.push_back(objCorner(token, mesh.positions.size(), what, number));
            if (polygon.size() < 3)
                failAt(what, number, "face " + polygonTooSmall(polygon.size()));
            addFan(mesh, polygon);
        } else if (keyword == "p" || keyword == "l") {
            ++pointsAndLines;
        } else if (keyword == "curv" || keyword == "curv2" || keyword == "surf") {
            failAt(what, number, "free-form curves and surfaces are not supported (export the mesh as polygons)");
        } else if (!std::isalpha(static_cast<unsigned char>(keyword[0]))) {
            failAt(what, number, quote(keyword) + " is not an OBJ statement");
        } else if (!objIgnorable(keyword) && unknown++ == 0) {
            firstUnknown = number;
            unknownKeyword = std::string(keyword);
        }
    }
    if (pointsAndLines > 0)
        warnings.push_back(what + ": " + std::to_string(pointsAndLines) +
                           " point and line statements ignored (they block no rays)");
    if (unknown > 0)
        warnings.push_back(what + ": " + std::to_string(unknown) + " unknown statements ignored (the first, " +
                           quote(unknownKeyword) + ", at line " + std::to_string(firstUnknown) + ")");
    return mesh;
}

// ---- PLY ---------------------------------------------------------------------------------------

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

// ---- OFF ---------------------------------------------------------------------------------------

/// The next line with a token after '#' comments are cut; false at the end of the text.
bool nextOffLine(Lines& lines, std::string_view& line)
{
    while (lines.next(line)) {
        line = line.substr(0, line.find('#'));
        if (std::string_view token; Tokens(line).next(token))
            return true;
    }
    return false;
}

/// "[ST][C][N]OFF" (the prefixes announce extra per-vertex data, which is not needed) with the
/// counts on its line or the next; binary and n-dimensional OFF are refused.
std::pair<std::size_t, std::size_t> offCounts(Lines& lines, const std::string& what)
{
    std::string_view line;
    if (!nextOffLine(lines, line))
        throw Error(what + ": empty OFF file");
    Tokens t(line);
    std::string_view keyword, token;
    t.next(keyword);
    const std::size_t prefix = keyword.size() >= 3 ? keyword.size() - 3 : 0;
    if (keyword.size() < 3 || keyword.substr(prefix) != "OFF" || keyword.substr(0, prefix).find_first_not_of("STCN") != npos)
        throw Error(what + ": not a supported OFF file (header " + quote(keyword) + ")");
    if (!t.next(token)) { // the counts are on the next line
        if (!nextOffLine(lines, line))
            throw Error(what + ": OFF header has no vertex and face counts");
        t = Tokens(line);
        t.next(token);
    }
    if (token == "BINARY")
        throw Error(what + ": binary OFF is not supported; save it as ASCII OFF, PLY or OBJ");
    long long counts[2] = {-1, -1};
    for (int k = 0; k < 2; ++k)
        if (const std::string why = readInteger(token, counts[k]); !why.empty() || counts[k] < 0 || (k == 0 && !t.next(token)))
            failAt(what, lines.number(), "OFF header has no valid vertex and face counts");
    return {static_cast<std::size_t>(counts[0]), static_cast<std::size_t>(counts[1])};
}

/// ASCII OFF, line by line: vertex lines "x y z ..." and face lines "n i1 .. in ..." (colours and
/// other trailing per-element data are not needed). Nothing is reserved from the header's counts.
Mesh readOff(std::string_view text, const std::string& what)
{
    Lines lines(text);
    const auto counts = offCounts(lines, what);
    const std::size_t vertices = counts.first, faces = counts.second;   // lambdas capture these (clang 14: not bindings)
    const auto truncated = [&](std::size_t v, std::size_t f) {
        throw Error(what + ": truncated: the header declares " + plural(vertices, "vertex") + " and " + plural(faces, "face") +
                    ", the data holds " + plural(v, "vertex") + " and " + plural(f, "face"));
    };
    Mesh mesh;
    std::string_view line, token;
    for (std::size_t i = 0; i < vertices; ++i) {
        if (!nextOffLine(lines, line))
            truncated(i, 0);
        Tokens t(line);
        glm::vec3 p(0.0f);
        for (int k = 0; k < 3; ++k) {
            if (!t.next(token))
                failAt(what, lines.number(), "vertex " + std::to_string(i) + " has fewer than 3 coordinates");
            if (const std::string why = readFloat(token, p[k]); !why.empty())
                failAt(what, lines.number(), "vertex " + std::to_string(i) + ": " + why);
        }
        mesh.positions.push_back(p);
    }
    std::vector<std::uint32_t> polygon;
    for (std::size_t f = 0; f < faces; ++f) {
        if (!nextOffLine(lines, line))
            truncated(vertices, f);
        const std::string face = "face " + std::to_string(f);
        Tokens t(line);
        long long n = 0;
        t.next(token);
        if (const std::string why = readInteger(token, n); !why.empty())
            failAt(what, lines.number(), face + ": vertex count " + why);
        if (n < 3)
            failAt(what, lines.number(), face + " " + polygonTooSmall(static_cast<std::size_t>(std::max(0ll, n))));
        polygon.clear();
        for (long long k = 0; k < n; ++k) {
            long long index = 0;
            if (!t.next(token))
                failAt(what, lines.number(), face + " announces " + std::to_string(n) + " vertices but lists " + std::to_string(k));
            if (const std::string why = readInteger(token, index); !why.empty())
                failAt(what, lines.number(), face + ": vertex index " + why);
            if (index < 0 || static_cast<unsigned long long>(index) >= vertices)
                failAt(what, lines.number(), face + ": vertex index " + std::to_string(index) + " is out of range (" +
                                                 plural(vertices, "vertex") + ")");
            polygon.push_back(static_cast<std::uint32_t>(index));
        }
        addFan(mesh, polygon);
    }
    if (nextOffLine(lines, line))
        failAt(what, lines.number(), "the data continues past the " + plural(faces, "face") + " the header declares");
    return mesh;
}

// ---- STL ---------------------------------------------------------------------------------------

/// ASCII STL: "solid name (facet normal n n n outer loop (vertex x y z){3,} endloop endfacet)*
/// endsolid", possibly several solids. Loops with more than 3 vertices are fan-triangulated.
Mesh readAsciiStl(std::string_view text, const std::string& what)
{
    TextTokens t(text);
    std::string_view token;
    bool more = t.next(token);
    const auto advance = [&] { more = t.next(token); };
    const auto expect = [&](const char* word) {
        if (!more || token != word)
            failAt(what, t.line(), "malformed or truncated STL: expected '" + std::string(word) + "', found " +
                                       (more ? quote(token) : std::string("the end of the file")));
        advance();
    };
    const auto number = [&](const char* role) {
        float v = 0.0f;
        if (!more)
            failAt(what, t.line(), "STL " + std::string(role) + " is truncated");
        if (const std::string why = readFloat(token, v); !why.empty())
            failAt(what, t.line(), "STL " + std::string(role) + ": " + why);
        advance();
        return v;
    };
    Mesh mesh;
    std::vector<std::uint32_t> loop;
    while (more) {
        expect("solid");
        while (more && token != "facet" && token != "endsolid")
            advance(); // the solid's name
        while (more && token == "facet") {
            advance();
            expect("normal");
            for (int k = 0; k < 3; ++k) { // unused, and some exporters write "nan" for degenerate facets
                if (!more || token == "outer")
                    failAt(what, t.line(), "STL facet normal has fewer than 3 values");
                advance();
            }
            expect("outer");
            expect("loop");
            loop.clear();
            while (more && token == "vertex") {
                advance();
                glm::vec3 p;
                for (int k = 0; k < 3; ++k)
                    p[k] = number("vertex");
                loop.push_back(static_cast<std::uint32_t>(mesh.positions.size()));
                mesh.positions.push_back(p);
            }
            if (loop.size() < 3)
                failAt(what, t.line(), "STL facet " + polygonTooSmall(loop.size()));
            addFan(mesh, loop);
            expect("endloop");
            expect("endfacet");
        }
        expect("endsolid");
        while (more && token != "solid")
            advance(); // the name after endsolid
    }
    return mesh;
}

/// Binary STL: 80-byte header, u32 count, then per facet 12 floats (normal, 3 vertices) + u16.
Mesh readBinaryStl(std::string_view bytes)
{
    static_assert(sizeof(glm::vec3) == 12, "vertices are copied as 3 packed floats");
    std::uint32_t count = 0;
    std::memcpy(&count, bytes.data() + 80, 4);
    Mesh mesh;
    mesh.positions.resize(std::size_t(count) * 3); // the caller matched the count to the file's size
    for (std::size_t f = 0; f < count; ++f)
        std::memcpy(&mesh.positions[3 * f], bytes.data() + 84 + 50 * f + 12, 36);
    mesh.indices.resize(mesh.positions.size());
    for (std::size_t k = 0; k < mesh.indices.size(); ++k)
        mesh.indices[k] = static_cast<std::uint32_t>(k);
    return mesh;
}

/// A file is binary STL exactly when its size matches its facet count; "solid" starts an ASCII one,
/// unless it holds NUL bytes (binary exporters often start their header with "solid" too).
Mesh readStl(std::string_view bytes, const std::string& what)
{
    std::uint32_t count = 0;
    if (bytes.size() >= 84) {
        std::memcpy(&count, bytes.data() + 80, 4);
        if (bytes.size() == 84 + 50 * std::uint64_t(count))
            return readBinaryStl(bytes);
    }
    if (bytes.substr(0, 5) == "solid" && bytes.find('\0') == npos)
        return readAsciiStl(bytes, what);
    if (bytes.size() >= 84)
        throw Error(what + ": truncated or corrupt binary STL: the header declares " + plural(count, "facet") + " (" +
                    std::to_string(84 + 50 * std::uint64_t(count)) + " bytes), the file has " +
                    std::to_string(bytes.size()) + " bytes");
    throw Error(what + ": not an STL file (too short for binary STL, and not ASCII STL)");
}

// ---- the importer ------------------------------------------------------------------------------

std::string lowerExtension(const std::filesystem::path& file)
{
    std::string e = file.extension().string();
    std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return e;
}

class MeshFileImporter final : public SceneImporter {
public:
    std::string name() const override { return "OBJ/PLY/OFF/STL"; }
    std::vector<std::string> extensions() const override { return {".obj", ".ply", ".off", ".stl"}; }

    Scene load(const std::filesystem::path& file, std::vector<std::string>& warnings) const override
    {
        const std::string what = file.string();
        // The importer interface has no role: these files are scenes or occluder meshes of one.
        const std::string bytes = readInputFile(file, "scene");
        const std::string ext = lowerExtension(file);
        Mesh mesh;
        try {
            mesh = ext == ".stl"   ? readStl(bytes, what)
                   : ext == ".obj" ? readObj(bytes, what, warnings)
                   : ext == ".ply" ? readPly(bytes, what)
                                   : readOff(bytes, what);
        } catch (const std::bad_alloc&) {
            // Memory grows with the geometry a file holds (a few times its size): still one line.
            throw Error(what + ": out of memory while reading " + std::to_string(bytes.size() >> 20) + " MB of geometry");
        }
        if (mesh.positions.empty())
            warnings.push_back(what + ": no vertices");
        return oneInstance(std::move(mesh), file);
    }

private:
    /// The file's one mesh, named after the file, at the origin. These formats carry no
    /// watertight flag: a closed, outward mesh earns it (watertight culling, §7).
    static Scene oneInstance(Mesh mesh, const std::filesystem::path& file)
    {
        mesh.name = file.stem().string();
        mesh.watertight = meshTopology(mesh).closedAndOutward();
        Scene scene;
        scene.addMeshInstance(std::move(mesh));
        validate(scene, file.string());
        return scene;
    }
};

} // namespace

std::unique_ptr<SceneImporter> makeMeshFileImporter() { return std::make_unique<MeshFileImporter>(); }

} // namespace sightline
