#include "cli/BenchCommand.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>

#include <CLI/CLI.hpp>

#include "bench/BenchChart.h"
#include "cli/OptionRules.h"
#include "cli/OutputPaths.h"
#include "project/Project.h"
#include "base/AtomicFile.h"
#include "base/Error.h"
#include "visibility/gl/HeadlessContext.h"

namespace sightline::cli {

namespace fs = std::filesystem;

CLI::App* addBenchCommand(CLI::App& app, BenchArgs& args)
{
    CLI::App* benchCmd = app.add_subcommand("bench", "Time every method against the raycast reference; CSV and chart");
    benchCmd->add_option("projects", args.settings.projects, "Project files")->required();
    benchCmd->add_option("--methods", args.methods,
                         "Comma-separated: embree-tuned (the baseline: a float Embree tracer, the fastest of its four "
                         "traversals), raycast, cpu, cpu-bitmask, cpu-hybrid, cpu-raycast, cpu-scalar (cpu without SIMD), "
                         "cpu-table-WxH, gl, gl-table-WxH (gl with the Hough table), hh (Heckbert-Herf, counts only), "
                         "raycast-jitter, cpu-jitter, gl-jitter (decorrelated sampling, §6.2)")
        ->capture_default_str();
    benchCmd->add_option("--sources", args.settings.sourceCounts, "Source sample counts (1..1024)")
        ->delimiter(',')
        ->check(CLI::Range(1, 1024))
        ->capture_default_str();
    benchCmd->add_option("--receivers", args.settings.receiverSides, "Receiver grid sides (NxN)")
        ->delimiter(',')
        ->check(CLI::Range(1, 1024))
        ->capture_default_str();
    benchCmd->add_option("--repeat", args.settings.repeat, "Rounds: each method runs once untimed, then timed (--min-time); methods interleaved (median reported)")
        ->check(CLI::Range(1, 1000))
        ->capture_default_str();
    benchCmd->add_option("--min-time", args.settings.minBatchMs,
                         "In each round, a method's timed runs go on until they took MS milliseconds (at most 100 runs)")
        ->check(CLI::Range(0.0, 600000.0))
        ->capture_default_str();
    benchCmd->add_option("--threads", args.settings.threads, "Worker threads (0 = all cores)")->check(CLI::Range(0, 1024));
    benchCmd->add_option("--gl-backend", args.glBackend, "gl, gl-table-WxH, hh: headless context, osmesa (software) or egl (GPU)")
        ->check(CLI::IsMember({"osmesa", "egl"}))
        ->capture_default_str();
    benchCmd->add_flag("--shadow", args.shadow,
                       "Soft shadows (paper §8): also compare each method's light fraction with a dense reference "
                       "(--dense), and chart time against that error");
    benchCmd->add_option("--dense", args.settings.denseSide,
                         "Dense reference: N x N regular source samples (multiple of 32; --shadow default 128)")
        ->check(CLI::Range(0, 1024));
    benchCmd->add_option("--csv", args.csv, "Write all rows as CSV")->check(outputFile());
    benchCmd->add_option("--chart", args.chart, "Write a PNG chart of time against error")->check(outputFile());
    addAllowOutsidePaths(benchCmd, args.settings.allowOutsidePaths);
    return benchCmd;
}

int runBench(const CLI::App& command, BenchArgs& args)
{
    args.settings.methods = bench::parseMethods(args.methods);
    const bool anyGl = std::any_of(args.settings.methods.begin(), args.settings.methods.end(), [](const std::string& m) {
        return m == "gl" || m == "hh" || m.starts_with("gl-");
    });
    if (given(command, "--gl-backend") && !anyGl)
        throw Error("--gl-backend applies to the GL methods (gl, gl-table-WxH, gl-jitter, hh), and --methods names none");
    args.settings.glBackend = gl::parseBackend(args.glBackend);
    if (args.shadow && args.settings.denseSide == 0)
        args.settings.denseSide = 128;
    if (args.settings.denseSide % 32 != 0)
        throw Error("--dense must be a multiple of 32, got " + std::to_string(args.settings.denseSide));
    // Before the runs, which may take minutes: the CSV or chart must not replace what is benchmarked.
    std::vector<FileRole> inputs;
    for (const std::string& file : args.settings.projects) {
        std::vector<FileRole> read{{"the project", file}};
        try {
            read = projectInputs(file, loadProject(file, {.allowOutsidePaths = args.settings.allowOutsidePaths}));
        } catch (const std::exception&) {
            // An unreadable project is refused by the run itself, with its own message.
        }
        inputs.insert(inputs.end(), read.begin(), read.end());
    }
    checkOutputs({{"--csv", args.csv}, {"--chart", args.chart}}, inputs);
    std::printf("%-28s %-18s %7s %9s %10s %10s %12s %12s %8s %10s %10s %10s  %s\n", "project", "method", "sources", "receiver",
                "ms", "thread-ms", "wrong-block", "wrong-free", "ties", "error", "light-mae", "dense-mae", "variant");
    std::uint64_t referenceErrors = 0;
    const auto rows = bench::run(args.settings, [&](const bench::Row& r) {
        const std::string name = fs::path(r.project).filename().string();
        const std::string ties = r.judged ? std::to_string(r.ties) : "-";
        std::printf("%-28s %-18s %7d %5dx%-4d %10.2f %10.2f %12llu %12llu %8s %10.6f %10.6f ", name.c_str(),
                    r.method.c_str(), r.sourceSamples, r.receiverSide, r.receiverSide, r.ms, r.threadMs,
                    (unsigned long long)r.wronglyBlocked, (unsigned long long)r.wronglyFree, ties.c_str(), r.errorFraction(),
                    r.lightMae);
        if (r.denseMae >= 0.0)
            std::printf("%10.6f", r.denseMae);
        else
            std::printf("%10s", "-");
        std::printf("  %s\n", r.variant.c_str());
        std::fflush(stdout);
        referenceErrors += r.referenceErrors;
    });
    if (referenceErrors > 0)
        std::fprintf(stderr, "warning: the raycast reference disagreed with the exact judge on %llu rays (a bug: please report it)\n",
                     (unsigned long long)referenceErrors);
    if (!args.csv.empty()) {
        writeFileAtomically(args.csv, bench::toCsv(rows));
        std::printf("wrote %s\n", args.csv.c_str());
    }
    if (!args.chart.empty()) {
        bench::writeChart(rows, args.chart, args.shadow ? bench::ChartKind::ShadowError : bench::ChartKind::RayErrors);
        std::printf("wrote %s\n", args.chart.c_str());
    }
    return 0;
}

} // namespace sightline::cli
