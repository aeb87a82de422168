#pragma once
// sightline-cli info: a scene's or a project's counts, bounds and instances (docs/cli.md).

#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace sightline::cli {

struct InfoArgs {
    std::string file;
    bool json = false;
    bool allowOutsidePaths = false;
};

CLI::App* addInfoCommand(CLI::App& app, InfoArgs& args);
int runInfo(const InfoArgs& args);

} // namespace sightline::cli
