#pragma once
// sightline-cli importance / shadow (Eisemann & Décoret §9, §8), kept apart from the visibility
// subcommands in sightline_cli.cpp.

#include <cstdint>
#include <string>

namespace CLI {
class App;
}

namespace sightline::cli {

struct GridOverrides {
    std::string sourceSamples;     ///< "NAxNB" or "N" (N x N); empty = the project's
    std::string receiverSamples;
};

struct ImportanceArgs {
    std::string project, out, npy;
    int frames = 0;                ///< 0: the motion's defaultFrames()
    bool path = false;             ///< accumulate over the recorded path, not the animation
    std::string of = "receiver";
    std::string statistic = "mean";
    std::string method = "cpu";
    std::string glBackend = "osmesa";
    std::uint32_t jitter = 0;
    int threads = 0;
    bool json = false;
    bool progress = false;
    bool allowOutsidePaths = false;
    GridOverrides grids;
};

struct ShadowArgs {
    std::string project, out, npy;
    std::string method = "cpu";
    std::string glBackend = "osmesa";
    std::uint32_t jitter = 0;
    int threads = 0;
    int scale = 1;
    bool intensity = false;
    bool json = false;
    bool allowOutsidePaths = false;
    GridOverrides grids;
};

CLI::App* addImportanceCommand(CLI::App& app, ImportanceArgs& args);
CLI::App* addShadowCommand(CLI::App& app, ShadowArgs& args);
/// Throw sightline::Error for an option the chosen --method would ignore (cli/OptionRules.h).
void checkImportanceOptions(const CLI::App& command, const ImportanceArgs& args);
void checkShadowOptions(const CLI::App& command, const ShadowArgs& args);
int runImportance(const ImportanceArgs& args);
int runShadow(const ShadowArgs& args);

} // namespace sightline::cli
