#include "project/ProjectMotion.h"

#include <algorithm>

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

ProjectMotion parseProjectMotion(const Project& project, ProjectMotion::Kind kind, const std::string& what)
{
    return kind == ProjectMotion::Kind::Animation ? ProjectMotion::of(parseAnimation(project, what))
                                                  : ProjectMotion::of(parseRecordedPath(project, what));
}

} // namespace sightline
