#pragma once
// The lit view's optional one bounce of indirect light: the lights' virtual point lights
// (lighting/Indirect.h: photons from the lights, a VPL where each first meets a surface) lit over
// the view's texels by the exact fast path, a few VPLs a frame within the frame's budget, summed
// as they come. No field is kept per VPL (hundreds of them over 200k texels would take hundreds of
// megabytes; nothing but the sum is shown). The bounce is traced again whenever the lights change;
// the photons of lights that did not change draw the same random numbers (each light's count comes
// from its power alone), so their VPLs come back bit for bit, and the new bounce is the last one
// less the VPLs gone plus the VPLs new: moving one light re-lights its few VPLs, not all of them.
// The last complete bounce stays shown until the new one is, so the view never flickers to a
// half-summed bounce. Plain C++ (no Qt).

#include <cstdint>
#include <memory>
#include <vector>

#include <glm/vec3.hpp>

#include "lighting/DirectLight.h"
#include "lighting/Indirect.h"
#include "lighting/Light.h"

namespace sightline::ui {

/// The lit view's bounce: as `sightline-cli lights --indirect` by default (each surface's material
/// albedo, else 0.5; a 0.1 m clamp), with fewer photons so that it follows a moved light within seconds.
IndirectOptions litIndirectOptions();

class LitIndirect {
public:
    explicit LitIndirect(std::vector<ShadingPoint> points, IndirectOptions options = litIndirectOptions());

    /// Traces the VPLs of `lights` again: every VPL stale, the previous bounce still shown.
    void setLights(const LightingScene& scene, const std::vector<Light>& lights);
    /// Lights the texels by the next VPLs whose segments (points x VPLs) fit `budget`, at least one.
    void update(const LightingScene& scene, std::uint64_t budget);
    /// Whether the bounce shown is that of the current lights, every VPL exact.
    bool exact() const { return exact_; }
    /// The bounce shown at each point (all zero until the first is complete).
    const std::vector<glm::dvec3>& irradiance() const { return shown_; }
    std::size_t vpls() const { return vplLights_.size(); }
    /// VPLs still to be lit (added or taken away) before the bounce of the current lights is whole.
    std::size_t pending() const { return work_.size() - next_; }

private:
    /// Once every step is summed: the bounce of the current lights is shown, exact.
    void finishIfDone();
    struct Step {
        Light vpl;
        double sign = 1.0;   ///< -1: a VPL of the shown bounce that is gone
    };
    std::vector<ShadingPoint> points_;
    std::unique_ptr<PointTiling> tiling_;   ///< the fast path's tiles over points_, built once
    IndirectOptions options_;
    std::vector<Light> vplLights_;         ///< the current lights' VPLs
    std::vector<Light> shownVpls_;         ///< the VPLs of the bounce shown (complete)
    bool anyShown_ = false;                ///< a complete bounce is shown
    std::vector<Step> work_;               ///< from the shown bounce (or nothing) to the current one
    std::size_t next_ = 0;                 ///< the first step not yet summed
    std::vector<glm::dvec3> sum_;          ///< the starting bounce and steps [0, next_)
    std::vector<glm::dvec3> shown_;
    bool exact_ = false;
};

} // namespace sightline::ui
