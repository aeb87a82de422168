#pragma once
// The editor's PVS debugger: the project's PVS baked in the background (the coarse
// pass over every cell first, then refinement, PvsBake.h), and, for the view cell the camera is
// in, which objects of the level it may see. The viewport tints the culled ones; freezing keeps
// the cell while the camera flies around it. Once the bake is over, the same worker measures it
// against the dense reference (PvsReference.h, in its random cells) and hands over the gap list:
// where the reference saw an object through an opening the bake culled it behind, shown as
// markers. Plain C++ (no Qt): the caller decides how an answer reaches its thread.

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <glm/vec3.hpp>

#include "project/Project.h"
#include "visibility/Scene.h"
#include "visibility/pvs/PvsBake.h"
#include "visibility/pvs/PvsData.h"
#include "visibility/pvs/PvsReference.h"

namespace sightline::ui {

/// What the bake has said so far: set once (`cells`, `objects` with `started`), then one row per
/// cell and pass as the cells are done.
struct PvsDebugEvent {
    std::uint64_t generation = 0;
    bool started = false;                 ///< cells and objects are set
    std::vector<Bounds> cells;
    std::vector<pvs::PvsObject> objects;
    std::optional<std::size_t> cell;      ///< a row for this cell
    pvs::PvsPass pass = pvs::PvsPass::Coarse;
    std::vector<std::uint8_t> row;
    bool finished = false;                ///< the bake is over (or failed: `error`)
    double ms = 0.0;
    std::string error;
    /// After `finished`: the accuracy check (gaps and counts over its reference cells).
    bool checked = false;
    std::vector<pvs::Gap> gaps;
    std::size_t referenceCells = 0;
    std::uint64_t referenceVisible = 0, missed = 0;
};

class PvsDebugger {
public:
    using Deliver = std::function<void(PvsDebugEvent event)>;   ///< called on worker threads
    explicit PvsDebugger(Deliver deliver);
    ~PvsDebugger();
    PvsDebugger(const PvsDebugger&) = delete;
    PvsDebugger& operator=(const PvsDebugger&) = delete;

    /// Cancels a running bake and starts one of `scene` (the level and the placed occluders) with
    /// the project's "pvs" settings (PvsSetup.h); `what` names the project in messages.
    void start(std::uint64_t generation, std::shared_ptr<const Scene> scene, Project project, std::string what);
    void stop();

private:
    Deliver deliver_;
    std::shared_ptr<std::atomic<bool>> cancel_;
    std::thread thread_;
};

/// The bake's seed in the editor: the hash of the scene's world triangles (unsaved edits included),
/// not of the file's bytes as `pvs bake` uses, so the two can differ by sampling alone.
std::string editorPvsSeed(const Scene& scene);

/// What a bake of `project` depends on besides the scene: its PVS settings (less the distance
/// cut-off and the overrides, which are applied over a bake), cells and grouping. A change of it
/// needs a new bake; the text of a parse error stands for a project that cannot be baked.
std::string pvsBakeKey(const Project& project);

/// The distance cut-off (PvsSettings::maxDistance, the project's pvs.max_distance) applied over
/// baked rows: objects whose bounds lie farther than `maxDistance` from a cell's box are culled
/// from its row, as the bake culls them. 0 or less: nothing changes.
void applyDistanceCutoff(const std::vector<Bounds>& cells, const std::vector<pvs::PvsObject>& objects, double maxDistance,
                         pvs::VisibilityRows& rows);

/// A baked PVS (`pvs bake`'s .pvs or .pvs.json) read for the editor and checked against the open
/// project: baked from its scene file (the file's SHA-256, as `pvs bake` records it), over the
/// objects of the level as it is now (names and boxes: an object moved since the bake shows); its
/// cells are the file's. Throws sightline::Error saying what differs and how to get a PVS that
/// fits (bake again: P, or `sightline-cli pvs bake`).
pvs::PvsData readBakedPvs(const std::filesystem::path& file, const Project& project, const Scene& scene);

/// Per instance of the scene: 1 where the instance belongs to an object `row` does not see.
std::vector<std::uint8_t> culledInstances(const std::vector<pvs::PvsObject>& objects, const std::uint8_t* row,
                                          std::size_t instanceCount);

} // namespace sightline::ui
