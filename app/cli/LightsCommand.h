#pragma once
// sightline-cli lights (docs/lights.md, a contract): direct irradiance from the project's lights,
// shadowed exactly, at given points or over the receiver patch's samples.

#include <cstdint>
#include <string>

namespace CLI {
class App;
}

namespace sightline::cli {

struct LightsArgs {
    std::string project, points, npy;
    bool json = false;
    bool reference = false;   ///< brute force: every light sample at every point by ray casting
    bool compare = false;     ///< also run the other path, report its time and the largest difference
    bool bitmaskArea = false; ///< area lights facing the receiver grid by the bitmask sampler
    double lightCut = 0.0;    ///< > 0: point lights by a light tree's cut with this error (approximate)
    bool gl = false;          ///< the GL path (octahedral shadow maps) instead of the exact fast path
    std::string glBackend = "osmesa";
    int glResolution = 512;
    bool glNoPyramid = false; ///< --gl: no tile classes (a map lookup for every pair)
    int threads = 0;
    bool allowOutsidePaths = false;
    // One bounce of indirect light (lighting/Indirect.h), added to the direct light when vpls > 0.
    int vpls = 0;
    std::uint64_t seed = 1;
    double albedo = 0.5;
    double clamp = 0.1;
    int gatherSamples = 0;    ///< > 0: also the Monte-Carlo gathering reference, for its error
    bool sets = false;        ///< O'Rorke's sets per light instead of irradiance
    std::string pvs;          ///< --sets: a baked PVS serving V and bounding L
    double texel = 0.0;       ///< > 0: bake a light map at this many texels a metre
    int drag = 0;             ///< > 0: time this many frames of dragging one light (LightingCache)
    std::string lightmap, gltf;
};

CLI::App* addLightsCommand(CLI::App& app, LightsArgs& args);
/// Throws sightline::Error for indirect-light options given without --indirect.
void checkLightsOptions(const CLI::App& command, const LightsArgs& args);
int runLights(const LightsArgs& args);

} // namespace sightline::cli
