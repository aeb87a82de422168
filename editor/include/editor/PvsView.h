#pragma once
// What the PVS debugger shows: the bake's rows as they arrive (PvsDebugger.h's events) or rows read
// from a file, the project's distance cut-off and overrides over them, the view cell shown (the
// eye's, or a frozen one), and the reference's gaps with the one selected. A plain model: the
// viewport owns one, feeds it events and the eye, and draws and words what it holds.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "editor/PvsDebugger.h"
#include "project/Project.h"
#include "visibility/pvs/PvsData.h"

namespace sightline::ui {

class PvsView {
public:
    /// A bake about to start (no cells yet, not finished) or rows read from `file` (finished:
    /// every cell done, refined).
    void reset(std::vector<Bounds> cells, std::vector<pvs::PvsObject> objects, pvs::VisibilityRows rows, bool finished,
               std::string file = {});
    /// Forgets the rows and the gaps: the scene they were for is gone.
    void clear();
    /// Takes one event of the running bake (the caller drops other bakes' by generation).
    void take(PvsDebugEvent event);

    /// The shown rows anew: the project's pvs.max_distance and pvs.overrides over the bake's rows,
    /// as `pvs bake` applies them (a bad override is reported as overrideError(), none applied).
    /// `what` names the project in messages.
    const pvs::VisibilityRows& applyProjectSettings(const Project& project, const std::string& what);
    /// Shows the frozen cell, or the cell `eye` is in. True when the cell shown changed, or the
    /// rows did since the last call (what is drawn must be updated).
    bool showFrom(glm::dvec3 eye);
    /// Shown rows need recomputing (the project's settings changed): the next showFrom says so.
    void markRowsChanged() { rowsChanged_ = true; }
    /// Keeps the current cell while the eye moves.
    void setFrozen(bool frozen);
    /// Selects gap k, a frozen view following its cell; false when there is no such gap.
    bool selectGap(std::size_t k);

    const std::vector<Bounds>& cells() const { return cells_; }
    const std::vector<pvs::PvsObject>& objects() const { return objects_; }
    const pvs::VisibilityRows& rows() const { return rows_; }
    /// What is shown: the rows with the project's settings applied (applyProjectSettings).
    const pvs::VisibilityRows& shown() const { return shown_; }
    /// Cells with a coarse answer, and with a refined one; whether the bake is over (or failed).
    std::size_t coarseDone() const { return coarse_; }
    std::size_t refinedDone() const { return refined_; }
    bool finished() const { return finished_; }
    /// Whether cell c's answer is still the coarse one (refinement has not reached it).
    bool cellCoarse(std::size_t cell) const { return cell >= cellRefined_.size() || !cellRefined_[cell]; }
    /// Per cell: 1 once its refined row is in.
    const std::vector<std::uint8_t>& cellsRefined() const { return cellRefined_; }
    std::optional<std::size_t> shownCell() const { return shownCell_; }
    bool frozen() const { return frozen_; }
    /// The reference's gap list, once the finished bake was checked.
    bool gapsReady() const { return gapsReady_; }
    const std::vector<pvs::Gap>& gaps() const { return gaps_; }
    int gapSelected() const { return gapSelected_; }   ///< -1: none
    const std::string& error() const { return error_; }   ///< the bake's, when it failed
    const std::string& overrideError() const { return overrideError_; }
    const std::string& fromFile() const { return fromFile_; }   ///< empty for the editor's own bake
    double cutoff() const { return cutoff_; }   ///< the pvs.max_distance last applied (0: none)
    /// A finished bake without error, with cells: it can serve the light sets' V and L.
    bool usable() const { return finished_ && error_.empty() && !cells_.empty(); }

private:
    std::vector<Bounds> cells_;
    std::vector<pvs::PvsObject> objects_;
    pvs::VisibilityRows rows_, shown_;
    std::size_t coarse_ = 0, refined_ = 0;
    std::vector<std::uint8_t> cellRefined_;
    bool finished_ = false, rowsChanged_ = false, frozen_ = false;
    std::optional<std::size_t> shownCell_, frozenCell_;
    std::vector<pvs::Gap> gaps_;
    bool gapsReady_ = false;
    int gapSelected_ = -1;
    std::string error_, overrideError_, fromFile_;
    double cutoff_ = 0.0;
};

} // namespace sightline::ui
