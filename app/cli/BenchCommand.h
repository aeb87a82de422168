#pragma once
// sightline-cli bench: every method timed against the raycast reference on the projects given, each
// ray judged by the exact contract; a table, a CSV and a chart of time against error (app/bench/).

#include <string>
#include <vector>

#include "bench/Bench.h"

namespace CLI {
class App;
}

namespace sightline::cli {

struct BenchArgs {
    bench::Settings settings;
    std::string methods = "raycast,cpu,cpu-bitmask,cpu-table-256x128";
    std::string csv, chart;
    std::string glBackend = "osmesa";
    bool shadow = false;
};

CLI::App* addBenchCommand(CLI::App& app, BenchArgs& args);
int runBench(const CLI::App& command, BenchArgs& args);

} // namespace sightline::cli
