#include "project/RecordedPath.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

#include "base/Error.h"

namespace sightline {

using nlohmann::json;

namespace {

[[noreturn]] void fail(const std::string& what, const std::string& key, const std::string& problem)
{
    throw Error(what + ": '" + key + "' " + problem);
}

double number(const json& object, const char* field, const std::string& what, const std::string& key)
{
    if (!object.contains(field) || !object.at(field).is_number())
        fail(what, key + "." + field, "must be a number");
    const double x = object.at(field).get<double>();
    if (!std::isfinite(x))
        fail(what, key + "." + field, "must be finite");
    return x;
}

glm::dvec3 vec3(const json& object, const char* field, const std::string& what, const std::string& key)
{
    const std::string name = key + "." + field;
    if (!object.contains(field))
        fail(what, name, "is missing");
    const json& a = object.at(field);
    if (!a.is_array() || a.size() != 3 || !a[0].is_number() || !a[1].is_number() || !a[2].is_number())
        fail(what, name, "must be an array of 3 numbers");
    const glm::dvec3 v{a[0].get<double>(), a[1].get<double>(), a[2].get<double>()};
    if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z))
        fail(what, name, "must be finite");
    return v;
}

int frameOf(const json& object, const std::string& what, const std::string& key, int frames)
{
    if (!object.contains("frame") || !object.at("frame").is_number_integer())
        fail(what, key + ".frame", "must be an integer");
    const long long f = object.at("frame").get<long long>();
    if (f < 0 || f >= frames)
        fail(what, key + ".frame", "must be in [0, frames) = [0, " + std::to_string(frames) + ")");
    return int(f);
}

json vec3Json(const glm::dvec3& v) { return json::array({v.x, v.y, v.z}); }

/// Which object an edit moves, for "its last key": patches by kind, occluders by index.
std::pair<int, std::size_t> objectId(const PathEdit& e) { return {int(e.object), e.index}; }

} // namespace

std::optional<PathCamera> RecordedPath::cameraAt(int frame) const
{
    if (camera.empty())
        return std::nullopt;
    const auto next = std::upper_bound(camera.begin(), camera.end(), frame,
                                       [](int f, const PathCameraKey& key) { return f < key.frame; });
    return next == camera.begin() ? camera.front().camera : (next - 1)->camera;
}

int RecordedPath::frameAtTime(double seconds) const
{
    if (frames <= 0)
        return 0;
    // A small slack so that k / fps maps back to k despite rounding.
    const double f = std::floor(seconds * fps + 1e-6);
    return int(std::clamp(f, 0.0, double(frames - 1)));
}

namespace {

/// The array under `field` of a recorded path: absent is empty; not an array, or longer than
/// kMaxPathKeys, is refused naming it.
const json* keyArray(const json& object, const char* field, const char* contents, const std::string& what, const std::string& root)
{
    if (!object.contains(field))
        return nullptr;
    const json& keys = object.at(field);
    const std::string name = root + "." + field;
    if (!keys.is_array())
        fail(what, name, std::string("must be an array of ") + contents);
    if (keys.size() > kMaxPathKeys)
        fail(what, name, "has " + std::to_string(keys.size()) + " keys; at most " + std::to_string(kMaxPathKeys) + " are read");
    return &keys;
}

PathCameraKey cameraKey(const json& k, const std::string& what, const std::string& key, int frames)
{
    if (!k.is_object())
        fail(what, key, "must be an object with frame, target, distance, yaw, pitch and fov_y");
    PathCameraKey cam;
    cam.frame = frameOf(k, what, key, frames);
    cam.camera.target = vec3(k, "target", what, key);
    cam.camera.distance = number(k, "distance", what, key);
    cam.camera.yaw = number(k, "yaw", what, key);
    cam.camera.pitch = number(k, "pitch", what, key);
    cam.camera.fovY = number(k, "fov_y", what, key);
    if (const auto flag = k.find("orthographic"); flag != k.end()) {
        if (!flag->is_boolean())
            fail(what, key + ".orthographic", "must be true or false");
        cam.camera.orthographic = flag->get<bool>();
    }
    if (!(cam.camera.distance > 0.0))
        fail(what, key + ".distance", "must be positive");
    if (!(std::abs(cam.camera.pitch) < 1.5708))
        fail(what, key + ".pitch", "must be in (-pi/2, pi/2)");
    if (!(cam.camera.fovY > 0.05 && cam.camera.fovY < 3.0))
        fail(what, key + ".fov_y", "must be in (0.05, 3) radians");
    return cam;
}

/// An occluder's edit: its index, name and affine transform.
void occluderEdit(const json& k, const std::string& what, const std::string& key, PathEdit& edit)
{
    edit.object = PathEdit::Object::Occluder;
    const json& index = k.value("index", json());
    if (!index.is_number_unsigned())
        fail(what, key + ".index", "must be an occluder's index (an integer >= 0)");
    edit.index = index.get<std::size_t>();
    if (!k.contains("name") || !k.at("name").is_string())
        fail(what, key + ".name", "must be the occluder's name");
    edit.name = k.at("name").get<std::string>();
    const json& m = k.value("transform", json());
    if (!m.is_array() || m.size() != 16)
        fail(what, key + ".transform", "must be an array of 16 numbers (column-major)");
    for (int i = 0; i < 16; ++i) {
        if (!m[std::size_t(i)].is_number() || !std::isfinite(m[std::size_t(i)].get<double>()))
            fail(what, key + ".transform", "must be an array of 16 finite numbers");
        edit.transform[i / 4][i % 4] = m[std::size_t(i)].get<float>();
    }
    // Occluders move rigidly or scale; a projective last row would warp them.
    if (edit.transform[0][3] != 0.0f || edit.transform[1][3] != 0.0f || edit.transform[2][3] != 0.0f ||
        edit.transform[3][3] != 1.0f)
        fail(what, key + ".transform", "must be affine: its last row (elements 3, 7, 11, 15) must be 0, 0, 0, 1");
}

PathEdit pathEdit(const json& k, const std::string& what, const std::string& key, int frames)
{
    if (!k.is_object())
        fail(what, key, "must be an object with frame and object");
    PathEdit edit;
    edit.frame = frameOf(k, what, key, frames);
    const std::string kind = k.value("object", std::string());
    if (kind == "source" || kind == "receiver") {
        edit.object = kind == "source" ? PathEdit::Object::Source : PathEdit::Object::Receiver;
        edit.patch.corner = vec3(k, "corner", what, key);
        edit.patch.u = vec3(k, "u", what, key);
        edit.patch.v = vec3(k, "v", what, key);
    } else if (kind == "occluder") {
        occluderEdit(k, what, key, edit);
    } else {
        fail(what, key + ".object", "must be \"source\", \"receiver\" or \"occluder\"");
    }
    return edit;
}

} // namespace

RecordedPath parseRecordedPath(const Project& project, const std::string& what)
{
    RecordedPath path;
    const auto it = project.extra.find(kRecordedPathKey);
    if (it == project.extra.end())
        return path;
    const json& object = *it;
    const std::string root = kRecordedPathKey;
    if (!object.is_object())
        fail(what, root, "must be an object with fps, frames, camera and edits");
    path.fps = number(object, "fps", what, root);
    if (!(path.fps > 0.0) || path.fps > 1000.0)
        fail(what, root + ".fps", "must be in (0, 1000]");
    if (!object.contains("frames") || !object.at("frames").is_number_integer())
        fail(what, root + ".frames", "must be an integer");
    const long long frames = object.at("frames").get<long long>();
    if (frames < 1 || frames > kMaxRecordedFrames)
        fail(what, root + ".frames", "must be in [1, " + std::to_string(kMaxRecordedFrames) + "]");
    path.frames = int(frames);

    if (const json* keys = keyArray(object, "camera", "camera keys", what, root))
        for (std::size_t k = 0; k < keys->size(); ++k) {
            const std::string key = root + ".camera[" + std::to_string(k) + "]";
            const PathCameraKey cam = cameraKey((*keys)[k], what, key, path.frames);
            if (!path.camera.empty() && cam.frame <= path.camera.back().frame)
                fail(what, key + ".frame", "must be greater than the previous key's frame");
            path.camera.push_back(cam);
        }
    if (const json* keys = keyArray(object, "edits", "edit keys", what, root))
        for (std::size_t k = 0; k < keys->size(); ++k) {
            const std::string key = root + ".edits[" + std::to_string(k) + "]";
            const PathEdit edit = pathEdit((*keys)[k], what, key, path.frames);
            if (!path.edits.empty() && edit.frame < path.edits.back().frame)
                fail(what, key + ".frame", "must not be less than the previous edit's frame");
            path.edits.push_back(edit);
        }
    return path;
}

json toJson(const RecordedPath& path)
{
    json camera = json::array();
    for (const PathCameraKey& key : path.camera) {
        camera.push_back({{"frame", key.frame}, {"target", vec3Json(key.camera.target)}, {"distance", key.camera.distance},
                          {"yaw", key.camera.yaw}, {"pitch", key.camera.pitch}, {"fov_y", key.camera.fovY}});
        if (key.camera.orthographic)
            camera.back()["orthographic"] = true;
    }
    json edits = json::array();
    for (const PathEdit& e : path.edits) {
        json key = {{"frame", e.frame}};
        if (e.object == PathEdit::Object::Occluder) {
            key["object"] = "occluder";
            key["index"] = e.index;
            key["name"] = e.name;
            json m = json::array();
            for (int i = 0; i < 16; ++i)
                m.push_back(double(e.transform[i / 4][i % 4]));
            key["transform"] = std::move(m);
        } else {
            key["object"] = e.object == PathEdit::Object::Source ? "source" : "receiver";
            key["corner"] = vec3Json(e.patch.corner);
            key["u"] = vec3Json(e.patch.u);
            key["v"] = vec3Json(e.patch.v);
        }
        edits.push_back(std::move(key));
    }
    return {{"fps", path.fps}, {"frames", path.frames}, {"camera", std::move(camera)}, {"edits", std::move(edits)}};
}

void setRecordedPath(Project& project, const RecordedPath& path)
{
    if (path.empty())
        project.extra.erase(kRecordedPathKey);
    else
        project.extra[kRecordedPathKey] = toJson(path);
}

Project projectAtPathFrame(const Project& project, const RecordedPath& path, int frame)
{
    // Per object, its last edit at or before `frame`, else its first one.
    std::map<std::pair<int, std::size_t>, const PathEdit*> state;
    for (const PathEdit& e : path.edits) {
        auto [it, inserted] = state.try_emplace(objectId(e), &e);
        if (!inserted && e.frame <= frame)
            it->second = &e;
    }
    Project moved = project;
    for (const auto& [id, edit] : state) {
        switch (edit->object) {
        case PathEdit::Object::Source:
        case PathEdit::Object::Receiver: {
            Patch& patch = edit->object == PathEdit::Object::Source ? moved.source : moved.receiver;
            patch.corner = edit->patch.corner;
            patch.u = edit->patch.u;
            patch.v = edit->patch.v;
            break;
        }
        case PathEdit::Object::Occluder:
            if (edit->index < moved.occluders.size() && moved.occluders[edit->index].name == edit->name)
                moved.occluders[edit->index].transform = edit->transform;
            break;
        }
    }
    return moved;
}

} // namespace sightline
