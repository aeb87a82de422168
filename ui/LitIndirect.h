#pragma once
// The lit view's optional one bounce of indirect light: the lights' virtual point lights
// (lighting/Indirect.h: photons from the lights, a VPL where each first meets a surface) lit over
// the view's texels by a LightingCache of their own, with the same amortised, exact updates. The
// bounce is traced again whenever the lights change; the last complete bounce stays shown until
// the new one is, so the view never flickers to a half-summed bounce. Plain C++ (no Qt).

#include <cstdint>
#include <memory>
#include <vector>

#include <glm/vec3.hpp>

#include "lighting/DirectLight.h"
#include "lighting/Indirect.h"
#include "lighting/Light.h"
#include "lighting/LightingCache.h"

namespace sightline::ui {

/// The lit view's bounce: as `sightline-cli lights --indirect` by default (albedo 0.5 everywhere,
/// a 0.1 m clamp), with fewer photons so that it follows a moved light within seconds.
IndirectOptions litIndirectOptions();

class LitIndirect {
public:
    explicit LitIndirect(std::vector<ShadingPoint> points, IndirectOptions options = litIndirectOptions());

    /// Traces the VPLs of `lights` again: every VPL stale, the previous bounce still shown.
    void setLights(const LightingScene& scene, const std::vector<Light>& lights);
    /// Refreshes stale VPLs within `budget` shadow segments (LightingCache::update).
    void update(const LightingScene& scene, std::uint64_t budget);
    /// Whether the bounce shown is that of the current lights, every VPL exact.
    bool exact() const { return exact_; }
    /// The bounce shown at each point (all zero until the first is complete).
    const std::vector<glm::dvec3>& irradiance() const { return shown_; }
    std::size_t vpls() const { return vpls_; }

private:
    std::vector<ShadingPoint> points_;
    IndirectOptions options_;
    std::unique_ptr<LightingCache> cache_;
    std::vector<glm::dvec3> shown_;
    std::size_t vpls_ = 0;
    bool exact_ = false;
};

} // namespace sightline::ui
