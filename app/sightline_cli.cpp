// sightline-cli: headless batch front end (docs/design.md §4, a contract).
//
//   sightline-cli shaft PROJECT.json [--method raycast|cpu|gl] [--mode exact|table] [--mask OUT.npy] [--json]
//   sightline-cli info SCENE_OR_PROJECT [--json]
//   sightline-cli demo OUTDIR
//   sightline-cli importance PROJECT.json --out MAP.png [--npy MAP.npy] [--frames N]   (cli/LightingCommands)
//   sightline-cli shadow PROJECT.json --out SHADOW.png
//   sightline-cli ao MESH_OR_PROJECT [--k 258] [--npy OUT.npy] [--json] ...             (cli/AoCommand, docs/ao.md)
//   sightline-cli lights PROJECT.json [--points P.npy] [--npy OUT.npy] [--json]   (cli/LightsCommand, docs/lights.md)
//   sightline-cli suggest PROJECT.json --depth T|--at X Y Z --normal N N N [--share F] [--shape convex|rect] [--write OUT.json] [--json]
//                                                                                 (cli/SuggestCommand)
//   sightline-cli gaps PROJECT.json [--json]                                      (cli/SuggestCommand)
//   sightline-cli coarse PROJECT.json [--kind closest|inner] [--triangles N] [--json] (cli/CoarseCommand)
//   sightline-cli pvs bake|merge|check|level|vis ...   (cli/PvsCommands, docs/pvs.md)
//   sightline-cli chart SPEC.json --out CHART.png   (cli/ChartCommand: the benchmark scripts' charts)
//
// Success returns 0; any failure prints one line "sightline-cli: error: ..." on stderr and
// returns non-zero.

#include <functional>
#include <iostream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "cli/AoCommand.h"
#include "cli/BenchCommand.h"
#include "cli/ChartCommand.h"
#include "cli/CoarseCommand.h"
#include "cli/DemoCommand.h"
#include "cli/DisagreementCommand.h"
#include "cli/InfoCommand.h"
#include "cli/LightingCommands.h"
#include "cli/LightsCommand.h"
#include "cli/PvsCommands.h"
#include "cli/ShaftCommand.h"
#include "cli/SuggestCommand.h"
#include "base/Error.h"

using namespace sightline;
using namespace sightline::cli;

int main(int argc, char** argv)
{
    CLI::App app{"Sightline: which rays between two patches are blocked, for level designers.\n"
                 "See docs/cli.md (README.md links every page); file formats and conventions: docs/design.md."};
    app.name("sightline-cli");
    app.set_version_flag("--version", "sightline-cli 0.1.0");
    app.require_subcommand(1);

    // Each subcommand: its options (cli/*.h) and how it runs once parsed, in --help's order.
    struct Command {
        CLI::App* app;
        std::function<int()> run;
    };
    std::vector<Command> commands;
    ShaftArgs shaft;
    CLI::App* shaftCmd = addShaftCommand(app, shaft);
    commands.push_back({shaftCmd, [&] { return runShaft(*shaftCmd, shaft); }});
    InfoArgs info;
    commands.push_back({addInfoCommand(app, info), [&] { return runInfo(info); }});
    BenchArgs bench;
    CLI::App* benchCmd = addBenchCommand(app, bench);
    commands.push_back({benchCmd, [&] { return runBench(*benchCmd, bench); }});
    ImportanceArgs importance;
    CLI::App* importanceCmd = addImportanceCommand(app, importance);
    commands.push_back({importanceCmd, [&] {
                            checkImportanceOptions(*importanceCmd, importance);
                            return runImportance(importance);
                        }});
    ShadowArgs shadow;
    CLI::App* shadowCmd = addShadowCommand(app, shadow);
    commands.push_back({shadowCmd, [&] {
                            checkShadowOptions(*shadowCmd, shadow);
                            return runShadow(shadow);
                        }});
    AoArgs ao;
    CLI::App* aoCmd = addAoCommand(app, ao);
    commands.push_back({aoCmd, [&] {
                            checkAoOptions(*aoCmd, ao);
                            return runAo(ao);
                        }});
    LightsArgs lights;
    CLI::App* lightsCmd = addLightsCommand(app, lights);
    commands.push_back({lightsCmd, [&] {
                            checkLightsOptions(*lightsCmd, lights);
                            return runLights(lights);
                        }});
    SuggestArgs suggest;
    commands.push_back({addSuggestCommand(app, suggest), [&] { return runSuggest(suggest); }});
    CoarseArgs coarse;
    commands.push_back({addCoarseCommand(app, coarse), [&] { return runCoarse(coarse); }});
    GapsArgs gaps;
    commands.push_back({addGapsCommand(app, gaps), [&] { return runGaps(gaps); }});
    DisagreementArgs disagreement;
    commands.push_back({addDisagreementCommand(app, disagreement), [&] { return runDisagreement(disagreement); }});
    PvsArgs pvs;
    commands.push_back({addPvsCommand(app, pvs), [&] { return runPvs(pvs, argc, argv); }});
    DemoArgs demo;
    commands.push_back({addDemoCommand(app, demo), [&] { return runDemo(demo); }});
    ChartArgs chart;
    commands.push_back({addChartCommand(app, chart), [&] { return runChart(chart); }});

    // CLI11 answers a misspelt subcommand ("sightline-cli shaf p.json") with "A subcommand is
    // required", as if none were given: name it and the ones there are.
    if (argc > 1 && argv[1][0] != '-') {
        std::string names;
        bool known = false;
        for (const CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; })) {
            known = known || sub->get_name() == argv[1];
            names += (names.empty() ? "" : ", ") + sub->get_name();
        }
        if (!known) {
            std::cerr << "sightline-cli: error: unknown subcommand '" << argv[1] << "' (" << names << "; see --help)\n";
            return 2;
        }
    }
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        std::cerr << "sightline-cli: error: " << e.what() << " (see --help)\n";
        return 2;
    }

    try {
        for (const Command& command : commands)
            if (*command.app)
                return command.run();
    } catch (const std::exception& e) {
        const CLI::App* command = app.get_subcommands().front();
        std::cerr << "sightline-cli: error: " << describeFailure(e, "running '" + command->get_name() + "'") << "\n";
        return 1;
    }
    return 1;
}
