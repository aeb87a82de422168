#pragma once
// sightline-cli shaft (docs/design.md §4, a contract): the hidden-samples map between the project's
// patches by one sampler (raycast, the exact CPU or GL bitmask, or the Heckbert-Herf baseline), its
// counts and time, and optionally the map as .npy.

#include <cstdint>
#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace sightline::cli {

struct ShaftArgs {
    std::string project;
    std::string method = "raycast";
    std::string mask;
    bool json = false;
    int threads = 0;
    bool singleRays = false;
    bool scalar = false;
    std::uint32_t jitter = 0;
    int repeat = 0;   ///< 0: --repeat not given, one cold run
    std::string strategy = "auto";
    bool strategyGiven = false;   ///< --strategy on the command line (else --scalar implies bitmask)
    std::string glBackend = "osmesa";
    std::string mode = "exact";
    std::vector<int> table = {256, 128};
    bool allowOutsidePaths = false;
};

CLI::App* addShaftCommand(CLI::App& app, ShaftArgs& args);
/// Refuses options `--method` (and `--mode`) would ignore, then runs.
int runShaft(const CLI::App& command, ShaftArgs& args);

} // namespace sightline::cli
