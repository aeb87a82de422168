#include "cli/PvsVisCommand.h"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "cli/OutputPaths.h"
#include "cli/Timing.h"
#include "base/AtomicFile.h"
#include "base/Error.h"
#include "base/InputFile.h"
#include "visibility/bsp/BspPortals.h"
#include "visibility/bsp/LeafWitness.h"
#include "visibility/bsp/PortalVis.h"
#include "visibility/bsp/QuakeBsp.h"

using nlohmann::json;

namespace sightline::cli {

namespace {

using Clock = std::chrono::steady_clock;

struct RowSizes {
    double meanVisible = 0.0;
    std::size_t lumpBytes = 0;
};

RowSizes rowSizes(const pvs::VisibilityRows& rows, std::size_t lumpBytes)
{
    return {rows.cellCount() ? double(rows.visibleCount()) / double(rows.cellCount()) : 0.0, lumpBytes};
}

/// Leaf pairs (ordered) the level's own rows hold and `rows` do not.
std::size_t culledHere(const pvs::VisibilityRows& rows, const pvs::VisibilityRows& level)
{
    std::size_t n = 0;
    for (std::size_t a = 0; a < rows.cellCount(); ++a)
        for (std::size_t b = 0; b < rows.objectCount(); ++b)
            n += level.visible(a, b) && !rows.visible(a, b);
    return n;
}

json witnessJson(const bsp::WitnessCount& w)
{
    json examples = json::array();
    for (const auto& [a, b] : w.examples)
        examples.push_back({a, b});
    return {{"pairs", w.pairs}, {"witnessed", w.witnessed}, {"examples", examples}};
}

struct VisRun {
    bsp::QuakeBsp level;
    std::size_t treePortals = 0, openPortals = 0;
    pvs::VisibilityRows rows, levelRows;
    std::string levelDamage;   ///< why the level's own rows could not be read (they are replaced all the same)
    bool compared() const { return level.hasVisibility() && levelDamage.empty(); }
    bsp::PortalVisStats stats;
    std::size_t lumpBytes = 0;
    double portalMs = 0.0, visMs = 0.0, checkMs = 0.0;
    std::optional<bsp::WitnessCount> culled, levelCulled, kept;
};

VisRun bake(const PvsVisArgs& args)
{
    VisRun run;
    run.level = bsp::readQuakeBsp(readInputFile(args.bsp, "BSP"), args.bsp);
    const bool clearLiquids = !args.opaqueLiquids;
    Clock::time_point start = Clock::now();
    const std::vector<bsp::LeafPortal> tree = bsp::treePortals(run.level);
    std::vector<bsp::LeafPortal> open;
    for (const bsp::LeafPortal& p : tree)
        if (bsp::seesThrough(run.level, p, clearLiquids))
            open.push_back(p);
    run.treePortals = tree.size();
    run.openPortals = open.size();
    run.portalMs = millisecondsSince(start);

    start = Clock::now();
    run.rows = bsp::portalVis(run.level, open, {.threads = args.threads}, &run.stats);
    run.visMs = millisecondsSince(start);
    run.lumpBytes = bsp::encodeVisibilityLump(run.rows).bytes.size();
    // The lump this replaces may be damaged: say so and go on, a new one is what is asked for.
    try {
        run.levelRows = bsp::levelVisibility(run.level, args.bsp);
    } catch (const Error& e) {
        run.levelDamage = e.what();
        std::cerr << "sightline-cli: warning: the level's own visibility lump is damaged (" << run.levelDamage
                  << "); it is not compared, and --out replaces it\n";
    }

    if (args.check > 0) {
        start = Clock::now();
        const bsp::WitnessOptions options{.segmentsPerPair = args.check, .clearLiquids = clearLiquids, .threads = args.threads};
        run.culled = bsp::searchWitnesses(run.level, tree, run.rows, true, options);
        if (run.compared())
            run.levelCulled = bsp::searchWitnesses(run.level, tree, run.levelRows, true, options);
        run.kept = bsp::searchWitnesses(run.level, tree, run.rows, false, options);
        run.checkMs = millisecondsSince(start);
    }
    if (!args.prt.empty())
        writeFileAtomically(args.prt, bsp::prt1(run.level, open));
    if (!args.out.empty())
        writeFileAtomically(args.out, bsp::withVisibility(run.level, run.rows));
    return run;
}

json runJson(const PvsVisArgs& args, const VisRun& run)
{
    const RowSizes ours = rowSizes(run.rows, run.lumpBytes);
    json out{{"bsp", args.bsp},
             {"format", bsp::formatName(run.level.format)},
             {"visleafs", run.level.visleafs},
             {"liquids", args.opaqueLiquids ? "opaque" : "clear"},
             {"portals", run.openPortals},
             {"tree_portals", run.treePortals},
             {"portals_ms", run.portalMs},
             {"vis_ms", run.visMs},
             {"chain_steps", run.stats.steps},
             {"portals_over_budget", run.stats.portalsOverBudget},
             {"visible_mean", ours.meanVisible},
             {"lump_bytes", ours.lumpBytes}};
    if (run.compared()) {
        const RowSizes level = rowSizes(run.levelRows, run.level.lumps[bsp::kVisibilityLump][1]);
        out["level"] = {{"visible_mean", level.meanVisible},
                        {"lump_bytes", level.lumpBytes},
                        {"pairs_it_keeps_culled_here", culledHere(run.rows, run.levelRows)},
                        {"pairs_culled_there_kept_here", culledHere(run.levelRows, run.rows)}};
    }
    if (run.culled) {
        out["check"] = {{"segments_per_pair", args.check}, {"check_ms", run.checkMs},
                        {"culled", witnessJson(*run.culled)}, {"kept", witnessJson(*run.kept)}};
        if (run.levelCulled)
            out["check"]["level_culled"] = witnessJson(*run.levelCulled);
    }
    if (!run.levelDamage.empty())
        out["level_damage"] = run.levelDamage;
    if (!args.out.empty())
        out["out"] = args.out;
    if (!args.prt.empty())
        out["prt"] = args.prt;
    return out;
}

void printRun(const PvsVisArgs& args, const VisRun& run)
{
    const RowSizes ours = rowSizes(run.rows, run.lumpBytes);
    std::printf("%s: %s, %d visleafs, %zu portals (liquids %s)\n", args.bsp.c_str(),
                bsp::formatName(run.level.format), run.level.visleafs, run.openPortals,
                args.opaqueLiquids ? "opaque" : "clear");
    std::printf("vis: %.2f s (portals %.2f s): %.1f leaves visible per leaf, lump %zu bytes\n", run.visMs / 1000.0,
                run.portalMs / 1000.0, ours.meanVisible, ours.lumpBytes);
    if (run.stats.portalsOverBudget)
        std::printf("  %zu portals ran past their step budget: their rows are their floods (safe, looser)\n",
                    run.stats.portalsOverBudget);
    if (run.compared()) {
        const RowSizes level = rowSizes(run.levelRows, run.level.lumps[bsp::kVisibilityLump][1]);
        std::printf("the level's own rows: %.1f leaves visible per leaf, lump %zu bytes; %zu of its visible pairs culled "
                    "here, %zu of its culled pairs kept here\n",
                    level.meanVisible, level.lumpBytes, culledHere(run.rows, run.levelRows), culledHere(run.levelRows, run.rows));
    }
    if (run.culled) {
        std::printf("check (%d segments per pair, %.2f s): culled pairs %zu, witnessed %zu", args.check,
                    run.checkMs / 1000.0, run.culled->pairs, run.culled->witnessed);
        if (run.levelCulled)
            std::printf("; the level's culled pairs %zu, witnessed %zu", run.levelCulled->pairs, run.levelCulled->witnessed);
        std::printf("; kept pairs %zu, witnessed %zu\n", run.kept->pairs, run.kept->witnessed);
    }
    if (!args.out.empty())
        std::printf("wrote %s\n", args.out.c_str());
    if (!args.prt.empty())
        std::printf("wrote %s\n", args.prt.c_str());
}

} // namespace

CLI::App* addPvsVisCommand(CLI::App& pvs, PvsVisArgs& a)
{
    CLI::App* vis = pvs.add_subcommand("vis", "Leaf-to-leaf visibility for a compiled Quake 1 or Half-Life level (BSP29, BSP2, BSP30), safe: "
                                              "written into a copy of the BSP (docs/pvs.md)");
    vis->add_option("bsp", a.bsp, "The compiled level (.bsp)")->required();
    vis->add_option("--out", a.out, "Write a copy of the level with the new visibility lump")->check(outputFile());
    vis->add_option("--prt", a.prt, "Write the level's portals as PRT1 (what vis tools read)")->check(outputFile());
    vis->add_flag("--opaque-liquids", a.opaqueLiquids, "Lines of sight stop at water, slime and lava surfaces");
    vis->add_option("--check", a.check, "Search witnesses, this many segments per leaf pair, for the new rows and the level's own")
        ->check(CLI::Range(1, 1 << 16));
    vis->add_option("--threads", a.threads, "Worker threads (0 = all cores; the rows never depend on it)")->check(CLI::Range(0, 1024));
    vis->add_flag("--print-json", a.printJson, "Print the summary as one JSON object");
    return vis;
}

int runPvsVis(const PvsVisArgs& args)
{
    checkOutputs({{"--out", args.out}, {"--prt", args.prt}}, {{"the level", args.bsp}});
    const VisRun run = bake(args);
    if (args.printJson)
        std::cout << runJson(args, run).dump() << "\n";
    else
        printRun(args, run);
    return 0;
}

} // namespace sightline::cli
