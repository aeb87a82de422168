#pragma once
// sightline-cli ao (docs/design.md §4): per-vertex (or per-texel) ambient occlusion of a
// mesh or a project's scene from the visibility matrix (Sattler et al. 2004), and the files a
// designer takes to an engine. See docs/ao.md.

#include <string>

namespace CLI {
class App;
}

namespace sightline::cli {

struct AoArgs {
    std::string input, npy, gltf, ply, lightmap, env;
    int k = 258;
    std::string method = "cpu";
    std::string weights = "solid-angle";
    std::string glBackend = "osmesa";
    int glResolution = 1024;
    double glSimplify = 0.25;   ///< texels (AoGlOptions::simplifyTexels)
    double rotate = 0.0, exposure = 0.0;
    double texel = 0.0;   ///< > 0: texel mode, texels per metre
    int threads = 0;
    bool json = false;
    bool allowOutsidePaths = false;
};

CLI::App* addAoCommand(CLI::App& app, AoArgs& args);
/// Throws sightline::Error for an option the chosen mode or method would ignore.
void checkAoOptions(const CLI::App& command, const AoArgs& args);
int runAo(const AoArgs& args);

} // namespace sightline::cli
