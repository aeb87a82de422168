#include "plugins/QuakeMap.h"

#include <charconv>
#include <cmath>

#include <glm/geometric.hpp>

#include "base/Error.h"
#include "visibility/bsp/BspPortals.h"

namespace sightline {

namespace {

bool isSpace(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f' || c == '\v'; }

/// The .map's tokens: braces, parentheses, quoted strings and bare words, with `//` comments; every
/// failure names the line.
class MapLexer {
public:
    MapLexer(std::string_view text, const std::string& what) : text_(text), what_(what) {}

    int line() const { return line_; }
    bool atEnd()
    {
        skipSpace();
        return at_ >= text_.size();
    }
    char peek()
    {
        skipSpace();
        return at_ < text_.size() ? text_[at_] : '\0';
    }
    void expect(char c, const char* context)
    {
        if (peek() != c)
            fail(std::string("expected '") + c + "' " + context + (at_ < text_.size() ? ", found '" + word(false) + "'" : ", found the end"));
        ++at_;
    }
    /// A quoted string (without its quotes), or a bare word up to the next space (braces and
    /// parentheses included: texture names such as "{grate" hold them).
    std::string word(bool consume = true)
    {
        skipSpace();
        const std::size_t start = at_;
        std::size_t end = at_;
        std::string out;
        if (end < text_.size() && text_[end] == '"') {
            const std::size_t close = text_.find('"', end + 1);
            if (close == std::string_view::npos)
                fail("a quoted string is not closed");
            out = std::string(text_.substr(end + 1, close - end - 1));
            if (out.find('\n') != std::string::npos && consume)
                fail("a quoted string runs over the end of its line");
            end = close + 1;
        } else {
            while (end < text_.size() && !isSpace(text_[end]))
                ++end;
            out = std::string(text_.substr(start, end - start));
        }
        if (consume)
            at_ = end;
        return out;
    }
    double number(const char* context)
    {
        skipSpace();
        std::size_t end = at_;
        while (end < text_.size() && !isSpace(text_[end]) && text_[end] != ')')
            ++end;
        const std::string_view token = text_.substr(at_, end - at_);
        double value = 0.0;
        const auto [ptr, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
        if (ec != std::errc() || ptr != token.data() + token.size() || !std::isfinite(value))
            fail(std::string("expected a number ") + context + ", found '" + std::string(token.substr(0, 40)) + "'");
        at_ = end;
        return value;
    }
    /// Skips what follows a plane's texture name (alignment, Valve axes, Quake 2 flags) up to the
    /// next plane or the brush's end.
    void skipToPlaneEnd()
    {
        while (!atEnd() && peek() != '(' && peek() != '}')
            word();
    }
    /// Skips a balanced { ... } block (Quake 3's patches and brushDef).
    void skipBlock()
    {
        expect('{', "opening the block");
        int depth = 1;
        while (depth > 0) {
            if (atEnd())
                fail("a block is not closed");
            const char c = peek();
            if (c == '{' || c == '}') {
                depth += c == '{' ? 1 : -1;
                ++at_;
            } else {
                word();
            }
        }
    }
    [[noreturn]] void fail(const std::string& message) const
    {
        throw Error(what_ + ":" + std::to_string(line_) + ": " + message);
    }

private:
    void skipSpace()
    {
        while (at_ < text_.size()) {
            const char c = text_[at_];
            if (c == '\n')
                ++line_;
            if (isSpace(c)) {
                ++at_;
            } else if (c == '/' && at_ + 1 < text_.size() && text_[at_ + 1] == '/') {
                while (at_ < text_.size() && text_[at_] != '\n')
                    ++at_;
            } else {
                break;
            }
        }
    }

    std::string_view text_;
    const std::string& what_;
    std::size_t at_ = 0;
    int line_ = 1;
};

glm::dvec3 point(MapLexer& in)
{
    in.expect('(', "opening a plane's point");
    glm::dvec3 p;
    for (int a = 0; a < 3; ++a) {
        p[a] = in.number("in a plane's point");
        if (std::abs(p[a]) > kMaxMapCoordinate)
            in.fail("a point lies beyond " + std::to_string(int(kMaxMapCoordinate)) + " units");
    }
    in.expect(')', "closing a plane's point");
    return p;
}

MapBrush brush(MapLexer& in, QuakeMap& map)
{
    MapBrush out;
    out.line = in.line();
    while (in.peek() == '(') {
        const glm::dvec3 p0 = point(in), p1 = point(in), p2 = point(in);
        MapPlane plane;
        plane.texture = in.word();
        in.skipToPlaneEnd();
        const glm::dvec3 n = glm::cross(p0 - p1, p2 - p1);
        const double length = glm::length(n);
        if (!(length > 1e-9)) {
            ++map.degeneratePlanes;
            continue;
        }
        plane.normal = n / length;
        plane.dist = glm::dot(plane.normal, p1);
        out.planes.push_back(std::move(plane));
        if (out.planes.size() > kMaxBrushPlanes)
            in.fail("a brush of more than " + std::to_string(kMaxBrushPlanes) + " planes");
    }
    return out;
}

MapEntity entity(MapLexer& in, QuakeMap& map)
{
    MapEntity out;
    in.expect('{', "opening an entity");
    while (true) {
        const char c = in.peek();
        if (c == '}') {
            in.expect('}', "closing the entity");
            return out;
        }
        if (c == '"') {
            std::string key = in.word();
            if (in.peek() != '"')
                in.fail("the key \"" + key + "\" has no quoted value");
            out.keys[std::move(key)] = in.word();
        } else if (c == '{') {
            in.expect('{', "opening a brush");
            if (in.peek() != '(' && in.peek() != '}') {
                const std::string kind = in.word();
                if (kind.rfind("patchDef", 0) != 0 && kind.rfind("brushDef", 0) != 0)
                    in.fail("expected a brush's plane '(' or a Quake 3 patchDef/brushDef, found '" + kind.substr(0, 40) + "'");
                in.skipBlock();
                ++map.leftOut;
            } else {
                out.brushes.push_back(brush(in, map));
            }
            in.expect('}', "closing the brush");
        } else {
            in.fail(c ? "expected a key, a brush or '}'" : "the entity is not closed");
        }
    }
}

} // namespace

std::string MapEntity::classname() const
{
    const auto it = keys.find("classname");
    return it == keys.end() ? std::string() : it->second;
}

QuakeMap parseQuakeMap(std::string_view text, const std::string& what)
{
    MapLexer in(text, what);
    QuakeMap map;
    while (!in.atEnd()) {
        if (in.peek() != '{')
            in.fail("expected '{' opening an entity, found '" + in.word(false).substr(0, 40) + "'");
        map.entities.push_back(entity(in, map));
    }
    return map;
}

std::vector<BrushFace> brushFaces(const MapBrush& brush)
{
    constexpr double kOnPlane = 1e-4;   // units: keeps corners shared by three planes
    std::vector<BrushFace> faces;
    for (std::size_t i = 0; i < brush.planes.size(); ++i) {
        const MapPlane& plane = brush.planes[i];
        double extent = 1024.0;
        for (const MapPlane& other : brush.planes)
            extent = std::max(extent, 4.0 * std::abs(other.dist) + 1024.0);
        // A square on the plane, large enough to hold the brush, then cut by every other plane.
        int major = 0;
        for (int a = 1; a < 3; ++a)
            if (std::abs(plane.normal[a]) > std::abs(plane.normal[major]))
                major = a;
        glm::dvec3 up = major == 2 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 0, 1);
        up = glm::normalize(up - plane.normal * glm::dot(up, plane.normal));
        const glm::dvec3 right = glm::cross(up, plane.normal), origin = plane.normal * plane.dist;
        // Counter-clockwise seen from the front (right, up, normal are right-handed).
        bsp::Winding w{origin - right * extent - up * extent, origin + right * extent - up * extent,
                       origin + right * extent + up * extent, origin - right * extent + up * extent};
        for (std::size_t j = 0; j < brush.planes.size() && !w.empty(); ++j)
            if (j != i)
                w = bsp::chopFront(w, -brush.planes[j].normal, -brush.planes[j].dist, kOnPlane);
        if (w.size() >= 3)
            faces.push_back({std::move(w), plane.texture});
    }
    return faces;
}

bool insideBrush(const MapBrush& brush, const glm::dvec3& p, double margin)
{
    for (const MapPlane& plane : brush.planes)
        if (glm::dot(plane.normal, p) - plane.dist > -margin)
            return false;
    return true;
}

} // namespace sightline
