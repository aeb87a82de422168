#include "visibility/suggest/OccluderSuggestion.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <optional>

#include <glm/geometric.hpp>

#include "base/Error.h"
#include "visibility/suggest/ShareTrimming.h"

namespace sightline::suggest {

namespace {

/// docs/design.md §2: a segment passing within this of a triangle's edge, or meeting it within
/// this of its own ends, is a tie.
constexpr double kTieDistance = 1e-5;
/// Directions of the support lines that trim a convex polygon to a share (ShareTrimming.h).
constexpr int kConvexTrimDirections = 64;
/// Orientations tried for a rectangle trimmed to a share, over a quarter turn.
constexpr int kRectTrimOrientations = 16;
/// The most unblocked rays a share below 1 chooses among (their crossings are held: about 21 bytes each).
constexpr std::uint64_t kMaxTrimmedRays = std::uint64_t(1) << 24;

/// Calls visit(point in the plane, ray, |cos| between the ray and the plane's normal) for every
/// unblocked ray of `map` that crosses `plane` (see crossUnblockedRays).
template <typename Visit>
void visitCrossings(const Patch& source, const Patch& receiver, const ReceiverHeights& heights, const HiddenSampleMap& map,
                    const SuggestPlane& plane, Visit&& visit)
{
    const int sources = source.sampleCount(), receivers = receiver.sampleCount();
    std::vector<glm::dvec3> sourceAt(std::size_t(sources), glm::dvec3{0.0});
    std::vector<double> sourceSide(std::size_t(sources), 0.0);
    for (int i = 0; i < sources; ++i) {
        sourceAt[std::size_t(i)] = source.sample(i) - plane.origin;
        sourceSide[std::size_t(i)] = glm::dot(plane.normal, sourceAt[std::size_t(i)]);
    }
    for (int j = 0; j < receivers; ++j) {
        const glm::dvec3 r = displacedReceiverSample(source, receiver, heights, j) - plane.origin;
        const double receiverSide = glm::dot(plane.normal, r);
        for (int i = 0; i < sources; ++i) {
            if (map.blocked(j, i))
                continue;
            const double s = sourceSide[std::size_t(i)];
            if (!((s < 0.0 && receiverSide > 0.0) || (s > 0.0 && receiverSide < 0.0)))
                continue;
            const glm::dvec3 along = r - sourceAt[std::size_t(i)];
            const double length = glm::length(along);
            const double t = s / (s - receiverSide);
            // An occluder meeting the segment within the tie distance of an end may go either way.
            if (t * length <= 2.0 * kTieDistance || (1.0 - t) * length <= 2.0 * kTieDistance)
                continue;
            const glm::dvec3 x = sourceAt[std::size_t(i)] + t * along;
            visit(Point2{glm::dot(plane.axisU, x), glm::dot(plane.axisV, x)},
                  std::uint64_t(j) * std::uint64_t(sources) + std::uint64_t(i), std::abs(receiverSide - s) / length);
        }
    }
}

std::string shareText(double share)
{
    char text[32];
    std::snprintf(text, sizeof text, "%.6g", share);
    return text;
}

/// The crossings kept (flags over all crossings) and the shape built on them.
struct Shaped {
    std::vector<char> keep;
    std::size_t kept = 0;
    std::vector<Point2> hull;
    Rect2 rect;
};

Shaped shapedOn(const std::vector<Point2>& points, std::vector<char> keep)
{
    Shaped shaped;
    std::vector<Point2> kept;
    for (std::size_t i = 0; i < points.size(); ++i)
        if (keep[i])
            kept.push_back(points[i]);
    shaped.keep = std::move(keep);
    shaped.kept = kept.size();
    shaped.hull = convexHull(std::move(kept));
    shaped.rect = minAreaRect(shaped.hull);
    return shaped;
}

/// Which crossings to keep: at least `keep` of them, or with `weights`, crossings weighing at least
/// `keepWeight`.
struct Keep {
    std::size_t count = 0;
    std::span<const double> weights;
    double weight = 0.0;

    bool all(std::size_t points) const { return weights.empty() && count >= points; }
    std::vector<char> trim(const std::vector<Point2>& points, std::span<const Point2> directions) const
    {
        return weights.empty() ? trimToShare(points, count, directions) : trimToWeight(points, weights, weight, directions);
    }
};

Shaped convexShape(const std::vector<Point2>& points, const Keep& keep)
{
    return shapedOn(points, keep.trim(points, evenDirections(kConvexTrimDirections)));
}

Shaped rectShape(const std::vector<Point2>& points, const Keep& keep)
{
    Shaped best = shapedOn(points, std::vector<char>(points.size(), 1));
    if (keep.all(points.size()))
        return best;
    // The full set's best orientation and an even spread of others, each trimmed as a box.
    std::vector<double> angles{std::atan2(best.rect.axis.y, best.rect.axis.x)};
    for (int k = 0; k < kRectTrimOrientations; ++k)
        angles.push_back(0.5 * std::numbers::pi * k / kRectTrimOrientations);
    best.rect.halfWidth = best.rect.halfHeight = std::numeric_limits<double>::infinity();
    for (const double angle : angles) {
        Shaped shaped = shapedOn(points, keep.trim(points, evenDirections(4, angle)));
        if (shaped.rect.area() < best.rect.area())
            best = std::move(shaped);
    }
    return best;
}

/// The hull of every crossing (share 1), in time and memory that follow the receiver samples
/// rather than the rays. From one receiver sample R the crossings are the central projection from
/// R of the source samples onto the plane, a projective map that keeps lines and convexity on the
/// source's side; so the crossings of one source row lie between those of its first and last
/// crossing sample, and the row's two ends are all the hull needs. So are they for the least
/// |cos| between a ray and the plane's normal (the margin's): along the row's segment between
/// them |cos| is quasi-concave in the source point (an affine function, positive there, over a
/// convex one), so its least value over the samples between is at one of the two.
struct StreamedHull {
    std::vector<Point2> points;
    std::uint64_t crossing = 0;
    double smallestCosine = 1.0;
};

StreamedHull hullOfAllCrossings(const Patch& source, const Patch& receiver, const ReceiverHeights& heights,
                                const HiddenSampleMap& map, const SuggestPlane& plane)
{
    constexpr std::size_t kChunk = std::size_t(1) << 20;
    const int sources = source.sampleCount(), na = source.na;
    std::vector<glm::dvec3> sourceAt(static_cast<std::size_t>(sources));
    std::vector<double> sourceSide(static_cast<std::size_t>(sources));
    // Sources by side of the plane, and those within the tie band of it (checked one by one).
    std::vector<std::uint64_t> negative(std::size_t(map.wordsPerRow()), 0), positive = negative, nearPlane = negative;
    for (int i = 0; i < sources; ++i) {
        sourceAt[std::size_t(i)] = source.sample(i) - plane.origin;
        const double side = sourceSide[std::size_t(i)] = glm::dot(plane.normal, sourceAt[std::size_t(i)]);
        const std::uint64_t bit = std::uint64_t(1) << (i & 63);
        (side < 0.0 ? negative : side > 0.0 ? positive : nearPlane)[std::size_t(i >> 6)] |= bit;
        if (std::abs(side) <= 2.0 * kTieDistance)
            nearPlane[std::size_t(i >> 6)] |= bit;
    }
    StreamedHull streamed;
    std::vector<std::uint64_t> crossing(std::size_t(map.wordsPerRow()));
    const auto cross = [&](int i, const glm::dvec3& r, double receiverSide, bool check) -> std::optional<Point2> {
        const double s = sourceSide[std::size_t(i)];
        const glm::dvec3 along = r - sourceAt[std::size_t(i)];
        const double length = glm::length(along);
        const double t = s / (s - receiverSide);
        if (check && (t * length <= 2.0 * kTieDistance || (1.0 - t) * length <= 2.0 * kTieDistance))
            return std::nullopt;
        const glm::dvec3 x = sourceAt[std::size_t(i)] + t * along;
        return Point2{glm::dot(plane.axisU, x), glm::dot(plane.axisV, x)};
    };
    for (int j = 0; j < receiver.sampleCount(); ++j) {
        const glm::dvec3 r = displacedReceiverSample(source, receiver, heights, j) - plane.origin;
        const double receiverSide = glm::dot(plane.normal, r);
        if (receiverSide == 0.0)
            continue;
        const std::vector<std::uint64_t>& opposite = receiverSide > 0.0 ? negative : positive;
        const bool nearReceiver = std::abs(receiverSide) <= 2.0 * kTieDistance;   // every ray checked
        const auto blocked = map.row(j);
        bool any = false;
        for (std::size_t w = 0; w < crossing.size(); ++w) {
            crossing[w] = ~blocked[w] & opposite[w];
            std::uint64_t check = nearReceiver ? crossing[w] : crossing[w] & nearPlane[w];
            while (check) {   // the few rays that may meet the plane within the tie band of an end
                const int i = int(w * 64) + std::countr_zero(check);
                check &= check - 1;
                if (!cross(i, r, receiverSide, true))
                    crossing[w] &= ~(std::uint64_t(1) << (i & 63));
            }
            streamed.crossing += std::uint64_t(std::popcount(crossing[w]));
            any = any || crossing[w] != 0;
        }
        if (!any)
            continue;
        for (int b = 0; b < source.nb; ++b) {   // each source row's first and last crossing sample
            int first = -1, last = -1;
            for (int i = b * na; i < (b + 1) * na; ++i) {
                if ((i & 63) == 0 && i + 64 <= (b + 1) * na && crossing[std::size_t(i >> 6)] == 0) {
                    i += 63;   // a whole empty word
                    continue;
                }
                if ((crossing[std::size_t(i >> 6)] >> (i & 63)) & 1) {
                    first = first < 0 ? i : first;
                    last = i;
                }
            }
            if (first < 0)
                continue;
            streamed.points.push_back(*cross(first, r, receiverSide, false));
            if (last != first)
                streamed.points.push_back(*cross(last, r, receiverSide, false));
            for (const int i : {first, last}) {
                const glm::dvec3 d = r - sourceAt[std::size_t(i)];
                streamed.smallestCosine = std::min(streamed.smallestCosine, std::abs(glm::dot(plane.normal, d)) / glm::length(d));
            }
        }
        if (streamed.points.size() >= kChunk)
            streamed.points = convexHull(std::move(streamed.points));
    }
    return streamed;
}

} // namespace

Shape parseShape(const std::string& name)
{
    if (name == "convex")
        return Shape::Convex;
    if (name == "rect")
        return Shape::Rect;
    throw Error("unknown shape '" + name + "': use convex (a convex polygon) or rect (a rectangle)");
}

const char* shapeName(Shape shape)
{
    return shape == Shape::Convex ? "convex" : "rect";
}

namespace {

/// A plane through `origin` with unit `normal`, and any frame in it: axisU from the world axis
/// least aligned with the normal.
SuggestPlane planeWithFrame(const glm::dvec3& origin, const glm::dvec3& normal)
{
    SuggestPlane plane;
    plane.origin = origin;
    plane.normal = normal;
    const glm::dvec3 n = normal;
    const glm::dvec3 seed = std::abs(n.x) <= std::abs(n.y) && std::abs(n.x) <= std::abs(n.z) ? glm::dvec3{1, 0, 0}
                            : std::abs(n.y) <= std::abs(n.z)                                 ? glm::dvec3{0, 1, 0}
                                                                                              : glm::dvec3{0, 0, 1};
    plane.axisU = glm::normalize(seed - glm::dot(seed, n) * n);
    plane.axisV = glm::cross(n, plane.axisU);
    return plane;
}

void checkSurface(const PickedSurface& surface)
{
    const auto finite3 = [](const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); };
    const bool finite = finite3(surface.point) && finite3(surface.normal);
    if (!finite || !(glm::length(surface.normal) > 1e-12))
        throw Error("a picked surface needs a finite point and a non-zero normal");
}

} // namespace

SuggestPlane suggestPlane(const Patch& source, const Patch& receiver, double depth)
{
    if (!(depth > 0.0 && depth < 1.0))
        throw Error("depth must lie strictly between 0 (the source) and 1 (the receiver), got " + shareText(depth));
    const glm::dvec3 from = source.centre(), to = receiver.centre();
    const glm::dvec3 line = to - from;
    const double length = glm::length(line);
    if (!(length > 0.0))
        throw Error("the source and receiver patches share their centre: no plane lies between them");
    return planeWithFrame(from + depth * line, line / length);
}

SuggestPlane surfacePlane(const Patch& source, const Patch& receiver, const PickedSurface& surface)
{
    checkSurface(surface);
    const glm::dvec3 from = source.centre(), to = receiver.centre();
    glm::dvec3 n = glm::normalize(surface.normal);
    if (glm::dot(n, to - from) < 0.0)
        n = -n;
    // Both centres strictly apart from the plane, on its two sides: the rays between the patches
    // cross it (those that do are the ones it can block).
    if (!(glm::dot(n, from - surface.point) < -kTieDistance && glm::dot(n, to - surface.point) > kTieDistance))
        throw Error("the picked surface's plane does not pass between the patches' centres: pick a surface that "
                    "stands between them (a doorway's frame, a window's wall)");
    return planeWithFrame(surface.point, n);
}

RayCrossings crossUnblockedRays(const Patch& source, const Patch& receiver, const ReceiverHeights& heights,
                                const HiddenSampleMap& map, const SuggestPlane& plane)
{
    RayCrossings crossings;
    crossings.unblocked = map.rayCount() - map.blockedCount();
    visitCrossings(source, receiver, heights, map, plane, [&](Point2 p, std::uint64_t ray, double cosine) {
        crossings.points.push_back(p);
        crossings.cosines.push_back(float(cosine));
        crossings.rays.push_back(ray);
    });
    return crossings;
}

std::vector<glm::dvec3> Suggestion::worldPolygon() const
{
    std::vector<glm::dvec3> corners;
    for (const Point2& p : polygon)
        corners.push_back(plane.world(p));
    return corners;
}

void validateRequest(const Request& request)
{
    if (request.surface)
        checkSurface(*request.surface);
    else if (!(request.depth > 0.0 && request.depth < 1.0))
        throw Error("depth must lie strictly between 0 (the source) and 1 (the receiver), got " + shareText(request.depth));
    if (!(request.share > 0.0 && request.share <= 1.0))
        throw Error("share must lie in (0, 1], got " + shareText(request.share));
}

double unblockedLight(const HiddenSampleMap& map, std::span<const double> sourceWeights)
{
    if (sourceWeights.size() != std::size_t(map.sourceCount()))
        throw Error("the light's weights are for " + std::to_string(sourceWeights.size()) + " source samples, the pair has " +
                    std::to_string(map.sourceCount()));
    double light = 0.0;
    for (int j = 0; j < map.receiverCount(); ++j)
        for (int i = 0; i < map.sourceCount(); ++i)
            if (!map.blocked(j, i))
                light += sourceWeights[std::size_t(i)];
    return light;
}

namespace {

/// The light each crossing carries; fills `result`'s light before and required. Throws when no
/// light passes, or the crossings carry less than the share asks.
std::vector<double> crossingLight(const HiddenSampleMap& map, const RayCrossings& crossings, const Request& request,
                                  Suggestion& result)
{
    for (const double w : request.sourceWeights)
        if (!(std::isfinite(w) && w >= 0.0))
            throw Error("a source sample's light weight must be finite and >= 0, got " + shareText(w));
    result.weighted = true;
    result.lightBefore = unblockedLight(map, request.sourceWeights);
    if (!(result.lightBefore > 0.0))
        throw Error("no light reaches the receiver through the unblocked rays (their source samples are dark): nothing to cut");
    result.lightRequired = request.share * result.lightBefore;
    std::vector<double> light(crossings.rays.size());
    double crossing = 0.0;
    const auto sources = std::uint64_t(map.sourceCount());
    for (std::size_t k = 0; k < light.size(); ++k)
        crossing += light[k] = request.sourceWeights[std::size_t(crossings.rays[k] % sources)];
    if (crossing < result.lightRequired * (1.0 - 1e-12))
        throw Error("the rays that cross the plane between the patches carry share " + shareText(crossing / result.lightBefore) +
                    " of the light, less than the share " + shareText(request.share) +
                    " asked: choose a depth nearer the middle of the view, or a smaller share");
    return light;
}

} // namespace

Suggestion suggestOccluder(const Patch& source, const Patch& receiver, const ReceiverHeights& heights,
                           const HiddenSampleMap& map, const Request& request)
{
    validateRequest(request);
    Suggestion result;
    result.plane = request.surface ? surfacePlane(source, receiver, *request.surface)
                                   : suggestPlane(source, receiver, request.depth);
    result.shape = request.shape;
    const std::uint64_t unblocked = map.rayCount() - map.blockedCount();
    if (unblocked == 0)
        throw Error("every ray between the patches is already blocked: there is nothing left to cut");
    const double wanted = std::ceil(request.share * double(unblocked) - 1e-9);
    result.unblockedBefore = unblocked;
    result.required = std::clamp<std::uint64_t>(std::uint64_t(std::max(wanted, 1.0)), 1, unblocked);
    result.promised = unblocked - result.required;
    const bool everyRay = result.required == unblocked;
    if (!everyRay && unblocked > kMaxTrimmedRays)
        throw Error("a share below 1 is chosen among at most " + std::to_string(kMaxTrimmedRays) +
                    " unblocked rays, and this pair has " + std::to_string(unblocked) +
                    ": use --share 1, or fewer samples on the patches");

    Shaped shaped;
    double smallestCosine = 1.0;
    if (everyRay) {
        StreamedHull streamed = hullOfAllCrossings(source, receiver, heights, map, result.plane);
        result.crossing = streamed.crossing;
        smallestCosine = streamed.smallestCosine;
        shaped.kept = std::size_t(streamed.crossing);
        shaped.hull = convexHull(std::move(streamed.points));
        if (!shaped.hull.empty())
            shaped.rect = minAreaRect(shaped.hull);
    } else {
        const RayCrossings crossings = crossUnblockedRays(source, receiver, heights, map, result.plane);
        result.crossing = crossings.points.size();
        std::vector<double> light;   // per crossing, with weights
        Keep keep{.count = std::size_t(result.required), .weights = {}, .weight = 0.0};
        if (!request.sourceWeights.empty()) {
            light = crossingLight(map, crossings, request, result);
            keep = Keep{.weights = light, .weight = result.lightRequired};
        }
        if (result.weighted || result.required <= result.crossing) {
            shaped = request.shape == Shape::Rect ? rectShape(crossings.points, keep) : convexShape(crossings.points, keep);
            for (std::size_t i = 0; i < shaped.keep.size(); ++i)
                if (shaped.keep[i]) {
                    smallestCosine = std::min(smallestCosine, double(crossings.cosines[i]));
                    result.lightEnclosed += light.empty() ? 0.0 : light[i];
                }
        }
        if (result.weighted) {   // the promise in rays: those it was built around are blocked
            result.required = shaped.kept;
            result.promised = unblocked - shaped.kept;
        }
    }
    if (result.required > result.crossing) {
        const double most = double(result.crossing) / double(unblocked);
        throw Error((request.surface ? std::string("the picked surface's plane") : "the plane at depth " + shareText(request.depth)) +
                    " misses " +
                    std::to_string(unblocked - result.crossing) + " of the " + std::to_string(unblocked) +
                    " unblocked rays (they do not cross it between the patches), so no occluder on it blocks share " +
                    shareText(request.share) + "; the most it can block is share " + shareText(most) +
                    (request.surface ? ": pick a surface the rays cross between the patches, or a smaller share"
                                     : ": choose a depth nearer the middle of the view or a smaller --share"));
    }
    result.enclosed = shaped.kept;

    // The margin (see the header): four tie distances plus float32 rounding of the corners,
    // measured across the ray, so divided by the least cosine of a kept crossing.
    double largest = 0.0;
    for (const Point2& p : shaped.hull) {
        const glm::dvec3 w = result.plane.world(p);
        largest = std::max({largest, std::abs(w.x), std::abs(w.y), std::abs(w.z)});
    }
    const double across = 4.0 * kTieDistance + 16.0 * std::ldexp(largest + 1.0, -24);
    result.margin = request.marginScale * across / std::max(smallestCosine, 0.05);

    const bool flat = shaped.hull.size() < 3 || polygonArea(shaped.hull) <= 1e-12 * (1.0 + largest * largest);
    if (request.shape == Shape::Rect || flat) {
        result.rect = shaped.rect;
        result.rect.halfWidth += result.margin;
        result.rect.halfHeight += result.margin;
        const auto corners = result.rect.corners();
        result.polygon.assign(corners.begin(), corners.end());
    } else {
        result.polygon = grownPolygon(shaped.hull, result.margin);
        result.rect = minAreaRect(result.polygon);
    }
    result.area = polygonArea(result.polygon);
    return result;
}

glm::dvec3 suggestionCentre(const Suggestion& suggestion)
{
    glm::dvec3 centroid{0.0};
    const std::vector<glm::dvec3> corners = suggestion.worldPolygon();
    for (const glm::dvec3& c : corners)
        centroid += c;
    return glm::dvec3(glm::vec3(centroid / double(corners.size())));
}

Mesh suggestionMesh(const Suggestion& suggestion, const std::string& name, glm::dvec3 origin)
{
    Mesh mesh;
    mesh.name = name;
    std::vector<glm::dvec3> corners = suggestion.worldPolygon();
    glm::dvec3 centroid{0.0};
    for (glm::dvec3& c : corners) {
        centroid += c;
        c -= origin;
    }
    centroid = centroid / double(corners.size()) - origin;
    mesh.positions.push_back(glm::vec3(centroid));
    for (const glm::dvec3& c : corners)
        mesh.positions.push_back(glm::vec3(c));
    const auto n = std::uint32_t(corners.size());
    for (std::uint32_t i = 0; i < n; ++i)   // the centroid's fan
        mesh.indices.insert(mesh.indices.end(), {0u, 1 + i, 1 + (i + 1) % n});
    for (std::uint32_t i = 1; i + 1 < n; ++i)   // the first corner's fan
        mesh.indices.insert(mesh.indices.end(), {1u, 1 + i, 2 + i});
    return mesh;
}

} // namespace sightline::suggest
