#include "cli/PvsCommands.h"

#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "cli/OutputLimits.h"
#include "cli/Timing.h"
#include "cli/OutputPaths.h"
#include "cli/PvsBakeJob.h"
#include "cli/SuggestCommand.h"
#include "demo/PvsLevel.h"
#include "plugins/SceneFormats.h"
#include "project/Project.h"
#include "base/AtomicFile.h"
#include "base/Error.h"
#include "base/InputFile.h"
#include "visibility/pvs/FirstHitCaster.h"
#include "visibility/pvs/OpenSpace.h"
#include "visibility/pvs/PvsFile.h"
#include "visibility/pvs/PvsObjects.h"
#include "visibility/pvs/Sha256.h"
#include "visibility/pvs/ViewCells.h"

namespace fs = std::filesystem;
using nlohmann::json;

namespace sightline::cli {

namespace {

std::string bytesOf(const std::vector<glm::vec3>& v)
{
    return std::string(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(glm::vec3));
}

/// "I/N" -> (I, N) with 0 <= I < N <= kMaxShards; throws for anything else. Digits only, read as
/// integers with their range checked before any narrowing.
std::pair<std::uint32_t, std::uint32_t> parseShard(const std::string& text)
{
    const auto fail = [&]() -> Error {
        return Error("--shard: expected I/N with 0 <= I < N <= " + std::to_string(pvs::kMaxShards) + " (e.g. 0/4), not '" +
                     text + "'");
    };
    const std::size_t slash = text.find('/');
    if (slash == std::string::npos)
        throw fail();
    auto whole = [&](std::string_view digits, std::uint64_t& value) {
        const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
        return !digits.empty() && ec == std::errc() && end == digits.data() + digits.size();
    };
    std::uint64_t i = 0, n = 0;
    const std::string_view view(text);
    if (!whole(view.substr(0, slash), i) || !whole(view.substr(slash + 1), n) || n == 0 || i >= n || n > pvs::kMaxShards)
        throw fail();
    return {std::uint32_t(i), std::uint32_t(n)};
}

/// The manifest written beside a part: an output of its own, checked like the others.
std::string manifestOf(const std::string& part) { return part + ".manifest.json"; }

/// Whether `part`'s manifest, when there, names these bytes. A part and a manifest out of step
/// (another bake's, or edited) are refused: a missing manifest is allowed (parts may travel alone,
/// and carry their own SHA-256).
void checkAgainstManifest(const std::string& part, const std::string& bytes)
{
    const std::string manifest = manifestOf(part);
    std::error_code ec;
    if (!fs::exists(manifest, ec))
        return;
    json m;
    try {
        m = json::parse(readInputFile(manifest, manifest));
    } catch (const json::exception&) {
        throw Error(manifest + ": not a part manifest (not JSON); bake the shard again or remove it");
    }
    if (!m.is_object() || !m.contains("part_sha256") || !m["part_sha256"].is_string())
        throw Error(manifest + ": has no part_sha256; bake the shard again or remove it");
    if (m["part_sha256"].get<std::string>() != pvs::sha256Hex(bytes))
        throw Error(part + ": does not match its manifest " + manifest + " (another bake's, or changed since); bake the shard again");
}

/// A file name that must not be empty: "--shard ''" or "--out ''" was taken for "not given".
CLI::Validator nonEmpty(const std::string& what)
{
    return CLI::Validator([what](std::string& value) { return value.empty() ? "an empty " + what : std::string(); },
                          "TEXT");
}

void writeText(const std::string& path, const std::string& bytes) { writeFileAtomically(path, bytes); }

/// What a PVS command writes never replaces what it reads, nor another of its outputs
/// (cli/OutputPaths.h): `pvs bake p.json --out p.json` replaced the project with the rows, and a
/// part's implicit manifest (PART.manifest.json) is an output too.
void checkPvsOutputs(const PvsOutputs& o, const std::string& gaps, const std::vector<FileRole>& inputs,
                     const std::string& manifest = {})
{
    if (!std::isfinite(o.prtScale) || o.prtScale < 1e-6 || o.prtScale > 1e6)
        throw Error("--prt-scale: units per metre must be a number in [1e-6, 1e6]");
    checkOutputs({{"--out", o.out}, {"--json", o.json}, {"--quake1", o.quake1}, {"--quake2", o.quake2}, {"--prt", o.prt},
                  {"--gaps", gaps}, {"the part's manifest (--out + .manifest.json)", manifest}},
                 inputs);
}

void addOutputOptions(CLI::App* cmd, PvsOutputs& o, bool outRequired)
{
    auto* out = cmd->add_option("--out", o.out, "Write the binary .pvs (docs/pvs.md)")->check(outputFile());
    if (outRequired)
        out->required();
    cmd->add_option("--json", o.json, "Also write docs/design.md §4's .pvs.json")->check(outputFile());
    cmd->add_option("--quake1", o.quake1, "Also write Quake 1 style cell-to-cell rows: numleafs, visofs[], zero-run-length rows")
        ->check(outputFile());
    cmd->add_option("--quake2", o.quake2, "Also write a Quake 2 / Source vis lump of cell-to-cell rows: numclusters, bitofs[n][2], rows")
        ->check(outputFile());
    cmd->add_option("--prt", o.prt, "Also write the cells' shared faces as a PRT1 portal file (TrenchBroom)")->check(outputFile());
    cmd->add_option("--prt-scale", o.prtScale, "PRT1 units per metre (1 keeps metres; 39.37 gives Quake units)")
        ->check(CLI::Range(1e-6, 1e6));
    cmd->add_flag("--raw", o.raw, "Store .pvs rows raw instead of zero-run-length encoded");
}

json accuracyJson(const pvs::AccuracyReport& a)
{
    return {{"reference_cells", a.cells.size()}, {"reference_visible_pairs", a.referenceVisible},
            {"baked_visible_pairs", a.bakedVisible}, {"missed_pairs", a.missed}, {"extra_pairs", a.extra},
            {"object_miss_rate", a.objectMissRate()}, {"pixels", a.pixels}, {"wrong_pixels", a.wrongPixels},
            {"pixel_error_rate", a.pixelErrorRate()}, {"pvs_size_ratio", a.sizeRatio()}, {"reference_rays", a.rays},
            {"reference_ms", a.ms}, {"gaps", a.gaps.size()}, {"edge_visible_pairs", a.edgeVisible},
            {"edge_missed_pairs", a.edgeMissed}, {"edge_rays", a.edgeRays}, {"adversarial_miss_rate", a.adversarialMissRate()}};
}

void writeGaps(const std::string& path, const pvs::AccuracyReport& a, const pvs::PvsData& data)
{
    json gaps = json::array();
    for (const pvs::Gap& g : a.gaps)
        gaps.push_back({{"cell", g.cell}, {"object", g.object}, {"name", data.objects[g.object].name},
                        {"from", {g.from.x, g.from.y, g.from.z}}, {"to", {g.to.x, g.to.y, g.to.z}},
                        {"opening", openingJson(g.opening)}});
    writeText(path, dumpJson(json{{"gaps", gaps}}) + "\n");
}

void printAccuracy(const pvs::AccuracyReport& a)
{
    std::printf("reference  %zu cells: %llu visible pairs; PVS keeps %llu (%.3fx), misses %llu (object miss rate %.3g)\n",
                a.cells.size(), (unsigned long long)a.referenceVisible, (unsigned long long)a.bakedVisible, a.sizeRatio(),
                (unsigned long long)a.missed, a.objectMissRate());
    std::printf("edges      %llu more visible pairs found along the blockers' edges, %llu of them culled (miss rate with "
                "them %.3g; %llu rays)\n",
                (unsigned long long)a.edgeVisible, (unsigned long long)a.edgeMissed, a.adversarialMissRate(),
                (unsigned long long)a.edgeRays);
    std::printf("pixels     %llu rendered, %llu culled wrongly (pixel error rate %.3g); %.1f ms\n",
                (unsigned long long)a.pixels, (unsigned long long)a.wrongPixels, a.pixelErrorRate(), a.ms);
}

int runBake(const PvsBakeArgs& args, int argc, char** argv)
{
    if (args.mpi) {
        if (!args.shard.empty())
            throw Error("--mpi and --shard: under MPI the ranks share the cells; use one or the other");
        return runMpiBake(args, argc, argv);
    }
    const auto start = std::chrono::steady_clock::now();
    PvsBakeJob job = prepareBakeJob(args);
    if (!args.shard.empty()) {
        const auto [shard, count] = parseShard(args.shard);
        if (!args.outputs.json.empty() || !args.outputs.quake1.empty() || !args.outputs.quake2.empty() ||
            !args.outputs.prt.empty() || args.check)
            throw Error("--shard writes a part file only; --json, --quake1, --quake2, --prt and --check belong to "
                        "'pvs merge' (or to a bake without --shard)");
        const auto cells = pvs::shardCells(job.data.cells.size(), shard, count);
        if (args.resume && fs::exists(args.outputs.out)) {
            try {
                const std::string bytes = readInputFile(args.outputs.out, args.outputs.out);
                const pvs::PvsPart old = pvs::decodePart(bytes, args.outputs.out);
                checkAgainstManifest(args.outputs.out, bytes);
                if (old.data.sceneSha256 == job.data.sceneSha256 && old.data.settingsSha256 == job.data.settingsSha256 &&
                    old.shard == shard && old.shardCount == count && fs::exists(manifestOf(args.outputs.out))) {
                    std::printf("kept       %s (shard %u/%u already baked with these settings)\n", args.outputs.out.c_str(),
                                shard, count);
                    return 0;
                }
            } catch (const Error& e) {
                std::fprintf(stderr, "sightline-cli: baking %s again: %s\n", args.outputs.out.c_str(), e.what());
            }
        }
        pvs::PvsStats stats;
        const auto bakeStart = std::chrono::steady_clock::now();
        pvs::PvsPart part;
        part.data = job.data;
        part.data.rows = cells.empty() ? pvs::VisibilityRows(job.data.cells.size(), job.data.objects.size())
                                       : job.baker->bake(cells, {}, &stats);
        if (job.baker->settings().cellRows)
            part.data.cellRows = cells.empty() ? pvs::VisibilityRows(job.data.cells.size(), job.data.cells.size())
                                               : job.baker->bakeCellRows(cells, {}, &stats);
        applyPvsOverrides(job.overrides, part.data.rows);
        // Only the shard's rows: overrides touched every cell.
        for (std::size_t c = 0; c < part.data.cells.size(); ++c)
            if (c % count != shard)
                std::fill(part.data.rows.row(c), part.data.rows.row(c) + part.data.rows.rowBytes(), std::uint8_t(0));
        const double bakeMs = millisecondsSince(bakeStart);
        part.shard = shard;
        part.shardCount = count;
        for (std::size_t c : cells)
            part.cellIndices.push_back(std::uint32_t(c));
        const std::string bytes = pvs::encodePart(part);
        writeText(manifestOf(args.outputs.out), pvs::partManifest(part, pvs::sha256Hex(bytes), job.settingsText));
        writeText(args.outputs.out, bytes);   // last: a part that exists is complete
        if (args.printJson)
            std::cout << dumpJson(json{{"shard", shard}, {"shards", count}, {"cells_in_part", cells.size()},
                                       {"bake_ms", bakeMs}, {"ms", millisecondsSince(start)}, {"part", args.outputs.out}})
                      << "\n";
        else
            std::printf("part       %s: shard %u/%u, %zu of %zu cells, %.1f ms\n", args.outputs.out.c_str(), shard, count,
                        cells.size(), job.data.cells.size(), bakeMs);
        return 0;
    }
    pvs::PvsStats stats;
    const auto bakeStart = std::chrono::steady_clock::now();
    pvs::PvsData data = job.data;
    data.rows = job.baker->bake({}, {}, &stats);
    if (job.baker->settings().cellRows)
        data.cellRows = job.baker->bakeCellRows({}, {}, &stats);
    applyPvsOverrides(job.overrides, data.rows);
    const double bakeMs = millisecondsSince(bakeStart);
    const json sizes = writePvsOutputs(data, args.outputs);
    std::optional<pvs::AccuracyReport> accuracy;
    if (args.check) {
        accuracy = checkBake(job, data, args.threads);
        if (!args.gaps.empty())
            writeGaps(args.gaps, *accuracy, data);
    }
    printBakeSummary(job, data, stats, bakeMs, 1, sizes, accuracy ? &*accuracy : nullptr, args);
    return 0;
}

int runMerge(const PvsMergeArgs& args)
{
    std::vector<FileRole> inputs;
    for (const std::string& name : args.parts) {
        inputs.push_back({"the part file", name});
        inputs.push_back({"the part's manifest", manifestOf(name)});
    }
    checkPvsOutputs(args.outputs, {}, inputs);
    std::vector<pvs::PvsPart> parts;
    for (const std::string& name : args.parts) {
        const std::string bytes = readInputFile(name, name);
        parts.push_back(pvs::decodePart(bytes, name));
        checkAgainstManifest(name, bytes);
    }
    const pvs::PvsData data = pvs::mergeParts(parts, args.parts);
    const json sizes = writePvsOutputs(data, args.outputs);
    if (args.printJson)
        std::cout << dumpJson(json{{"parts", parts.size()}, {"cells", data.cells.size()}, {"objects", data.objects.size()},
                                   {"visible_pairs", data.rows.visibleCount()}, {"sizes", sizes}})
                  << "\n";
    else
        std::printf("merged     %zu parts: %zu cells x %zu objects, %zu visible pairs -> %s (rows %llu bytes raw, %llu "
                    "zero-run-length)\n",
                    parts.size(), data.cells.size(), data.objects.size(), data.rows.visibleCount(), args.outputs.out.c_str(),
                    (unsigned long long)sizes["raw_row_bytes"].get<std::uint64_t>(),
                    (unsigned long long)sizes["compressed_row_bytes"].get<std::uint64_t>());
    return 0;
}

int runCheck(const PvsCheckArgs& args)
{
    PvsBakeArgs bakeArgs;
    bakeArgs.project = args.project;
    bakeArgs.gaps = args.gaps;
    bakeArgs.allowOutsidePaths = args.allowOutsidePaths;
    const PvsBakeJob job = prepareBakeJob(bakeArgs, {{"the .pvs file", args.pvs}});
    const pvs::PvsData data = pvs::decodePvs(readInputFile(args.pvs, args.pvs), args.pvs);
    if (data.sceneSha256 != job.data.sceneSha256)
        throw Error(args.pvs + " was baked from another scene (scene sha256 " + data.sceneSha256.substr(0, 12) + "..., " +
                    args.project + "'s is " + job.data.sceneSha256.substr(0, 12) + "...)");
    pvs::ReferenceSettings settings;
    settings.cells = args.cells;
    settings.cellPoints = args.cellPoints;
    settings.objectPoints = args.objectPoints;
    settings.views = args.views;
    settings.threads = args.threads;
    const pvs::AccuracyReport a = pvs::measureAccuracy(job.scene, data, settings);
    if (!args.gaps.empty())
        writeGaps(args.gaps, a, data);
    if (args.printJson)
        std::cout << dumpJson(accuracyJson(a)) << "\n";
    else
        printAccuracy(a);
    return 0;
}

int runLevel(const PvsLevelArgs& args)
{
    const fs::path sceneFile = fs::path(args.folder) / "pvs_level.glb";
    const fs::path projectFile = fs::path(args.folder) / "pvs_level.json";
    std::error_code ec;
    for (const fs::path& file : {sceneFile, projectFile})
        if (!args.force && fs::exists(file, ec))
            throw Error(file.string() + " already exists; choose another folder, or add --force to replace it");
    fs::create_directories(args.folder, ec);
    if (ec)
        throw Error(args.folder + ": cannot create folder (" + ec.message() + ")");
    const demo::PvsLevel level = demo::makePvsLevel(args.roomsX, args.roomsZ, args.objects, std::uint64_t(args.seed));
    saveScene(level.scene, sceneFile);
    Project project;
    project.folder = fs::absolute(args.folder);
    project.scene = sceneFile.filename().string();
    project.source = level.source;
    project.receiver = level.receiver;
    json cells = json::array();
    for (const Bounds& b : level.cells)
        cells.push_back({{"min", {b.min.x, b.min.y, b.min.z}}, {"max", {b.max.x, b.max.y, b.max.z}}});
    project.extra["pvs"] = {{"cells", cells}};
    project.extra["description"] = "Sightline PVS benchmark level: " + std::to_string(args.roomsX) + " x " +
                                   std::to_string(args.roomsZ) + " rooms (levelgen/demo/PvsLevel.h)";
    saveProject(project, projectFile);
    std::printf("wrote %s (%zu instances, %zu triangles) and %s (%zu cells)\n", sceneFile.c_str(), level.scene.instances.size(),
                level.scene.triangleCount(), projectFile.c_str(), level.cells.size());
    return 0;
}

} // namespace

PvsBakeJob prepareBakeJob(const PvsBakeArgs& args, const std::vector<FileRole>& alsoRead)
{
    const auto start = std::chrono::steady_clock::now();
    PvsBakeJob job;
    const Project project = loadProject(args.project, {.allowOutsidePaths = args.allowOutsidePaths});
    std::vector<FileRole> inputs = projectInputs(args.project, project);
    inputs.insert(inputs.end(), alsoRead.begin(), alsoRead.end());
    checkPvsOutputs(args.outputs, args.gaps, inputs, args.shard.empty() ? std::string() : manifestOf(args.outputs.out));
    const std::string what = fs::path(args.project).filename().string();
    PvsSetup setup = parsePvsSetup(project, what);
    // CLI11's ranges let NaN through, and a NaN here would read as "not given".
    if (!std::isfinite(args.smallestGap) || !std::isfinite(args.maxDistance))
        throw Error(std::string(std::isfinite(args.smallestGap) ? "--max-distance" : "--smallest-gap") +
                    ": must be a finite number of metres");
    if (args.coarse > 0)
        setup.settings.coarseShafts = args.coarse;
    if (args.fine > 0)
        setup.settings.fineShafts = args.fine;
    if (args.smallestGap > 0.0)
        setup.settings.smallestGap = args.smallestGap;
    if (args.residueRays >= 0)
        setup.settings.residueRays = args.residueRays;
    if (args.maxDistance >= 0.0)
        setup.settings.maxDistance = args.maxDistance;
    if (args.cellRows || !args.outputs.quake1.empty() || !args.outputs.quake2.empty())
        setup.settings.cellRows = true;
    if (args.safe)
        setup.settings.safe = true;
    if (args.noOpenSpace)
        setup.settings.openSpace = false;
    if (args.noRefine)
        setup.settings.refine = false;
    setup.settings.threads = args.threads;
    setup.settings.validate();
    if (project.scene.empty())
        throw Error(what + ": has no scene to bake a PVS of");
    const fs::path sceneFile = project.resolve(project.scene, "scene");
    job.data.sceneSha256 = pvs::sha256Hex(readInputFile(sceneFile, sceneFile.filename().string()));
    std::vector<std::string> warnings;
    job.scene = buildScene(project, &warnings);
    printWarnings(warnings);
    if (setup.gridCells) {
        const pvs::FirstHitCaster caster(job.scene);
        try {
            setup.cells = pvs::gridCells(job.scene, caster, setup.grid);
        } catch (const Error& e) {
            throw Error(what + ": " + e.what());
        }
    }
    pvs::validateCells(setup.cells, what + ": pvs cells");
    job.data.cells = setup.cells;
    job.data.objects = pvs::sceneObjects(job.scene, setup.groupByName);
    job.overrides = resolvePvsOverrides(setup.overridesJson, job.data.objects, job.data.cells.size(), what);
    // Everything that changes the answer, hashed: a part from other settings is refused at merge.
    const WorldTriangles world = worldTriangles(job.scene);
    std::string names;
    for (const Instance& i : job.scene.instances)
        names += i.name + '\n';
    std::string cellBytes;
    for (const Bounds& b : job.data.cells)
        cellBytes += bytesOf({b.min, b.max});
    job.settingsText = setup.settings.canonical() + "\nworld " +
                       pvs::sha256Hex(bytesOf(world.vertices) +
                                      std::string(reinterpret_cast<const char*>(world.instanceOf.data()),
                                                  world.instanceOf.size() * 4) +
                                      names) +
                       "\ncells " + pvs::sha256Hex(cellBytes) + "\ngroup_by_name " + (setup.groupByName ? "1" : "0") +
                       "\noverrides " + setup.overridesJson.dump() + "\n";
    job.data.settingsSha256 = pvs::sha256Hex(job.settingsText);
    job.baker = std::make_unique<pvs::PvsBaker>(job.scene, job.data.cells, job.data.objects, job.data.sceneSha256,
                                                setup.settings);
    job.loadMs = millisecondsSince(start);
    return job;
}

json writePvsOutputs(const pvs::PvsData& data, const PvsOutputs& o)
{
    const pvs::EncodedSizes sizes = pvs::encodedSizes(data.rows);
    json out = {{"raw_row_bytes", sizes.raw}, {"compressed_row_bytes", sizes.compressed}};
    if (data.hasCellRows()) {
        const pvs::EncodedSizes cellSizes = pvs::encodedSizes(data.cellRows);
        out["cell_rows_raw_bytes"] = cellSizes.raw;
        out["cell_rows_compressed_bytes"] = cellSizes.compressed;
    }
    if ((!o.quake1.empty() || !o.quake2.empty()) && !data.hasCellRows())
        throw Error(std::string(o.quake1.empty() ? "--quake2" : "--quake1") +
                    " writes cell-to-cell rows (the engines' clusters), and these parts have none: bake them with --cell-rows");
    const std::string bytes = pvs::encodePvs(data, o.raw ? pvs::RowEncoding::Raw : pvs::RowEncoding::ZeroRuns);
    out["pvs_bytes"] = bytes.size();
    if (!o.json.empty())
        writeText(o.json, pvs::pvsJson(data));
    if (!o.quake1.empty()) {
        const std::string q = pvs::quake1Vis(data.cellRows);
        out["quake1_bytes"] = q.size();
        writeText(o.quake1, q);
    }
    if (!o.quake2.empty()) {
        const std::string q = pvs::quake2Vis(data.cellRows);
        out["quake2_bytes"] = q.size();
        writeText(o.quake2, q);
    }
    if (!o.prt.empty())
        writeText(o.prt, pvs::prt1(data.cells, o.prtScale));
    if (!o.out.empty())
        writeText(o.out, bytes);
    return out;
}

pvs::AccuracyReport checkBake(const PvsBakeJob& job, const pvs::PvsData& data, int threads)
{
    pvs::ReferenceSettings settings;
    settings.threads = threads;
    return pvs::measureAccuracy(job.scene, data, settings);
}

json openSpaceJson(const pvs::OpenSpaceStats& s)
{
    return {{"leaves", s.leaves},         {"passages", s.passages},       {"sealed_passages", s.sealedPassages},
            {"open_leaves", s.openLeaves}, {"open_portals", s.openPortals}, {"parts", s.parts},
            {"portal_vis", s.portalVis},   {"build_ms", s.buildMs},         {"vis_ms", s.visMs}};
}

void printBakeSummary(const PvsBakeJob& job, const pvs::PvsData& data, const pvs::PvsStats& stats, double bakeMs, int ranks,
                      const json& sizes, const pvs::AccuracyReport* accuracy, const PvsBakeArgs& args)
{
    const std::size_t pairs = data.cells.size() * data.objects.size();
    if (args.printJson) {
        json out = {{"cells", data.cells.size()},
                    {"objects", data.objects.size()},
                    {"visible_pairs", data.rows.visibleCount()},
                    {"visible_fraction", pairs ? double(data.rows.visibleCount()) / double(pairs) : 0.0},
                    {"ms", bakeMs},
                    {"load_ms", job.loadMs},
                    {"coarse_ms", stats.coarseMs},
                    {"refine_ms", stats.refineMs},
                    {"cell_rows_ms", stats.cellRowsMs},
                    {"ranks", ranks},
                    {"threads", args.threads},
                    {"triangles", job.scene.triangleCount()},
                    {"overlap_pairs", stats.overlapPairs},
                    {"direct_witnesses", stats.directWitnesses},
                    {"shaft_witnesses", stats.shaftWitnesses},
                    {"proven_hidden", stats.provenHidden},
                    {"space_hidden", stats.spaceHidden},
                    {"open_space", openSpaceJson(job.baker->openSpaceStats())},
                    {"unknown_pairs", stats.unknownPairs},
                    {"residue_witnesses", stats.search.residueWitnesses},
                    {"safe_kept", stats.safeKept},
                    {"distance_culled", stats.distanceCulled},
                    {"node_tests", stats.nodeTests},
                    {"nodes_culled", stats.nodesCulled},
                    {"direct_casts", stats.directCasts},
                    {"sub_shafts", stats.search.shafts},
                    {"shaft_casts", stats.search.casts},
                    {"plane_proofs", stats.search.planeProofs},
                    {"solid_proofs", stats.search.solidProofs},
                    {"open_sub_shafts", stats.search.openShafts},
                    {"residue_rays", stats.search.residueRays},
                    {"scene_sha256", data.sceneSha256},
                    {"settings_sha256", data.settingsSha256},
                    {"sizes", sizes}};
        if (accuracy)
            out["accuracy"] = accuracyJson(*accuracy);
        std::cout << dumpJson(out) << "\n";
        return;
    }
    std::printf("scene      %zu triangles, %zu cells x %zu objects (load %.1f ms)\n", job.scene.triangleCount(),
                data.cells.size(), data.objects.size(), job.loadMs);
    std::printf("bake       %.1f ms (coarse %.1f, refine %.1f); %llu pairs proven hidden, %llu unknown (%s)%s\n", bakeMs,
                stats.coarseMs, stats.refineMs, (unsigned long long)stats.provenHidden, (unsigned long long)stats.unknownPairs,
                job.baker->settings().safe ? "kept: safe mode" : "culled after the residue rays", ranks > 1 ? (" over " + std::to_string(ranks) + " ranks").c_str() : "");
    const pvs::OpenSpaceStats& space = job.baker->openSpaceStats();
    if (!job.baker->settings().openSpace)
        std::printf("open space off\n");
    else
        std::printf("open space %zu boxes, %zu of %zu passages sealed; %zu open boxes, %zu portals (%s) in %zu parts: "
                "%llu pairs proven hidden (%.1f + %.1f ms)\n",
                space.leaves, space.sealedPassages, space.passages, space.openLeaves, space.openPortals,
                space.portalVis ? "portal vis" : "flood only", space.parts, (unsigned long long)stats.spaceHidden,
                space.buildMs, space.visMs);
    std::printf("visible    %zu of %zu pairs (%.2f%%)\n", data.rows.visibleCount(), pairs,
                pairs ? 100.0 * double(data.rows.visibleCount()) / double(pairs) : 0.0);
    std::printf("rows       %llu bytes raw, %llu zero-run-length; .pvs %llu bytes\n",
                (unsigned long long)sizes["raw_row_bytes"].get<std::uint64_t>(),
                (unsigned long long)sizes["compressed_row_bytes"].get<std::uint64_t>(),
                (unsigned long long)sizes["pvs_bytes"].get<std::uint64_t>());
    if (accuracy)
        printAccuracy(*accuracy);
}

CLI::App* addPvsCommand(CLI::App& app, PvsArgs& args)
{
    CLI::App* pvsCmd = app.add_subcommand("pvs", "Potentially visible sets: bake, merge parts, check accuracy, make a test level, vis a Quake level");
    pvsCmd->require_subcommand(1);

    PvsBakeArgs& b = args.bake;
    CLI::App* bake = pvsCmd->add_subcommand("bake", "Bake which objects each view cell may see (docs/pvs.md)");
    bake->add_option("project", b.project, "Project file (JSON, docs/design.md §3; its \"pvs\" key sets cells and objects)")
        ->required();
    addOutputOptions(bake, b.outputs, true);
    bake->add_option("--shard", b.shard, "Bake the I-th of N shares of the cells into a part file (--out PART)")
        ->check(nonEmpty("shard; give I/N, e.g. 0/4"));
    bake->add_flag("--resume", b.resume, "--shard: keep an existing part of the same scene and settings");
    bake->add_flag("--mpi", b.mpi, "Under mpirun: the ranks share the cells, rank 0 writes the outputs");
    bake->add_option("--threads", b.threads, "Worker threads (0 = all cores; the output never depends on it)")
        ->check(CLI::Range(0, 1024));
    bake->add_flag("--safe", b.safe, "Safe mode: cull only pairs proven hidden (docs/pvs.md)");
    bake->add_flag("--no-open-space", b.noOpenSpace, "Skip the open-space proof (docs/pvs.md), to measure what it gains");
    bake->add_option("--coarse", b.coarse, "Sub-shafts per (cell, target), coarse pass")->check(CLI::Range(1, pvs::kMaxCoarseShafts));
    bake->add_option("--fine", b.fine, "Sub-shafts per (cell, target), refine pass")->check(CLI::Range(1, pvs::kMaxFineShafts));
    bake->add_option("--smallest-gap", b.smallestGap, "Metres: the refine pass splits shafts down to this spread")
        ->check(CLI::Range(1e-4, 100.0));
    bake->add_option("--residue-rays", b.residueRays, "Default mode: rays per pair over what no proof or witness settled")
        ->check(CLI::Range(0, pvs::kMaxResidueRays));
    bake->add_option("--max-distance", b.maxDistance, "Metres: cull what is farther from the cell (0: no cut-off)")
        ->check(CLI::Range(0.0, 1e7));
    bake->add_flag("--cell-rows", b.cellRows, "Also bake cell-to-cell rows (--quake1 and --quake2 write them)");
    bake->add_flag("--no-refine", b.noRefine, "Coarse pass only");
    bake->add_flag("--check", b.check, "Measure accuracy against the dense reference in the same run");
    bake->add_option("--gaps", b.gaps, "--check: write the gap list (the openings of each missed pair, with a witness ray through each) as JSON")
        ->check(outputFile());
    bake->add_flag("--print-json", b.printJson, "Print the summary as one JSON object");
    bake->add_flag("--allow-outside-paths", b.allowOutsidePaths,
                   "Read files the project names by a relative path that leaves its folder");
    args.bakeCmd = bake;

    PvsMergeArgs& m = args.merge;
    CLI::App* merge = pvsCmd->add_subcommand("merge", "Join the part files of a sharded bake into one PVS");
    merge->add_option("parts", m.parts, "Part files (one per shard)")->required();
    addOutputOptions(merge, m.outputs, true);
    merge->add_flag("--print-json", m.printJson, "Print the summary as one JSON object");
    args.mergeCmd = merge;

    PvsCheckArgs& c = args.check;
    CLI::App* check = pvsCmd->add_subcommand("check", "Measure a .pvs against the dense reference: object miss rate, "
                                                      "pixel error rate, size, gap list");
    check->add_option("project", c.project, "The project it was baked from")->required();
    check->add_option("pvs", c.pvs, "The .pvs file")->required();
    check->add_option("--cells", c.cells, "Random reference cells")->check(CLI::Range(1, 1000000))->capture_default_str();
    check->add_option("--cell-points", c.cellPoints, "Stratified points per cell")->check(CLI::Range(1, 65536))->capture_default_str();
    check->add_option("--object-points", c.objectPoints, "Points per object")->check(CLI::Range(1, 65536))->capture_default_str();
    check->add_option("--views", c.views, "Panoramas per cell (pixel error)")->check(CLI::Range(0, 4096))->capture_default_str();
    check->add_option("--threads", c.threads, "Worker threads (0 = all cores)")->check(CLI::Range(0, 1024));
    check->add_option("--gaps", c.gaps, "Write the gap list (the openings of each missed pair, with a witness ray through each) as JSON")->check(outputFile());
    check->add_flag("--print-json", c.printJson, "Print one JSON object");
    check->add_flag("--allow-outside-paths", c.allowOutsidePaths,
                    "Read files the project names by a relative path that leaves its folder");
    args.checkCmd = check;

    PvsLevelArgs& l = args.level;
    CLI::App* level = pvsCmd->add_subcommand("level", "Write a generated PVS benchmark level (pvs_level.glb, pvs_level.json)");
    level->add_option("folder", l.folder, "Output folder")->required()->check(nonEmpty("folder name; name the folder to write"));
    level->add_flag("--force", l.force, "Replace a pvs_level.glb / pvs_level.json already in the folder");
    level->add_option("--rooms", l.roomsX, "Rooms along x and z (16 gives 4,096 cells)")->check(CLI::Range(1, 256))->capture_default_str();
    level->add_option("--objects", l.objects, "Instances in all (walls, floor, props)")->check(CLI::Range(1, 1000000))->capture_default_str();
    level->add_option("--seed", l.seed, "Layout seed")->check(CLI::Range(0, 1000000))->capture_default_str();
    args.levelCmd = level;
    args.visCmd = addPvsVisCommand(*pvsCmd, args.vis);
    return pvsCmd;
}

int runPvs(PvsArgs& args, int argc, char** argv)
{
    if (*args.bakeCmd) {
        if (!args.bake.gaps.empty() && !args.bake.check)
            throw Error("--gaps lists what --check finds; add --check");
        return runBake(args.bake, argc, argv);
    }
    if (*args.mergeCmd)
        return runMerge(args.merge);
    if (*args.checkCmd)
        return runCheck(args.check);
    if (*args.levelCmd) {
        args.level.roomsZ = args.level.roomsX;
        return runLevel(args.level);
    }
    if (*args.visCmd)
        return runPvsVis(args.vis);
    return 1;
}

} // namespace sightline::cli
