// libFuzzer harness for the Quake BSP reader and what runs on what it reads (docs/pvs.md, "Quake
// levels"): the level's own rows, the world's faces (what the scene importer reads), the portals
// rebuilt from its tree, the portal flow (with a small step budget) and the rewritten copy. Bad input must end in sightline::Error; anything else (a
// crash, a sanitizer report, a hang, memory beyond the limit) is a finding.

#include <cstdint>
#include <string>

#include "base/Error.h"
#include "visibility/bsp/BspPortals.h"
#include "visibility/bsp/PortalVis.h"
#include "visibility/bsp/QuakeBsp.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
    using namespace sightline;
    try {
        const bsp::QuakeBsp level = bsp::readQuakeBsp(std::string(reinterpret_cast<const char*>(data), size), "input.bsp");
        (void)bsp::levelVisibility(level, "input.bsp");
        (void)bsp::worldFaces(level, "input.bsp");
        const auto open = bsp::openPortals(level, true);
        (void)bsp::prt1(level, open);
        const auto rows = bsp::portalVis(level, open, {.stepsPerPortal = 20000, .threads = 1});
        (void)bsp::withVisibility(level, rows);
    } catch (const Error&) {
    }
    return 0;
}
