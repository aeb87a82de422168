// The PVS debugger's model (editor/PvsView.h): a bake's events in, the shown cell, frozen cells,
// gaps, and the project's cut-off over the rows.

#include <gtest/gtest.h>

#include "editor/PvsView.h"

namespace {

using namespace sightline;
using namespace sightline::ui;

Bounds box(glm::vec3 min, glm::vec3 max)
{
    Bounds b;
    b.extend(min);
    b.extend(max);
    return b;
}

/// Two cells side by side along x, three objects: one in each cell and one far off.
PvsDebugEvent started()
{
    PvsDebugEvent event;
    event.generation = 1;
    event.started = true;
    event.cells = {box({0, 0, 0}, {1, 1, 1}), box({1, 0, 0}, {2, 1, 1})};
    for (int k = 0; k < 3; ++k) {
        pvs::PvsObject object;
        object.name = "object" + std::to_string(k);
        object.instance = std::uint32_t(k);
        const float x = k == 2 ? 50.0f : float(k);
        object.bounds = box({x + 0.25f, 0.25f, 0.25f}, {x + 0.75f, 0.75f, 0.75f});
        event.objects.push_back(object);
    }
    return event;
}

PvsDebugEvent row(std::size_t cell, std::uint8_t bits, pvs::PvsPass pass)
{
    PvsDebugEvent event;
    event.generation = 1;
    event.cell = cell;
    event.pass = pass;
    event.row = {bits};
    return event;
}

TEST(PvsView, ABakesRowsArriveCoarseThenRefinedAndTheEyesCellIsShown)
{
    PvsView view;
    view.reset({}, {}, {}, false);
    EXPECT_TRUE(view.cells().empty());
    view.take(started());
    ASSERT_EQ(view.cells().size(), 2u);
    ASSERT_EQ(view.rows().cellCount(), 2u);
    EXPECT_TRUE(view.showFrom({0.5, 0.5, 0.5}));   // the first cell: shown anew
    EXPECT_EQ(view.shownCell(), std::optional<std::size_t>(0));
    EXPECT_FALSE(view.showFrom({0.4, 0.5, 0.5}));   // the same cell, nothing new

    view.take(row(0, 0b111, pvs::PvsPass::Coarse));
    view.take(row(1, 0b011, pvs::PvsPass::Coarse));
    EXPECT_EQ(view.coarseDone(), 2u);
    EXPECT_TRUE(view.cellCoarse(0));
    EXPECT_TRUE(view.showFrom({0.4, 0.5, 0.5}));   // the shown cell's row changed
    view.take(row(0, 0b011, pvs::PvsPass::Refine));
    EXPECT_FALSE(view.cellCoarse(0));
    EXPECT_TRUE(view.cellCoarse(1));
    EXPECT_EQ(view.refinedDone(), 1u);
    EXPECT_FALSE(view.rows().visible(0, 2));
    EXPECT_FALSE(view.finished());

    PvsDebugEvent done;
    done.finished = true;
    view.take(done);
    EXPECT_TRUE(view.finished());
    EXPECT_TRUE(view.usable());
    // A row of the wrong size is ignored.
    view.take(row(1, 0, pvs::PvsPass::Refine));
    PvsDebugEvent bad = row(1, 0, pvs::PvsPass::Refine);
    bad.row = {0, 0};
    view.take(bad);
    EXPECT_EQ(view.refinedDone(), 2u);
}

TEST(PvsView, AFrozenCellStaysWhileTheEyeMovesAndFollowsASelectedGap)
{
    PvsView view;
    view.take(started());
    view.showFrom({0.5, 0.5, 0.5});
    view.setFrozen(true);
    view.showFrom({1.5, 0.5, 0.5});
    EXPECT_EQ(view.shownCell(), std::optional<std::size_t>(0));
    EXPECT_FALSE(view.selectGap(0));   // no gaps yet
    PvsDebugEvent checked;
    checked.checked = true;
    pvs::Gap gap;
    gap.cell = 1;
    gap.object = 2;
    checked.gaps = {gap};
    view.take(checked);
    ASSERT_TRUE(view.gapsReady());
    EXPECT_TRUE(view.selectGap(0));
    EXPECT_EQ(view.gapSelected(), 0);
    EXPECT_TRUE(view.showFrom({0.5, 0.5, 0.5}));
    EXPECT_EQ(view.shownCell(), std::optional<std::size_t>(1));   // the gap's cell, though the eye is in cell 0
    view.setFrozen(false);
    view.showFrom({0.5, 0.5, 0.5});
    EXPECT_EQ(view.shownCell(), std::optional<std::size_t>(0));
    view.showFrom({9.0, 9.0, 9.0});
    EXPECT_EQ(view.shownCell(), std::nullopt);
}

TEST(PvsView, TheProjectsCutOffIsShownOverTheRowsAndABadOverrideIsReportedNotApplied)
{
    PvsView view;
    view.take(started());
    view.take(row(0, 0b111, pvs::PvsPass::Refine));
    Project project;
    project.extra["pvs"] = {{"max_distance", 10.0}};
    const pvs::VisibilityRows& shown = view.applyProjectSettings(project, "p.json");
    EXPECT_DOUBLE_EQ(view.cutoff(), 10.0);
    EXPECT_TRUE(shown.visible(0, 0));
    EXPECT_TRUE(shown.visible(0, 1));
    EXPECT_FALSE(shown.visible(0, 2));   // 49 m off: beyond the cut-off
    EXPECT_TRUE(view.rows().visible(0, 2));   // the bake's own row is kept
    EXPECT_TRUE(view.overrideError().empty());

    // An override forces what the cut-off hid; one naming no object is reported, nothing applied.
    project.extra["pvs"]["overrides"] = nlohmann::json::array({{{"object", "object2"}, {"visible", "always"}}});
    view.applyProjectSettings(project, "p.json");
    EXPECT_TRUE(view.overrideError().empty()) << view.overrideError();
    EXPECT_TRUE(view.shown().visible(0, 2));
    project.extra["pvs"]["overrides"] = nlohmann::json::array({{{"object", "lamp"}, {"visible", "never"}}});
    view.applyProjectSettings(project, "p.json");
    EXPECT_NE(view.overrideError().find("no object is named 'lamp'"), std::string::npos) << view.overrideError();
}

TEST(PvsView, AFailedBakeIsFinishedWithItsErrorAndClearForgetsEverything)
{
    PvsView view;
    view.take(started());
    PvsDebugEvent failed;
    failed.error = "p.json: no view cells";
    view.take(failed);
    EXPECT_TRUE(view.finished());
    EXPECT_EQ(view.error(), "p.json: no view cells");
    EXPECT_FALSE(view.usable());
    view.clear();
    EXPECT_TRUE(view.cells().empty());
    EXPECT_TRUE(view.error().empty());
    EXPECT_FALSE(view.finished());
    EXPECT_EQ(view.shown().cellCount(), 0u);
}

} // namespace
