#include "project/ProjectMotion.h"

#include <algorithm>
#include <string>

#include "base/Error.h"
#include "visibility/Patch.h"

namespace sightline {

ProjectMotion ProjectMotion::of(Animation animation)
{
    ProjectMotion motion;
    motion.kind = Kind::Animation;
    motion.animation = std::move(animation);
    return motion;
}

ProjectMotion ProjectMotion::of(RecordedPath path)
{
    ProjectMotion motion;
    motion.kind = Kind::RecordedPath;
    motion.path = std::move(path);
    return motion;
}

bool ProjectMotion::empty() const { return kind == Kind::Animation ? animation.empty() : path.empty(); }

int ProjectMotion::defaultFrames() const
{
    if (kind == Kind::Animation)
        return defaultFrameCount(animation);
    return std::max(path.frames, 1);
}

Project ProjectMotion::at(const Project& project, int frame) const
{
    return kind == Kind::Animation ? projectAtFrame(project, animation, frame) : projectAtPathFrame(project, path, frame);
}

bool ProjectMotion::mayChangeAt(int frame) const
{
    if (kind == Kind::Animation || frame <= 0)
        return true;
    // Edits are in non-decreasing frame order; frames past the end hold the last one.
    const auto key = std::lower_bound(path.edits.begin(), path.edits.end(), frame,
                                      [](const PathEdit& edit, int f) { return edit.frame < f; });
    return key != path.edits.end() && key->frame == frame;
}

std::string ProjectMotion::name() const { return kind == Kind::Animation ? "animation" : "recorded path"; }

Project withoutMotionKeys(Project project)
{
    project.extra.erase("animation");
    project.extra.erase(kRecordedPathKey);
    return project;
}

void validateMotionFrames(const Project& base, const ProjectMotion& motion, int frames)
{
    const auto check = [&](int f, const Patch& source, const Patch& receiver) {
        try {
            validatePatchPair(source, receiver);
        } catch (const Error& e) {
            throw Error(frames > 1 ? "frame " + std::to_string(f) + ": " + e.what() : std::string(e.what()));
        }
    };
    if (motion.kind == ProjectMotion::Kind::Animation) {
        for (int f = 0; f < frames; ++f) {
            const Project frame = motion.at(base, f);
            check(f, frame.source, frame.receiver);
            if (motion.empty())
                return;   // every frame is the project itself
        }
        return;
    }
    // A path in one pass over its edits (projectAtPathFrame per frame would be quadratic in them):
    // the patches start at their first edit, and each frame with edits applies them in order, so
    // that the state checked at frame f is projectAtPathFrame's.
    Patch source = base.source, receiver = base.receiver;
    const auto apply = [&](const PathEdit& edit) {
        if (edit.object == PathEdit::Object::Occluder)
            return;
        Patch& patch = edit.object == PathEdit::Object::Source ? source : receiver;
        patch.corner = edit.patch.corner;
        patch.u = edit.patch.u;
        patch.v = edit.patch.v;
    };
    const std::vector<PathEdit>& edits = motion.path.edits;
    for (const PathEdit::Object object : {PathEdit::Object::Source, PathEdit::Object::Receiver}) {
        const auto first = std::find_if(edits.begin(), edits.end(), [&](const PathEdit& e) { return e.object == object; });
        if (first != edits.end())
            apply(*first);
    }
    std::size_t k = 0;
    for (int f = 0; f < frames; ) {
        while (k < edits.size() && edits[k].frame <= f)
            apply(edits[k++]);
        check(f, source, receiver);
        if (k == edits.size())
            return;
        f = edits[k].frame;
    }
}

ProjectMotion parseProjectMotion(const Project& project, ProjectMotion::Kind kind, const std::string& what)
{
    return kind == ProjectMotion::Kind::Animation ? ProjectMotion::of(parseAnimation(project, what))
                                                  : ProjectMotion::of(parseRecordedPath(project, what));
}

} // namespace sightline
