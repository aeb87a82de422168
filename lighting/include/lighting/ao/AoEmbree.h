#pragma once
// Embree for ambient occlusion: the single-ray baseline filler (rtcOccluded1 per point and facing
// direction, the "calling Embree per ray" the exact CPU mode must beat, in the same run), and the
// Monte-Carlo reference: many cosine-weighted rays per point (docs/design.md §5), against which every
// direction set and weighting is measured.

#include <cstdint>
#include <memory>
#include <vector>

#include "lighting/ao/AoFiller.h"

namespace sightline {

class AoEmbreeScene {
public:
    explicit AoEmbreeScene(const AoOccluders& occluders);
    ~AoEmbreeScene();
    AoEmbreeScene(const AoEmbreeScene&) = delete;
    AoEmbreeScene& operator=(const AoEmbreeScene&) = delete;
    /// Whether the ray from `origin` towards unit `direction` leaves the scene unblocked.
    bool unblocked(const glm::vec3& origin, const glm::vec3& direction) const;
    /// The same for directions [first, last) of `set` (at most 16) in one packet: a bit per
    /// direction, set where it is unblocked and faces `normal` (dot > 0).
    std::uint32_t unblocked16(const glm::vec3& origin, const glm::vec3& normal, const AoDirectionSet& set, int first,
                              int last) const;

    struct Impl;
    const Impl& impl() const { return *impl_; }

private:
    std::unique_ptr<Impl> impl_;
};

/// How the baseline casts a point's directions: one rtcOccluded1 each (the plain baseline of
/// docs/ao.md), or 16 to a packet (rtcOccluded16, Embree's default incoherent traversal), which
/// `sightline-ao-bench` also times: the baseline it reports is the faster of the two.
enum class AoEmbreeTraversal { SingleRays, DirectionPackets };

class AoEmbreeCaster final : public AoFiller {
public:
    explicit AoEmbreeCaster(const AoOccluders& occluders, int threads = 0,
                            AoEmbreeTraversal traversal = AoEmbreeTraversal::SingleRays);
    std::string name() const override
    {
        return traversal_ == AoEmbreeTraversal::SingleRays ? "embree-single-rays" : "embree-direction-packets";
    }
    bool fill(const AoPoints& points, const AoDirectionSet& set, int first, int last, VisibilityMatrix& matrix,
              const AoFillControl& control = {}) override;

private:
    AoEmbreeScene scene_;
    int threads_;
    AoEmbreeTraversal traversal_;
};

/// The cosine-weighted AO of every usable point from `rays` Monte-Carlo rays (stratified: a
/// sqrt(rays)^2 jittered grid mapped to the hemisphere by Malley's method, rotated at random about
/// the normal per point; `rays` is rounded down to a square). NaN for unusable points. The standard
/// error of one point's value is at most sqrt(a (1 - a) / rays) (stratification only lowers it).
std::vector<float> monteCarloAo(const AoEmbreeScene& scene, const AoPoints& points, int rays, std::uint64_t seed = 1,
                                int threads = 0);

} // namespace sightline
