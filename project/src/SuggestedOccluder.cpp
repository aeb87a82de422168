#include "project/SuggestedOccluder.h"

#include <chrono>
#include <set>

#include <glm/gtc/matrix_transform.hpp>

#include "project/CoarseOccluders.h"
#include "project/LightingSetup.h"
#include "visibility/CpuBitmaskSampler.h"
#include "base/Error.h"

namespace sightline {

namespace {

/// Suggestions made before giving up, each after the exact sampler found a ray the last one should
/// have blocked: the margin four times wider each time (for a rectangle, every second time: the
/// other tries turn its diagonal).
constexpr int kAttempts = 5;

double millisecondsSince(std::chrono::steady_clock::time_point start)
{
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

HiddenSampleMap sampleExactly(const Scene& scene, const Patch& source, const Patch& receiver, const ReceiverHeights& heights,
                              int threads)
{
    const CpuBitmaskSampler sampler(scene);
    BitmaskOptions options;
    options.threads = threads;
    options.heights = heights.empty() ? nullptr : &heights;
    return sampler.sample(source, receiver, options);
}

glm::dvec3 inPlane(const suggest::SuggestPlane& plane, suggest::Point2 direction)
{
    return direction.x * plane.axisU + direction.y * plane.axisV;
}

} // namespace

glm::mat4 planeTransform(const suggest::SuggestPlane& plane, const suggest::Rect2& rect, bool otherDiagonal)
{
    // The same rectangle a quarter turn round: its sides swap, and the built-in's diagonal (from
    // its -x -z corner to its +x +z one) lands on the rectangle's other diagonal.
    suggest::Rect2 r = rect;
    if (otherDiagonal) {
        r.axis = {-rect.axis.y, rect.axis.x};
        std::swap(r.halfWidth, r.halfHeight);
    }
    const glm::dvec3 first = inPlane(plane, r.axis);
    const glm::dvec3 second = inPlane(plane, {-r.axis.y, r.axis.x});
    glm::dmat4 m(1.0);
    m[0] = glm::dvec4(2.0 * r.halfWidth * first, 0.0);
    m[1] = glm::dvec4(plane.normal, 0.0);
    // The plane's +z edge runs along -second: a rotation, not a mirror, and the same rectangle.
    m[2] = glm::dvec4(-2.0 * r.halfHeight * second, 0.0);
    m[3] = glm::dvec4(plane.world(r.centre), 1.0);
    return glm::mat4(m);
}

PlacedSuggestion placeSuggestion(const suggest::Suggestion& suggestion, const std::string& name, const std::string& meshFile,
                                 bool otherDiagonal)
{
    PlacedSuggestion placed;
    placed.spec.name = name;
    if (suggestion.shape == suggest::Shape::Rect) {
        placed.spec.mesh = "plane";
        placed.spec.transform = planeTransform(suggestion.plane, suggestion.rect, otherDiagonal);
        placed.mesh.addMeshInstance(builtinMesh("plane"));
    } else {
        const glm::dvec3 centre = suggest::suggestionCentre(suggestion);
        placed.spec.mesh = meshFile;
        placed.spec.transform = glm::translate(glm::mat4(1.0f), glm::vec3(centre));
        placed.mesh.addMeshInstance(suggest::suggestionMesh(suggestion, name, centre));
    }
    return placed;
}

std::vector<double> sourceLightWeights(const Project& project)
{
    const AreaLight light = projectLight(project, project.source, project.name);
    std::vector<double> weights(std::size_t(project.source.sampleCount()), 0.0);
    for (const LightGroup& group : light.groups) {
        const double w = (double(group.colour.r) + double(group.colour.g) + double(group.colour.b)) / 3.0;
        for (std::size_t i = 0; i < weights.size(); ++i)
            if ((group.mask[i / 64] >> (i % 64)) & 1u)
                weights[i] = w;
    }
    return weights;
}

std::string unusedOccluderName(const Project& project, const std::string& name)
{
    std::set<std::string> used;
    for (const OccluderSpec& spec : project.occluders)
        used.insert(spec.name);
    if (!used.contains(name))
        return name;
    for (int k = 2;; ++k)
        if (const std::string candidate = name + " " + std::to_string(k); !used.contains(candidate))
            return candidate;
}

SuggestedOccluder suggestForProject(const Project& project, const suggest::Request& request, const std::string& meshFile,
                                    int threads)
{
    const ReceiverHeights heights = validatedPairHeights(project);
    return suggestOnScene(buildRayScene(project), project.source, project.receiver, heights, request,
                          unusedOccluderName(project, "suggested occluder"), meshFile, threads);
}

SuggestedOccluder suggestOnScene(const Scene& scene, const Patch& source, const Patch& receiver,
                                 const ReceiverHeights& heights, const suggest::Request& request, const std::string& name,
                                 const std::string& meshFile, int threads)
{
    validatePatchPair(source, receiver);
    SuggestedOccluder result;
    auto start = std::chrono::steady_clock::now();
    const HiddenSampleMap before = sampleExactly(scene, source, receiver, heights, threads);
    result.sampleMs = millisecondsSince(start);

    suggest::Request attempt = request;
    for (result.attempts = 1;; ++result.attempts) {
        start = std::chrono::steady_clock::now();
        result.suggestion = suggest::suggestOccluder(source, receiver, heights, before, attempt);
        result.suggestMs = millisecondsSince(start);

        // A rectangle's second try turns the built-in plane so that its inner diagonal, where a
        // crossing is a tie, runs the other way; later tries widen the margin.
        PlacedSuggestion placed = placeSuggestion(result.suggestion, name, meshFile, result.attempts % 2 == 0);
        result.spec = std::move(placed.spec);
        result.mesh = std::move(placed.mesh);
        Scene with = scene;
        appendOccluder(with, result.mesh, result.spec);
        start = std::chrono::steady_clock::now();
        const HiddenSampleMap after = sampleExactly(with, source, receiver, heights, threads);
        result.unblockedAfter = after.rayCount() - after.blockedCount();
        const suggest::Suggestion& s = result.suggestion;
        if (s.weighted)
            result.lightAfter = suggest::unblockedLight(after, request.sourceWeights);
        result.checkMs = millisecondsSince(start);
        // Weighted, the light left too: at most what the rays it was built around did not carry.
        const bool lightKept = !s.weighted || result.lightAfter <= (s.lightBefore - s.lightEnclosed) * (1.0 + 1e-9) + 1e-12;
        if (result.unblockedAfter <= s.promised && lightKept)
            return result;
        if (result.attempts == kAttempts)
            throw Error("the suggested occluder leaves " + std::to_string(result.unblockedAfter) +
                        " rays unblocked, more than the " + std::to_string(result.suggestion.promised) +
                        " promised, even after " + std::to_string(result.attempts) +
                        " tries with wider margins (please report this pair)");
        if (request.shape == suggest::Shape::Convex || result.attempts % 2 == 0)
            attempt.marginScale *= 4.0;
    }
}

} // namespace sightline
