#pragma once
// sightline-cli disagreement: what a fast or coarse mode costs, ray by ray. The project's pair is
// sampled exactly and by the approximation (project/Approximation.h); every ray they answer
// differently is judged by the contract's brute force (visibility/RayDisagreement.h) and counted as
// false-blocked, false-free or a tie, and drawn, with every other ray, into a PNG.

#include <string>

namespace CLI {
class App;
}

namespace sightline::cli {

struct DisagreementArgs {
    std::string project;
    std::string approximation = "table";
    std::string image;           ///< PNG of every ray (RayDisagreement.h's picture); empty: none
    std::string glBackend = "osmesa";
    int threads = 0;
    bool json = false;
    bool allowOutsidePaths = false;
};

CLI::App* addDisagreementCommand(CLI::App& app, DisagreementArgs& args);
int runDisagreement(const DisagreementArgs& args);

} // namespace sightline::cli
