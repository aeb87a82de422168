#include "visibility/ReceiverHeights.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

#include <glm/geometric.hpp>

#include "base/Error.h"

namespace sightline {

namespace {

std::string metresText(double value)
{
    std::ostringstream text;
    text.precision(6);
    text << value << " m";
    return text.str();
}

std::string sampleText(const Patch& receiver, int j)
{
    return "receiver sample " + std::to_string(j) + " (a " + std::to_string(j % receiver.na) + ", b " +
           std::to_string(j / receiver.na) + ")";
}

} // namespace

glm::dvec3 receiverNormalTowardSource(const Patch& source, const Patch& receiver)
{
    // The same orientation rule as the samplers' receiver frame (PatchFrame, ShaftGeometry.h), so
    // that every method displaces the samples to the same positions, bit for bit.
    glm::dvec3 n = receiver.normal();
    if (glm::dot(source.centre() - receiver.corner, n) < 0.0)
        n = -n;
    return n;
}

glm::dvec3 displacedReceiverSample(const Patch& source, const Patch& receiver, const ReceiverHeights& heights, int j)
{
    if (heights.empty())
        return receiver.sample(j);
    return receiver.sample(j) + heights.metres[std::size_t(j)] * receiverNormalTowardSource(source, receiver);
}

bool flatReceiver(const ReceiverHeights* heights)
{
    return !heights || std::all_of(heights->metres.begin(), heights->metres.end(), [](double h) { return h == 0.0; });
}

void validateReceiverHeights(const Patch& source, const Patch& receiver, const ReceiverHeights& heights)
{
    if (heights.empty())
        return;
    const std::size_t expected = std::size_t(receiver.sampleCount());
    if (heights.metres.size() != expected)
        throw Error("receiver heights: " + std::to_string(heights.metres.size()) + " values for a " +
                    std::to_string(receiver.na) + "x" + std::to_string(receiver.nb) + " receiver; give one per sample (" +
                    std::to_string(expected) + ") or none");
    for (std::size_t j = 0; j < expected; ++j)
        if (!std::isfinite(heights.metres[j]))
            throw Error("receiver heights: the height of " + sampleText(receiver, int(j)) + " is not a finite number");

    // Every segment must run from the source plane into the receiver's side; a sample on or
    // behind the source plane has no such segment. "Strictly" with the tolerance validatePatchPair
    // uses: closer than a relative 1e-9 of the scene's size counts as touching.
    glm::dvec3 sourceNormal = source.normal();
    if (glm::dot(receiver.centre() - source.corner, sourceNormal) < 0.0)
        sourceNormal = -sourceNormal;
    const double scale = std::max({glm::length(source.u), glm::length(source.v), glm::length(receiver.u),
                                   glm::length(receiver.v), glm::length(receiver.corner - source.corner)});
    const double eps = 1e-9 * scale;
    const glm::dvec3 n = receiverNormalTowardSource(source, receiver);
    const double rate = glm::dot(n, sourceNormal);   // change of the source distance per metre of height
    for (int j = 0; j < receiver.sampleCount(); ++j) {
        const double h = heights.metres[std::size_t(j)];
        const glm::dvec3 flat = receiver.sample(j);
        if (glm::dot(flat + h * n - source.corner, sourceNormal) > eps)
            continue;
        const double flatDistance = glm::dot(flat - source.corner, sourceNormal);
        std::string limit;
        if (rate < 0.0)
            limit = "; keep it below " + metresText((flatDistance - eps) / -rate) + " there";
        else if (rate > 0.0)
            limit = "; keep it above " + metresText(-(flatDistance - eps) / rate) + " there";
        throw Error("receiver heights: the height " + metresText(h) + " of " + sampleText(receiver, j) +
                    " reaches the source's plane" + limit);
    }
}

} // namespace sightline
