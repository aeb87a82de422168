#include "editor/ObjectFlags.h"

#include <algorithm>

namespace sightline::ui {

using nlohmann::json;

namespace {

constexpr const char* kOwnKey = "editor";   // inside an occluder's entry

/// The list `editor[flag][group]` holds `entry`.
bool listed(const json& editor, const char* flag, const char* group, const json& entry)
{
    if (!editor.is_object())
        return false;
    const auto f = editor.find(flag);
    if (f == editor.end() || !f->is_object())
        return false;
    const auto g = f->find(group);
    return g != f->end() && g->is_array() && std::find(g->begin(), g->end(), entry) != g->end();
}

void setListed(json& editor, const char* flag, const char* group, const json& entry, bool on)
{
    if (!editor.is_object())
        editor = json::object();
    json& f = editor[flag];
    if (!f.is_object())
        f = json::object();
    json& g = f[group];
    if (!g.is_array())
        g = json::array();
    std::vector<json> entries;
    for (const json& e : g)
        if (e != entry)
            entries.push_back(e);
    if (on)
        entries.push_back(entry);
    std::sort(entries.begin(), entries.end());   // the same flags always write the same file
    g = entries;
    if (g.empty())
        f.erase(group);
    if (f.empty())
        editor.erase(flag);
}

/// The entry that names `object` in a list: the instance index, or "source" / "receiver".
std::pair<const char*, json> entryOf(ObjectRef object)
{
    switch (object.kind) {
    case ObjectKind::Source: return {"patches", "source"};
    case ObjectKind::Receiver: return {"patches", "receiver"};
    case ObjectKind::SceneObject: return {"instances", object.index};
    default: return {nullptr, nullptr};
    }
}

} // namespace

ObjectFlags occluderFlags(const OccluderSpec& occluder)
{
    const auto it = occluder.extra.find(kOwnKey);
    if (it == occluder.extra.end() || !it->is_object())
        return {};
    const auto flag = [&](const char* key) {
        const auto f = it->find(key);
        return f != it->end() && f->is_boolean() && f->get<bool>();
    };
    return {flag("hidden"), flag("locked")};
}

void setOccluderFlags(OccluderSpec& occluder, ObjectFlags flags)
{
    json& own = occluder.extra[kOwnKey];
    if (!own.is_object())
        own = json::object();
    const auto set = [&](const char* key, bool on) {
        if (on)
            own[key] = true;
        else
            own.erase(key);
    };
    set("hidden", flags.hidden);
    set("locked", flags.locked);
    if (own.empty())
        occluder.extra.erase(kOwnKey);
}

ObjectFlags settingsFlags(const json& editor, ObjectRef object)
{
    const auto [group, entry] = entryOf(object);
    if (!group)
        return {};
    return {listed(editor, "hidden", group, entry), listed(editor, "locked", group, entry)};
}

void setSettingsFlags(json& editor, ObjectRef object, ObjectFlags flags)
{
    const auto [group, entry] = entryOf(object);
    if (!group)
        return;
    setListed(editor, "hidden", group, entry, flags.hidden);
    setListed(editor, "locked", group, entry, flags.locked);
}

} // namespace sightline::ui
