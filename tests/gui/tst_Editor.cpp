// The editor as a user drives it, under Xvfb (Qt Test): open the demo project, place a patch with
// a click, drag an occluder into the shaft with the gizmo, undo, save and reload, screenshot.

#include <QSignalSpy>
#include <QStandardPaths>
#include <QTest>

#include <glm/gtc/matrix_transform.hpp>

#include "MainWindow.h"
#include "UiTestScene.h"
#include "ViewSettings.h"
#include "Viewport.h"
#include "project/Project.h"
#include "visibility/RayCastSampler.h"

using namespace sightline;
using namespace sightline::ui;

namespace {

/// The reference's blocked count for a project file, as the CLI computes it.
std::uint64_t referenceBlocked(const std::filesystem::path& file)
{
    const Project project = loadProject(file);
    return RayCastScene(buildScene(project)).sample(project.source, project.receiver).blockedCount();
}

QPoint pixelOf(const ViewportController& controller, const glm::dvec3& point)
{
    const glm::dvec3 p = toPixels(controller.camera(), point, controller.width(), controller.height());
    return {int(std::lround(p.x)), int(std::lround(p.y))};
}

bool yellowish(QRgb c) { return qRed(c) > qBlue(c) + 40 && qGreen(c) > qBlue(c) + 30; }

} // namespace

class EditorTest : public QObject {
    Q_OBJECT

private slots:
    void initTestCase()
    {
        QStandardPaths::setTestModeEnabled(true);
        folder_ = test::freshFolder("editor-gui");
        project_ = test::copyDemoProject(folder_);
        window_ = std::make_unique<MainWindow>(EditorOptions{.offerRecovery = false});
        window_->viewportContainer()->setFixedSize(800, 600);
        window_->show();
        QVERIFY(QTest::qWaitForWindowExposed(window_.get()));
        QVERIFY(window_->openFile(QString::fromStdString(project_.string())));
        waitForUpdate();
    }

    void opensTheDemoProjectAndMatchesTheReference()
    {
        const VisibilityResult& result = window_->viewport().visibility();
        QVERIFY(result.valid);
        QCOMPARE(result.rays, std::uint64_t(1) << 20);
        const std::uint64_t reference = referenceBlocked(project_);
        QVERIFY2(std::max(result.blocked, reference) - std::min(result.blocked, reference) <= result.rays / 10000,
                 qPrintable(QString("editor %1, reference %2").arg(result.blocked).arg(reference)));
    }

    void placesTheReceiverWithAClick()
    {
        EditorDocument& document = window_->document();
        ViewportController& controller = window_->controller();
        const Patch before = document.project().receiver;
        controller.setTool(Tool::PlaceReceiver);
        // The receiver's own centre is on a wall-facing patch in front of the far wall; click a
        // point of the floor halfway along the shaft.
        const glm::dvec3 floorPoint = 0.5 * (before.centre() + document.project().source.centre()) * glm::dvec3(1, 0, 1);
        const QPoint click = pixelOf(controller, floorPoint + glm::dvec3(0, 0.001, 0));
        const auto hit = pickSurface(worldTriangles(document.scene()),
                                     pixelRay(controller.camera(), click.x(), click.y(), controller.width(), controller.height()));
        QVERIFY(hit);
        QTest::mouseClick(&window_->viewport(), Qt::LeftButton, {}, click);
        const Patch placed = document.project().receiver;
        const Patch expected = patchOnSurface(*hit, glm::length(before.u), glm::length(before.v), before.na, before.nb);
        QVERIFY(glm::length(placed.centre() - expected.centre()) < 1e-9);
        QVERIFY(glm::length(placed.normal() - hit->normal) < 1e-9);
        QCOMPARE(controller.tool(), Tool::Select);
        document.undoStack()->undo();
        QVERIFY(document.project().receiver.corner == before.corner);
        waitForUpdate();
    }

    void draggingAnOccluderIntoTheShaftMatchesTheReferenceAndUndoRestores()
    {
        EditorDocument& document = window_->document();
        ViewportController& controller = window_->controller();
        const Project& project = document.project();
        const std::uint64_t before = window_->viewport().visibility().blocked;

        // A crate beside the shaft (2 m off its axis along z), then dragged along z into it.
        const glm::dvec3 inShaft = project.source.centre() + 0.3 * (project.receiver.centre() - project.source.centre());
        OccluderSpec crate;
        crate.name = "crate";
        crate.mesh = "box";
        crate.transform = glm::scale(glm::translate(glm::mat4(1.0f), glm::vec3(inShaft + glm::dvec3(0, 0, 2.0))), glm::vec3(0.6f));
        document.addOccluder(crate);
        controller.setGizmoMode(GizmoMode::Move);
        waitForUpdate();
        const std::uint64_t beside = window_->viewport().visibility().blocked;

        const GizmoFrame frame = *controller.gizmo();
        const glm::dvec3 grabPoint = frame.pivot + 0.7 * frame.length * glm::dvec3(0, 0, 1);
        const QPoint grab = pixelOf(controller, grabPoint);
        QCOMPARE(pickGizmoAxis(frame, controller.camera(), grab.x(), grab.y(), controller.width(), controller.height()), 2);
        QTest::mousePress(&window_->viewport(), Qt::LeftButton, {}, grab);
        for (int step = 1; step <= 4; ++step)   // the drag shows live, one frame per step
            QTest::mouseMove(&window_->viewport(), pixelOf(controller, grabPoint - glm::dvec3(0, 0, 0.5 * step)));
        QTest::mouseRelease(&window_->viewport(), Qt::LeftButton, {}, pixelOf(controller, grabPoint - glm::dvec3(0, 0, 2.0)));
        QVERIFY(std::abs(pivotOf(document.state({ObjectKind::Occluder, 0})).z - inShaft.z) < 0.05);
        waitForUpdate();

        const std::uint64_t dragged = window_->viewport().visibility().blocked;
        QVERIFY2(dragged > beside, "the crate in the shaft blocks more rays");
        QVERIFY(window_->saveTo(QString::fromStdString((folder_ / "dragged.json").string())));
        const std::uint64_t reference = referenceBlocked(folder_ / "dragged.json");
        QVERIFY2(std::max(dragged, reference) - std::min(dragged, reference) <= (std::uint64_t(1) << 20) / 10000,
                 qPrintable(QString("editor %1, reference %2").arg(dragged).arg(reference)));

        document.undoStack()->undo();   // the drag: one command
        waitForUpdate();
        QCOMPARE(window_->viewport().visibility().blocked, beside);
        document.undoStack()->undo();   // the crate
        waitForUpdate();
        QCOMPARE(window_->viewport().visibility().blocked, before);
        document.undoStack()->redo();
        document.undoStack()->redo();
        waitForUpdate();
        QCOMPARE(window_->viewport().visibility().blocked, dragged);
    }

    void saveAndReloadRoundTrips()
    {
        const auto file = folder_ / "round-trip.json";
        QVERIFY(window_->saveTo(QString::fromStdString(file.string())));
        QVERIFY(!window_->document().isModified());
        EditorDocument reopened;
        reopened.open(file);
        QVERIFY(toJson(reopened.project()) == toJson(window_->document().project()));
        QCOMPARE(reopened.project().occluders.size(), std::size_t(1));
    }

    void screenshotShowsRaysInTheShaft()
    {
        window_->document().select({});
        const Project& project = window_->document().project();
        ViewportController& controller = window_->controller();
        controller.setCamera(shaftView(project.source, project.receiver));
        window_->viewport().style().freeColour = {1.0f, 0.85f, 0.15f, 1.0f};
        window_->viewport().style().rayCap = 1 << 20;
        window_->viewport().requestUpdate();
        QTest::qWait(200);
        const auto file = folder_ / "screenshot.png";
        QVERIFY(window_->screenshotTo(QString::fromStdString(file.string())));
        QImage image(QString::fromStdString(file.string()));
        QVERIFY(!image.isNull());
        image = image.scaled(controller.width(), controller.height());   // device pixels -> logical
        // Just in front of the source every ray is still open; well above the shaft there are none.
        const glm::dvec3 nearSource = project.source.centre() + 0.05 * (project.receiver.centre() - project.source.centre());
        const QPoint inside = pixelOf(controller, nearSource);
        const QPoint above = pixelOf(controller, nearSource + glm::dvec3(0, 3.0, 0));
        QVERIFY(yellowish(image.pixel(inside)));
        QVERIFY(!yellowish(image.pixel(above)));
    }

    void cleanupTestCase()
    {
        window_->document().undoStack()->setClean();
        window_.reset();
    }

private:
    void waitForUpdate()
    {
        QSignalSpy spy(&window_->viewport(), &Viewport::visibilityUpdated);
        window_->viewport().requestUpdate();
        spy.wait(3000);
        QTest::qWait(50);
    }

    std::filesystem::path folder_;
    std::filesystem::path project_;
    std::unique_ptr<MainWindow> window_;
};

QTEST_MAIN(EditorTest)
#include "tst_Editor.moc"
