#pragma once
// What `pvs bake` shares between its one-process, sharded and MPI forms: the loaded project,
// scene, cells, objects, hashes and baker, and the writer of every output format.

#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli/OutputPaths.h"
#include "cli/PvsCommands.h"
#include "project/PvsSetup.h"
#include "visibility/Scene.h"
#include "visibility/pvs/PvsBake.h"
#include "visibility/pvs/PvsData.h"
#include "visibility/pvs/PvsReference.h"

namespace sightline::cli {

struct PvsBakeJob {
    Scene scene;
    pvs::PvsData data;                  ///< cells, objects, hashes; rows empty
    std::unique_ptr<pvs::PvsBaker> baker;
    std::vector<PvsOverride> overrides;
    std::string settingsText;           ///< what settingsSha256 hashes
    double loadMs = 0.0;
};

/// Loads and checks everything, including that no output (args.outputs, args.gaps) would replace
/// a file the project names or one of `alsoRead`; throws sightline::Error with one line.
PvsBakeJob prepareBakeJob(const PvsBakeArgs& args, const std::vector<FileRole>& alsoRead = {});

/// Writes --out (.pvs) and the other formats asked for; returns the summary of sizes.
nlohmann::json writePvsOutputs(const pvs::PvsData& data, const PvsOutputs& outputs);

/// The summary a bake prints (text or --print-json), with the accuracy report when checked.
void printBakeSummary(const PvsBakeJob& job, const pvs::PvsData& data, const pvs::PvsStats& stats, double bakeMs,
                      int ranks, const nlohmann::json& sizes, const pvs::AccuracyReport* accuracy, const PvsBakeArgs& args);

/// The accuracy check of a bake, with the reference's default settings.
pvs::AccuracyReport checkBake(const PvsBakeJob& job, const pvs::PvsData& data, int threads);

/// sightline-cli pvs bake --mpi (PvsMpi.cpp, or a stub that says MPI is missing).
int runMpiBake(const PvsBakeArgs& args, int argc, char** argv);

} // namespace sightline::cli
