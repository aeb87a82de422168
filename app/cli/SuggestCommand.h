#pragma once
// The occluder assistant on the command line. sightline-cli suggest (docs/design.md §4, a
// contract): the smallest occluder on a plane between the patches that blocks a share of the rays
// now unblocked, checked by the exact sampler, and optionally saved into a copy of the project.
// sightline-cli gaps: the openings those rays pass through, largest first.

#include <limits>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "visibility/suggest/Openings.h"

namespace CLI {
class App;
}

namespace sightline::cli {

struct SuggestArgs {
    std::string project;
    double depth = std::numeric_limits<double>::quiet_NaN();   ///< NaN: not given
    std::vector<double> at, normal;                            ///< a picked surface instead of --depth
    double share = 1.0;
    bool weighted = false;   ///< the share of the light the rays carry (the project's "light"), not of their count
    std::string shape = "convex";
    std::string write;
    bool json = false;
    int threads = 0;
    bool allowOutsidePaths = false;
};

CLI::App* addSuggestCommand(CLI::App& app, SuggestArgs& args);
int runSuggest(const SuggestArgs& args);

/// sightline-cli gaps: the openings the view leaks through (visibility/suggest/ViewGaps.h).
struct GapsArgs {
    std::string project;
    bool json = false;
    int threads = 0;
    bool allowOutsidePaths = false;
};
CLI::App* addGapsCommand(CLI::App& app, GapsArgs& args);
int runGaps(const GapsArgs& args);

/// An opening as `gaps --json` and `pvs check --gaps` write it: rays, centre, min, max, clearance.
nlohmann::json openingJson(const suggest::Opening& opening);

} // namespace sightline::cli
