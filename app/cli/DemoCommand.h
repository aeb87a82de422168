#pragma once
// sightline-cli demo: the built-in demo level and its projects, the benchmark scenes and seeds of
// each generated bench kind, written to a folder (levelgen/demo/).

#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace sightline::cli {

struct DemoArgs {
    std::string folder;
    std::string seeds = "1-3";   ///< FIRST-LAST of each generated kind
};

CLI::App* addDemoCommand(CLI::App& app, DemoArgs& args);
int runDemo(const DemoArgs& args);

} // namespace sightline::cli
