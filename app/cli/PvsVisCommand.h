#pragma once
// sightline-cli pvs vis: leaf-to-leaf visibility for a compiled Quake 1 or Half-Life level (BSP29,
// BSP2, BSP30), written back into a copy of the BSP as its visibility lump (docs/pvs.md, "Quake
// levels").

#include <string>

namespace CLI {
class App;
}

namespace sightline::cli {

struct PvsVisArgs {
    std::string bsp;
    std::string out;            ///< a copy of the BSP with the new visibility lump
    std::string prt;            ///< the portals as PRT1 (what vis tools read)
    bool opaqueLiquids = false;
    int check = 0;              ///< segments per leaf pair in the witness search; 0: none
    int threads = 0;
    bool printJson = false;
};

CLI::App* addPvsVisCommand(CLI::App& pvs, PvsVisArgs& args);
int runPvsVis(const PvsVisArgs& args);

} // namespace sightline::cli
