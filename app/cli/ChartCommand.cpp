#include "cli/ChartCommand.h"

#include <cstdio>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "cli/OutputPaths.h"
#include "report/SeriesChart.h"
#include "base/Error.h"
#include "base/InputFile.h"
#include "base/JsonDepth.h"

using nlohmann::json;

namespace sightline::cli {

namespace {

constexpr std::uintmax_t kMaxSpecBytes = std::uintmax_t(16) << 20;

const json& member(const json& object, const char* key, const std::string& where)
{
    if (!object.is_object() || !object.contains(key))
        throw Error(where + ": missing \"" + key + "\"");
    return object.at(key);
}

QString text(const json& object, const char* key, const std::string& where)
{
    if (!object.contains(key))
        return {};
    const json& v = object.at(key);
    if (!v.is_string())
        throw Error(where + ": \"" + key + "\" is not a string");
    return QString::fromStdString(v.get<std::string>());
}

ChartAxis axis(const json& spec, const char* key, const std::string& what)
{
    const std::string where = what + ", \"" + key + "\"";
    const json& a = member(spec, key, what);
    ChartAxis out{text(a, "title", where), false};
    if (a.contains("log")) {
        if (!a.at("log").is_boolean())
            throw Error(where + ": \"log\" is not true or false");
        out.log = a.at("log").get<bool>();
    }
    return out;
}

SeriesChartSpec parseSpec(const std::string& bytes, const std::string& what)
{
    checkJsonDepth(bytes, what);
    json spec;
    try {
        spec = json::parse(bytes);
    } catch (const json::exception& e) {
        throw Error(what + ": not JSON (" + std::string(e.what()) + ")");
    }
    if (!spec.is_object())
        throw Error(what + ": not a JSON object");
    SeriesChartSpec out{text(spec, "title", what), axis(spec, "x", what), axis(spec, "y", what), {}};
    const json& series = member(spec, "series", what);
    if (!series.is_array())
        throw Error(what + ": \"series\" is not an array");
    for (std::size_t s = 0; s < series.size(); ++s) {
        const std::string where = what + ", series " + std::to_string(s);
        ChartSeries one{text(series[s], "name", where), {}};
        const json& points = member(series[s], "points", where);
        if (!points.is_array())
            throw Error(where + ": \"points\" is not an array");
        for (std::size_t k = 0; k < points.size(); ++k) {
            const json& p = points[k];
            if (!p.is_array() || p.size() != 2 || !p[0].is_number() || !p[1].is_number())
                throw Error(where + ", point " + std::to_string(k) + ": not a pair of numbers [x, y]");
            one.points.emplace_back(p[0].get<double>(), p[1].get<double>());
        }
        out.series.push_back(std::move(one));
    }
    return out;
}

} // namespace

CLI::App* addChartCommand(CLI::App& app, ChartArgs& a)
{
    CLI::App* chart = app.add_subcommand("chart", "Draw a line chart from a JSON description (the benchmark scripts' charts)");
    chart->add_option("spec", a.spec,
                      "{\"title\", \"x\": {\"title\", \"log\"}, \"y\": {...}, \"series\": [{\"name\", \"points\": [[x, y], ...]}]}")
        ->required();
    chart->add_option("--out", a.out, "The PNG to write")->required()->check(outputFile());
    chart->add_option("--width", a.width, "Pixels")->check(CLI::Range(200, 8192))->capture_default_str();
    chart->add_option("--height", a.height, "Pixels")->check(CLI::Range(150, 8192))->capture_default_str();
    return chart;
}

int runChart(const ChartArgs& args)
{
    checkOutputs({{"--out", args.out}}, {{"the chart's description", args.spec}});
    const SeriesChartSpec spec = parseSpec(readInputFile(args.spec, "chart description", kMaxSpecBytes), args.spec);
    writeSeriesChart(spec, args.width, args.height, args.out);
    std::printf("wrote %s\n", args.out.c_str());
    return 0;
}

} // namespace sightline::cli
