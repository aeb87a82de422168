#pragma once
// `sightline-cli suggest` and the editor's occluder assistant on a project (docs/design.md §4):
// samples the pair exactly, suggests the occluder (visibility/suggest/OccluderSuggestion.h),
// inserts it as the project will load it and samples again, so the count it reports is the exact
// sampler's answer on the saved file, not a promise.

#include <cstdint>
#include <filesystem>
#include <string>

#include "project/Project.h"
#include "visibility/suggest/OccluderSuggestion.h"

namespace sightline {

struct SuggestedOccluder {
    suggest::Suggestion suggestion;
    /// As the project will hold it: the built-in "plane" placed by a transform (a rectangle), or
    /// the mesh file named by the caller with the identity transform (a convex polygon).
    OccluderSpec spec;
    Scene mesh;                        ///< the occluder's mesh in object space, as `spec` loads it
    std::uint64_t unblockedAfter = 0;  ///< by the exact sampler with the occluder inserted
    double lightAfter = 0.0;           ///< with the request's source weights: their unblocked sum after
    int attempts = 1;                  ///< suggestions made (another diagonal or a wider margin after a tie went the other way)
    double sampleMs = 0.0;             ///< the pair sampled before, exactly
    double suggestMs = 0.0;            ///< the shape chosen
    double checkMs = 0.0;              ///< the pair sampled again with it inserted
};

/// For `project`'s pair as it is now. `meshFile` is what a convex occluder's spec names (a path
/// relative to the folder the project will be saved in). Throws sightline::Error: an invalid pair,
/// nothing unblocked, a share the plane cannot block, or (never expected) a suggestion that still
/// leaves more than it promised after the margin was widened.
SuggestedOccluder suggestForProject(const Project& project, const suggest::Request& request, const std::string& meshFile,
                                    int threads = 0);

/// The same on a scene already built (the level and every occluder placed), for the occluder
/// `name`: what suggestForProject does after loading, and what the editor calls on its scene.
SuggestedOccluder suggestOnScene(const Scene& scene, const Patch& source, const Patch& receiver,
                                 const ReceiverHeights& heights, const suggest::Request& request, const std::string& name,
                                 const std::string& meshFile, int threads = 0);

/// The suggestion as the project will hold it, named `name`: the built-in "plane" placed on the
/// rectangle (Shape::Rect), or the mesh file `meshFile` holding the polygon around its centre,
/// placed there by a translation (Shape::Convex: the gizmo's pivot is then the occluder's middle).
struct PlacedSuggestion {
    OccluderSpec spec;
    Scene mesh;   ///< what `spec.mesh` loads: the built-in plane, or the polygon's mesh to write
};
/// The light each source sample of `project`'s pair carries (its light's colour, mean of the
/// channels; white: 1): a suggestion's importance weights (suggest::Request::sourceWeights).
std::vector<double> sourceLightWeights(const Project& project);

/// `otherDiagonal`: a rectangle's built-in plane turned a quarter so that its two triangles meet on
/// the rectangle's other diagonal.
PlacedSuggestion placeSuggestion(const suggest::Suggestion& suggestion, const std::string& name, const std::string& meshFile,
                                 bool otherDiagonal = false);

/// `name` when no occluder of `project` has it, else "name 2", "name 3", ...
std::string unusedOccluderName(const Project& project, const std::string& name);

/// The built-in plane's transform that places it on `rect` of `plane` (columns: the rectangle's
/// first side, the plane's normal, its second side reversed, its centre), or with the rectangle
/// taken a quarter turn round (`otherDiagonal`: the same rectangle, the other inner diagonal).
glm::mat4 planeTransform(const suggest::SuggestPlane& plane, const suggest::Rect2& rect, bool otherDiagonal = false);

} // namespace sightline
