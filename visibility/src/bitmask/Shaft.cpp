#include "Shaft.h"

#include <algorithm>

#include <glm/geometric.hpp>

#include "visibility/ExactSegment.h"

namespace sightline::bitmask {

Shaft::Shaft(const Patch& source, const Patch& receiver, const SourceJitter& jitter,
             const std::vector<glm::dvec3>* displaced)
    : frames(source, receiver), S(source.sampleCount()), na(source.na), nb(source.nb), rna(receiver.na),
      rnb(receiver.nb), jittered(jitter.enabled()), rowCentres(detail::rowCentres(source.nb)),
      metresPerS(glm::length(source.u)), metresPerT(glm::length(source.v))
{
    // Sample i seen from j lies at (s_i + dx, t_i + dy); testing the backprojection shifted by
    // (-dx, -dy) against the regular grid is the same test.
    jitterShift.resize(std::size_t(receiver.sampleCount()));
    for (int j = 0; j < receiver.sampleCount(); ++j) {
        const glm::dvec2 o = jitter.offset(j);
        jitterShift[std::size_t(j)] = {o.x / na, o.y / nb};
    }
    receiverInSource.resize(std::size_t(receiver.sampleCount()));
    for (int j = 0; j < receiver.sampleCount(); ++j)
        receiverInSource[std::size_t(j)] =
            frames.source.coordinates(displaced ? (*displaced)[std::size_t(j)] : receiver.sample(j));
    minReceiverDistance = 1e300;
    double maxReceiverDistance = 0.0;
    for (int k = 0; k < 4; ++k) {
        const glm::dvec3 sc = source.cornerPoint(k);
        sourceCornersInReceiver[std::size_t(k)] = frames.receiver.coordinates(sc);
        const glm::dvec3 rc = receiver.cornerPoint(k);
        minReceiverDistance = std::min(minReceiverDistance, frames.source.coordinates(rc).z);
        maxReceiverDistance = std::max(maxReceiverDistance, frames.source.coordinates(rc).z);
    }
    receiverCentre = frames.source.coordinates(receiver.centre());
    parallel = maxReceiverDistance - minReceiverDistance <= 1e-12 * maxReceiverDistance;
    receiverDistance = receiverCentre.z;
    if (displaced)
        setBumps(*displaced);
    for (const glm::dvec3& r : receiverInSource) {
        receiverS.push_back(float(r.x));
        receiverT.push_back(float(r.y));
        receiverD.push_back(float(r.z));
    }
}

void Shaft::setBumps(const std::vector<glm::dvec3>& displaced)
{
    // A bumpy receiver (§8): every receiver sample is backprojected from its displaced position
    // (receiverInSource), so the quantities that assumed the plane are taken over those samples.
    bumpy = true;
    double lowest = 1e300, highest = -1e300;
    minReceiverDistance = 1e300;
    glm::dvec3 sum(0.0);
    for (std::size_t j = 0; j < displaced.size(); ++j) {
        minReceiverDistance = std::min(minReceiverDistance, receiverInSource[j].z);
        sum += receiverInSource[j];
        const double height = frames.receiver.coordinates(displaced[j]).z;
        lowest = std::min(lowest, height), highest = std::max(highest, height);
    }
    // The samples' distances from the source differ: no per-occluder projection factors.
    parallel = false;
    // Only sizes occluders (Hybrid, the narrowed shaft): any point closer than every sample.
    receiverCentre = sum / double(displaced.size());
    receiverDistance = receiverCentre.z;
    levels = {lowest, highest};
    levelCount = highest > lowest ? 2 : 1;
    bumpySourceMargin = kEndMarginMetres;
    // A segment's receiver-frame distance runs between its two ends, so no segment reaches below
    // the lowest bump (nor below the source, were a bump to rise past a source corner). Parts
    // beyond an individual sample are clipped per sample (DoubleBackprojection.h).
    bumpyReceiverLevel = lowest;
    for (const glm::dvec3& corner : sourceCornersInReceiver)
        bumpyReceiverLevel = std::min(bumpyReceiverLevel, corner.z);
}

ClippedPolygon Shaft::clip(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) const
{
    if (!bumpy)
        return frames.clipToSlab(a, b, c);
    ClippedPolygon polygon;
    polygon.vertices[0] = glm::dvec3(a);
    polygon.vertices[1] = glm::dvec3(b);
    polygon.vertices[2] = glm::dvec3(c);
    polygon.count = 3;
    const PatchFrame& s = frames.source;
    const PatchFrame& r = frames.receiver;
    clipPolygon(polygon, s.dAxis, glm::dot(s.origin, s.dAxis) + bumpySourceMargin);
    if (polygon.count)
        clipPolygon(polygon, r.dAxis, glm::dot(r.origin, r.dAxis) + bumpyReceiverLevel);
    return polygon;
}

Path Shaft::pathFor(double maxD, double nearest) const
{
    if (maxD >= nearest - (bumpy ? 2.0 : 1.0) * kEndMarginMetres)
        return Path::Clip;
    if (floatKernel && maxD <= nearest * (1.0 - 1.0 / detail::kMaxFloatFactor))
        return Path::Float;
    return Path::Double;
}

double Shaft::clipDistance(double d) { return d - kEndMarginMetres; }

} // namespace sightline::bitmask
