#pragma once
// sightline-cli chart: a line chart drawn from a JSON description (report/SeriesChart.h), for the
// benchmark scripts that sweep a parameter and collect figures from several runs (docs/cli.md).

#include <string>

namespace CLI {
class App;
}

namespace sightline::cli {

struct ChartArgs {
    std::string spec;
    std::string out;
    int width = 1100, height = 700;
};

CLI::App* addChartCommand(CLI::App& app, ChartArgs& args);
int runChart(const ChartArgs& args);

} // namespace sightline::cli
