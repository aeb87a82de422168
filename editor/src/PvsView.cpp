#include "editor/PvsView.h"

#include <algorithm>

#include "project/PvsSetup.h"

namespace sightline::ui {

void PvsView::reset(std::vector<Bounds> cells, std::vector<pvs::PvsObject> objects, pvs::VisibilityRows rows, bool finished,
                    std::string file)
{
    const std::size_t done = finished ? cells.size() : 0;
    cells_ = std::move(cells);
    objects_ = std::move(objects);
    rows_ = std::move(rows);
    coarse_ = refined_ = done;
    cellRefined_.assign(done, 1);
    gaps_.clear();
    gapsReady_ = false;
    gapSelected_ = -1;
    finished_ = finished;
    frozenCell_.reset();
    rowsChanged_ = true;
    error_.clear();
    fromFile_ = std::move(file);
}

void PvsView::clear()
{
    reset({}, {}, {}, false);
    shown_ = {};
}

void PvsView::take(PvsDebugEvent event)
{
    if (!event.error.empty()) {
        error_ = std::move(event.error);
        finished_ = true;
        return;
    }
    error_.clear();
    if (event.started) {
        cells_ = std::move(event.cells);
        objects_ = std::move(event.objects);
        rows_ = pvs::VisibilityRows(cells_.size(), objects_.size());
    }
    if (event.checked) {
        gaps_ = std::move(event.gaps);
        gapsReady_ = true;
    }
    if (event.cell && *event.cell < rows_.cellCount() && event.row.size() == rows_.rowBytes()) {
        std::copy(event.row.begin(), event.row.end(), rows_.row(*event.cell));
        ++(event.pass == pvs::PvsPass::Coarse ? coarse_ : refined_);
        if (event.pass == pvs::PvsPass::Refine) {
            cellRefined_.resize(rows_.cellCount(), 0);
            cellRefined_[*event.cell] = 1;
        }
        rowsChanged_ = rowsChanged_ || event.cell == shownCell_;
    }
    if (event.finished)
        finished_ = true;
}

const pvs::VisibilityRows& PvsView::applyProjectSettings(const Project& project, const std::string& what)
{
    shown_ = rows_;
    overrideError_.clear();
    if (rows_.cellCount() > 0) {
        try {
            const PvsSetup setup = parsePvsSetup(project, what);
            cutoff_ = setup.settings.maxDistance;
            applyDistanceCutoff(cells_, objects_, cutoff_, shown_);
            applyPvsOverrides(resolvePvsOverrides(setup.overridesJson, objects_, cells_.size(), what), shown_);
        } catch (const std::exception& e) {
            overrideError_ = e.what();
        }
    }
    return shown_;
}

bool PvsView::showFrom(glm::dvec3 eye)
{
    if (frozen_ && !frozenCell_)
        frozenCell_ = pvs::cellAt(cells_, eye);
    const std::optional<std::size_t> cell = frozen_ ? frozenCell_ : pvs::cellAt(cells_, eye);
    const bool changed = cell != shownCell_ || rowsChanged_;
    shownCell_ = cell;
    rowsChanged_ = false;
    return changed;
}

void PvsView::setFrozen(bool frozen)
{
    frozen_ = frozen;
    frozenCell_ = frozen ? shownCell_ : std::nullopt;
}

bool PvsView::selectGap(std::size_t k)
{
    if (k >= gaps_.size())
        return false;
    gapSelected_ = int(k);
    if (frozen_)
        frozenCell_ = gaps_[k].cell;   // a frozen view shows the gap's cell
    return true;
}

} // namespace sightline::ui
