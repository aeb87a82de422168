#include "GltfValidation.h"

#include <cstdint>
#include <limits>
#include <optional>
#include <vector>

#include "base/Error.h"
#include "visibility/SceneLimits.h"

namespace sightline::gltf {

namespace {

using nlohmann::json;

/// The top-level lists whose elements other fields name, with the word for one element.
struct ListName {
    const char* list;
    const char* element;
};
constexpr ListName kLists[] = {{"scenes", "scene"},         {"nodes", "node"},       {"meshes", "mesh"},
                               {"accessors", "accessor"},   {"bufferViews", "bufferView"},
                               {"buffers", "buffer"},       {"images", "image"},     {"skins", "skin"},
                               {"materials", "material"},   {"cameras", "camera"},   {"textures", "texture"},
                               {"samplers", "sampler"},     {"animations", "animation"}};

/// A value for a message: short, whatever it is (the document is depth-checked, so dump is safe).
std::string shown(const json& value)
{
    std::string text = value.dump();
    if (text.size() > 40)
        text = text.substr(0, 37) + "...";
    return text;
}

/// The value as a non-negative integer, or nothing when it is not one (3.5, -1, 1e308, "2", true).
std::optional<std::uint64_t> nonNegativeInteger(const json& value)
{
    if (value.is_number_unsigned())
        return value.get<std::uint64_t>();
    if (value.is_number_integer() && value.get<std::int64_t>() >= 0)
        return static_cast<std::uint64_t>(value.get<std::int64_t>());
    return std::nullopt;
}

class Checker {
public:
    Checker(const json& doc, const std::string& what) : doc_(doc), what_(what) {}

    [[noreturn]] void fail(const std::string& message) const { throw Error(what_ + ": " + message); }

    /// The list's elements (empty when absent); a list must be an array of objects.
    const json& list(const char* name) const
    {
        static const json empty = json::array();
        const auto it = doc_.find(name);
        if (it == doc_.end())
            return empty;
        if (!it->is_array())
            fail("'" + std::string(name) + "' is " + shown(*it) + ", not an array");
        for (std::size_t i = 0; i < it->size(); ++i)
            if (!(*it)[i].is_object())
                fail("'" + std::string(name) + "' element " + std::to_string(i) + " is " + shown((*it)[i]) +
                     ", not an object");
        return *it;
    }

    /// An optional member that must be an object (or, for `array`, an array).
    const json* member(const json& owner, const char* key, const std::string& where, bool array) const
    {
        const auto it = owner.find(key);
        if (it == owner.end())
            return nullptr;
        if (array ? !it->is_array() : !it->is_object())
            fail(where + " '" + key + "' is " + shown(*it) + ", not " + (array ? "an array" : "an object"));
        return &*it;
    }

    /// An optional non-negative integer member no larger than `max`.
    void count(const json& owner, const char* key, const std::string& where,
               std::uint64_t max = std::numeric_limits<std::uint64_t>::max()) const
    {
        if (const auto it = owner.find(key); it != owner.end())
            integer(*it, where + " '" + key + "'", max);
    }

    /// An optional member that must name an element of the top-level list `target`.
    void index(const json& owner, const char* key, const char* target, const std::string& where) const
    {
        if (const auto it = owner.find(key); it != owner.end())
            indexValue(*it, target, where + " '" + key + "'");
    }

    /// An optional array member each of whose entries must name an element of `target`.
    void indexArray(const json& owner, const char* key, const char* target, const std::string& where) const
    {
        const json* values = member(owner, key, where, true);
        if (!values)
            return;
        for (std::size_t i = 0; i < values->size(); ++i)
            indexValue((*values)[i], target, where + " '" + key + "' entry " + std::to_string(i));
    }

    /// Every member of an object (attributes, morph targets) must name an element of `target`.
    void indexObject(const json& object, const char* target, const std::string& where) const
    {
        for (auto it = object.begin(); it != object.end(); ++it)
            indexValue(it.value(), target, where + " '" + it.key() + "'");
    }

    void indexValue(const json& value, const char* target, const std::string& where) const
    {
        indexInto(value, size(target), element(target), target, where);
    }

    /// `value` must name one of `available` elements (a list local to its owner, e.g. an animation's samplers).
    void indexInto(const json& value, std::size_t available, const std::string& element, const std::string& plural,
                   const std::string& where) const
    {
        const std::uint64_t i = integer(value, where, std::numeric_limits<std::int32_t>::max());
        if (i >= available)
            fail(where + " names " + element + " " + std::to_string(i) + ", but the file has " +
                 std::to_string(available) + " " + plural);
    }

private:
    std::uint64_t integer(const json& value, const std::string& where, std::uint64_t max) const
    {
        const std::optional<std::uint64_t> n = nonNegativeInteger(value);
        if (!n)
            fail(where + " is " + shown(value) + ", not a non-negative integer");
        if (*n > max)
            fail(where + " is " + shown(value) + ", beyond the largest allowed (" + std::to_string(max) + ")");
        return *n;
    }

    std::size_t size(const char* name) const
    {
        const auto it = doc_.find(name);
        return it != doc_.end() && it->is_array() ? it->size() : 0;
    }

    static std::string element(const char* list)
    {
        for (const ListName& l : kLists)
            if (std::string(l.list) == list)
                return l.element;
        return list;
    }

    const json& doc_;
    const std::string& what_;
};

constexpr std::uint64_t kMaxInt = std::numeric_limits<std::int32_t>::max(); // tinygltf keeps enums as int

void checkPrimitive(const Checker& c, const json& primitive, const std::string& where)
{
    if (!primitive.is_object())
        c.fail(where + " is " + shown(primitive) + ", not an object");
    c.index(primitive, "indices", "accessors", where);
    c.index(primitive, "material", "materials", where);
    c.count(primitive, "mode", where, 6);
    if (const json* attributes = c.member(primitive, "attributes", where, false))
        c.indexObject(*attributes, "accessors", where + " attribute");
    if (const json* targets = c.member(primitive, "targets", where, true))
        for (std::size_t t = 0; t < targets->size(); ++t) {
            const std::string target = where + " morph target " + std::to_string(t);
            if (!(*targets)[t].is_object())
                c.fail(target + " is " + shown((*targets)[t]) + ", not an object");
            c.indexObject((*targets)[t], "accessors", target + " attribute");
        }
}

void checkAccessor(const Checker& c, const json& accessor, const std::string& where)
{
    c.index(accessor, "bufferView", "bufferViews", where);
    c.count(accessor, "byteOffset", where);
    c.count(accessor, "count", where);
    c.count(accessor, "componentType", where, kMaxInt);
    // Without a bufferView the accessor's data is zeros (plus any sparse values) that are not in
    // the file: its count alone would size the allocation, so it is bounded here.
    if (!accessor.contains("bufferView"))
        c.count(accessor, "count", where + " (no bufferView: its data is not in the file)", kMaxUnbackedAccessorElements);
    const json* sparse = c.member(accessor, "sparse", where, false);
    if (!sparse)
        return;
    c.count(*sparse, "count", where + " sparse");
    for (const char* part : {"indices", "values"})
        if (const json* p = c.member(*sparse, part, where + " sparse", false)) {
            const std::string at = where + " sparse " + part;
            c.index(*p, "bufferView", "bufferViews", at);
            c.count(*p, "byteOffset", at);
            c.count(*p, "componentType", at, kMaxInt);
        }
}

void checkAnimation(const Checker& c, const json& animation, const std::string& where)
{
    const json* samplers = c.member(animation, "samplers", where, true);
    if (samplers)
        for (std::size_t s = 0; s < samplers->size(); ++s) {
            const std::string at = where + " sampler " + std::to_string(s);
            if (!(*samplers)[s].is_object())
                c.fail(at + " is " + shown((*samplers)[s]) + ", not an object");
            c.index((*samplers)[s], "input", "accessors", at);
            c.index((*samplers)[s], "output", "accessors", at);
        }
    if (const json* channels = c.member(animation, "channels", where, true))
        for (std::size_t k = 0; k < channels->size(); ++k) {
            const std::string at = where + " channel " + std::to_string(k);
            const json& channel = (*channels)[k];
            if (!channel.is_object())
                c.fail(at + " is " + shown(channel) + ", not an object");
            if (const auto it = channel.find("sampler"); it != channel.end())
                c.indexInto(*it, samplers ? samplers->size() : 0, "sampler", "samplers in the animation",
                            at + " 'sampler'");
            if (const json* target = c.member(channel, "target", at, false))
                c.index(*target, "node", "nodes", at + " target");
        }
}

/// Calls `check(element, "node 3")` for each element of a top-level list.
template <class Check>
void each(const Checker& c, const char* list, const char* element, Check check)
{
    const json& elements = c.list(list);
    for (std::size_t i = 0; i < elements.size(); ++i)
        check(elements[i], std::string(element) + " " + std::to_string(i));
}

} // namespace

void checkIndices(const json& doc, const std::string& what)
{
    if (!doc.is_object())
        throw Error(what + ": the JSON root is not an object");
    const Checker c(doc, what);
    for (const ListName& l : kLists)
        c.list(l.list);
    if (const auto it = doc.find("scene"); it != doc.end())
        c.indexValue(*it, "scenes", "'scene'");
    each(c, "scenes", "scene", [&](const json& s, const std::string& at) { c.indexArray(s, "nodes", "nodes", at); });
    each(c, "nodes", "node", [&](const json& n, const std::string& at) {
        c.index(n, "mesh", "meshes", at);
        c.index(n, "camera", "cameras", at);
        c.index(n, "skin", "skins", at);
        c.indexArray(n, "children", "nodes", at);
    });
    each(c, "meshes", "mesh", [&](const json& m, const std::string& at) {
        if (const json* primitives = c.member(m, "primitives", at, true))
            for (std::size_t p = 0; p < primitives->size(); ++p)
                checkPrimitive(c, (*primitives)[p], at + " primitive " + std::to_string(p));
    });
    each(c, "accessors", "accessor", [&](const json& a, const std::string& at) { checkAccessor(c, a, at); });
    each(c, "bufferViews", "bufferView", [&](const json& v, const std::string& at) {
        c.index(v, "buffer", "buffers", at);
        c.count(v, "byteOffset", at);
        c.count(v, "byteLength", at);
        c.count(v, "byteStride", at, kMaxInt);
        c.count(v, "target", at, kMaxInt);
    });
    each(c, "buffers", "buffer", [&](const json& b, const std::string& at) { c.count(b, "byteLength", at); });
    each(c, "images", "image", [&](const json& i, const std::string& at) { c.index(i, "bufferView", "bufferViews", at); });
    each(c, "textures", "texture", [&](const json& t, const std::string& at) {
        c.index(t, "source", "images", at);
        c.index(t, "sampler", "samplers", at);
    });
    each(c, "skins", "skin", [&](const json& s, const std::string& at) {
        c.indexArray(s, "joints", "nodes", at);
        c.index(s, "skeleton", "nodes", at);
        c.index(s, "inverseBindMatrices", "accessors", at);
    });
    each(c, "animations", "animation", [&](const json& a, const std::string& at) { checkAnimation(c, a, at); });
}

void checkNodeForest(const json& doc, const std::string& what)
{
    const auto fail = [&](const std::string& message) { throw Error(what + ": " + message); };
    const json empty = json::array();
    const json& nodes = doc.contains("nodes") ? doc["nodes"] : empty;
    constexpr std::size_t kNone = std::numeric_limits<std::size_t>::max();

    // Each node has at most one parent, and is not its own.
    std::vector<std::size_t> parent(nodes.size(), kNone);
    for (std::size_t p = 0; p < nodes.size(); ++p) {
        if (!nodes[p].contains("children"))
            continue;
        for (const json& entry : nodes[p]["children"]) {
            const auto child = entry.get<std::size_t>(); // checkIndices made it an index
            if (child == p)
                fail("node " + std::to_string(p) + " lists itself as a child");
            if (parent[child] == p)
                fail("node " + std::to_string(p) + " lists child " + std::to_string(child) + " twice");
            if (parent[child] != kNone)
                fail("node " + std::to_string(child) + " is a child of both node " + std::to_string(parent[child]) +
                     " and node " + std::to_string(p) + "; glTF nodes must form strict trees (one parent each)");
            parent[child] = p;
        }
    }

    // With one parent each, a node is in a tree when walking up reaches a node without a parent;
    // otherwise the walk comes back to itself: a cycle. Each node is walked over once.
    enum : unsigned char { kUnseen, kWalking, kRooted };
    std::vector<unsigned char> state(nodes.size(), kUnseen);
    std::vector<std::size_t> path;
    for (std::size_t start = 0; start < nodes.size(); ++start) {
        std::size_t n = start;
        while (n != kNone && state[n] == kUnseen) {
            state[n] = kWalking;
            path.push_back(n);
            n = parent[n];
        }
        if (n != kNone && state[n] == kWalking)
            fail("node " + std::to_string(n) + " is its own ancestor (a cycle in the node hierarchy)");
        for (std::size_t walked : path)
            state[walked] = kRooted;
        path.clear();
    }

    // Scene roots: root nodes, each once.
    if (!doc.contains("scenes"))
        return;
    const json& scenes = doc["scenes"];
    for (std::size_t s = 0; s < scenes.size(); ++s) {
        if (!scenes[s].contains("nodes"))
            continue;
        std::vector<bool> listed(nodes.size(), false);
        for (const json& entry : scenes[s]["nodes"]) {
            const auto root = entry.get<std::size_t>();
            if (parent[root] != kNone)
                fail("scene " + std::to_string(s) + " lists node " + std::to_string(root) + " as a root, but it is a child of node " +
                     std::to_string(parent[root]) + "; scene roots must be root nodes");
            if (listed[root])
                fail("scene " + std::to_string(s) + " lists root node " + std::to_string(root) + " twice");
            listed[root] = true;
        }
    }
}

} // namespace sightline::gltf
