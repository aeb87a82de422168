#include "project/Animation.h"

#include <algorithm>
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

#include "base/Error.h"

namespace sightline {

using nlohmann::json;

glm::dvec3 AnimationTrack::offsetAt(int frame) const
{
    if (keys.empty())
        return glm::dvec3(0.0);
    if (loop)
        frame %= keys.back().frame + 1;
    if (frame <= keys.front().frame)
        return keys.front().translate;
    if (frame >= keys.back().frame)
        return keys.back().translate;
    // The last key at or before `frame`, and the next one.
    const auto next = std::upper_bound(keys.begin(), keys.end(), frame,
                                       [](int f, const AnimationKey& key) { return f < key.frame; });
    const AnimationKey& k1 = *next;
    const AnimationKey& k0 = *(next - 1);
    if (step)
        return k0.translate;
    const double t = double(frame - k0.frame) / double(k1.frame - k0.frame);
    return k0.translate + t * (k1.translate - k0.translate);
}

int defaultFrameCount(const Animation& animation)
{
    if (animation.frames > 0)
        return animation.frames;
    int frames = 1;
    for (const AnimationTrack& track : animation.tracks)
        if (!track.keys.empty())
            frames = std::max(frames, track.keys.back().frame + 1);
    return frames;
}

bool Animation::movesOccluders() const
{
    return std::any_of(tracks.begin(), tracks.end(),
                       [](const AnimationTrack& t) { return t.target == AnimationTrack::Target::Occluder; });
}

namespace {

[[noreturn]] void fail(const std::string& what, const std::string& key, const std::string& problem)
{
    throw Error(what + ": '" + key + "' " + problem);
}

int integer(const json& value, const std::string& what, const std::string& key, int lo, int hi)
{
    if (!value.is_number_integer())
        fail(what, key, "must be an integer");
    const long long x = value.get<long long>();
    if (x < lo || x > hi)
        fail(what, key, "must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    return int(x);
}

AnimationTrack parseTrack(const Project& project, const json& object, const std::string& what, const std::string& key)
{
    if (!object.is_object())
        fail(what, key, "must be an object with target and keys");
    AnimationTrack track;
    const std::string target = object.value("target", std::string());
    if (target == "source")
        track.target = AnimationTrack::Target::Source;
    else if (target == "receiver")
        track.target = AnimationTrack::Target::Receiver;
    else if (target == "occluder")
        track.target = AnimationTrack::Target::Occluder;
    else
        fail(what, key + ".target", "must be \"source\", \"receiver\" or \"occluder\"");
    if (track.target == AnimationTrack::Target::Occluder) {
        if (!object.contains("name") || !object.at("name").is_string())
            fail(what, key + ".name", "must name one of the project's occluders");
        track.name = object.at("name").get<std::string>();
        const auto count = std::count_if(project.occluders.begin(), project.occluders.end(),
                                         [&](const OccluderSpec& o) { return o.name == track.name; });
        if (count != 1)
            fail(what, key + ".name", "'" + track.name + "' matches " + std::to_string(count) +
                                          " occluders; it must match exactly one");
    }
    const std::string interpolation = object.value("interpolation", std::string("linear"));
    if (interpolation != "linear" && interpolation != "step")
        fail(what, key + ".interpolation", "must be \"linear\" or \"step\"");
    track.step = interpolation == "step";
    if (object.contains("loop")) {
        if (!object.at("loop").is_boolean())
            fail(what, key + ".loop", "must be true or false");
        track.loop = object.at("loop").get<bool>();
    }
    if (!object.contains("keys") || !object.at("keys").is_array() || object.at("keys").empty())
        fail(what, key + ".keys", "must be a non-empty array of {frame, translate}");
    const json& keys = object.at("keys");
    for (std::size_t k = 0; k < keys.size(); ++k) {
        const std::string keyName = key + ".keys[" + std::to_string(k) + "]";
        if (!keys[k].is_object() || !keys[k].contains("frame") || !keys[k].contains("translate"))
            fail(what, keyName, "must be an object with frame and translate");
        AnimationKey animationKey;
        animationKey.frame = integer(keys[k].at("frame"), what, keyName + ".frame", 0, kMaxAnimationFrames);
        const json& t = keys[k].at("translate");
        if (!t.is_array() || t.size() != 3 || !t[0].is_number() || !t[1].is_number() || !t[2].is_number())
            fail(what, keyName + ".translate", "must be an array of 3 numbers");
        animationKey.translate = {t[0].get<double>(), t[1].get<double>(), t[2].get<double>()};
        if (!std::isfinite(animationKey.translate.x) || !std::isfinite(animationKey.translate.y) ||
            !std::isfinite(animationKey.translate.z))
            fail(what, keyName + ".translate", "must be finite");
        if (!track.keys.empty() && animationKey.frame <= track.keys.back().frame)
            fail(what, keyName + ".frame", "must be greater than the previous key's frame");
        track.keys.push_back(animationKey);
    }
    return track;
}

} // namespace

Animation parseAnimation(const Project& project, const std::string& what)
{
    Animation animation;
    if (!project.extra.contains("animation"))
        return animation;
    const json& object = project.extra.at("animation");
    if (!object.is_object())
        fail(what, "animation", "must be an object with frames and tracks");
    if (object.contains("frames"))
        animation.frames = integer(object.at("frames"), what, "animation.frames", 1, kMaxAnimationFrames);
    if (object.contains("tracks")) {
        const json& tracks = object.at("tracks");
        if (!tracks.is_array())
            fail(what, "animation.tracks", "must be an array");
        for (std::size_t k = 0; k < tracks.size(); ++k)
            animation.tracks.push_back(parseTrack(project, tracks[k], what, "animation.tracks[" + std::to_string(k) + "]"));
    }
    return animation;
}

Project projectAtFrame(const Project& project, const Animation& animation, int frame)
{
    Project moved = project;
    for (const AnimationTrack& track : animation.tracks) {
        const glm::dvec3 offset = track.offsetAt(frame);
        switch (track.target) {
        case AnimationTrack::Target::Source: moved.source.corner += offset; break;
        case AnimationTrack::Target::Receiver: moved.receiver.corner += offset; break;
        case AnimationTrack::Target::Occluder:
            for (OccluderSpec& spec : moved.occluders) {
                if (spec.name == track.name)
                    spec.transform = glm::translate(glm::mat4(1.0f), glm::vec3(offset)) * spec.transform;
            }
            break;
        }
    }
    return moved;
}

} // namespace sightline
