#pragma once
// sightline-cli lights (docs/lights.md, a contract): direct irradiance from the project's lights,
// shadowed exactly, at given points or over the receiver patch's samples.

#include <string>

namespace CLI {
class App;
}

namespace sightline::cli {

struct LightsArgs {
    std::string project, points, npy;
    bool json = false;
    bool reference = false;   ///< brute force: every light sample at every point by ray casting
    bool compare = false;
    bool bitmaskArea = false; ///< area lights facing the receiver grid by the bitmask sampler     ///< also run the other path, report its time and the largest difference
    int threads = 0;
    bool allowOutsidePaths = false;
};

CLI::App* addLightsCommand(CLI::App& app, LightsArgs& args);
int runLights(const LightsArgs& args);

} // namespace sightline::cli
