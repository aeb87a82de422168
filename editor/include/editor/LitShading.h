#pragma once
// What the editor's lit view shows on the level's texels (LitPreview.h), over the same computed
// light: switching between them casts no shadow ray (but Error, which computes the reference).

namespace sightline::ui {

enum class LitShading {
    Light,        ///< the lights' irradiance, tone-mapped
    Complexity,   ///< per texel, of the lights that reach it unshadowed: fully lit (green), partly (blue), shadowed (red)
    Overlap,      ///< per texel, how many lights light it against a budget: green to yellow up to it, red over it
    Staleness,    ///< the share of the shown light that comes from stale lights, in red over the light
    Error,        ///< per texel, the shown light's relative error against the reference path (LitReference.h)
};

} // namespace sightline::ui
