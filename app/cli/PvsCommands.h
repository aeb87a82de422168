#pragma once
// sightline-cli pvs bake / merge / check / level (docs/design.md §4's contract for bake and
// merge). The core is visibility/pvs (no MPI there); the MPI bake lives in PvsMpi.cpp, built only
// where CMake found MPI.

#include <string>
#include <vector>

#include "cli/PvsVisCommand.h"

namespace CLI {
class App;
}

namespace sightline::cli {

struct PvsOutputs {
    std::string out, json, quake1, quake2, prt;
    double prtScale = 1.0;
    bool raw = false;
};

struct PvsBakeArgs {
    std::string project;
    PvsOutputs outputs;
    std::string shard;          ///< "I/N", empty for all cells
    bool mpi = false;
    bool resume = false;        ///< --shard: keep an existing part of the same scene and settings
    int threads = 0;
    bool safe = false;
    bool noOpenSpace = false;
    int coarse = 0, fine = 0;   ///< sub-shafts per pair and pass; 0: the project's (or the defaults)
    double smallestGap = 0.0;   ///< 0: the project's
    int residueRays = -1;       ///< -1: the project's
    double maxDistance = -1.0;  ///< -1: the project's
    bool cellRows = false;      ///< also bake cell-to-cell rows (implied by --quake1 / --quake2)
    bool noRefine = false;
    bool check = false;         ///< measure accuracy in the same run
    std::string gaps;           ///< --check: write the gap list as JSON
    bool printJson = false;
    bool allowOutsidePaths = false;
};

struct PvsMergeArgs {
    std::vector<std::string> parts;
    PvsOutputs outputs;
    bool printJson = false;
};

struct PvsCheckArgs {
    std::string project, pvs, gaps;
    int cells = 64, cellPoints = 64, objectPoints = 64, views = 4;
    int threads = 0;
    bool printJson = false;
    bool allowOutsidePaths = false;
};

struct PvsLevelArgs {
    std::string folder;
    int roomsX = 16, roomsZ = 16, objects = 2000;
    int seed = 1;
    bool force = false;   ///< replace pvs_level.glb / pvs_level.json already in the folder
};

struct PvsArgs {
    PvsBakeArgs bake;
    PvsMergeArgs merge;
    PvsCheckArgs check;
    PvsLevelArgs level;
    PvsVisArgs vis;
    CLI::App* bakeCmd = nullptr;
    CLI::App* mergeCmd = nullptr;
    CLI::App* checkCmd = nullptr;
    CLI::App* levelCmd = nullptr;
    CLI::App* visCmd = nullptr;
};

CLI::App* addPvsCommand(CLI::App& app, PvsArgs& args);
/// Runs the chosen pvs subcommand. `argc`/`argv` reach MPI_Init under --mpi.
int runPvs(PvsArgs& args, int argc, char** argv);

/// Whether this build has the MPI bake (CMake found MPI).
bool pvsHasMpi();

} // namespace sightline::cli
