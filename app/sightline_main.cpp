// sightline: the editor. Also renders a project's view headlessly (--screenshot) and measures the
// live update rate (--benchmark-interaction).

#include <cstdio>
#include <string>

#include <CLI/CLI.hpp>
#include <QApplication>
#include <QCoreApplication>
#include <QSurfaceFormat>

#include "EditorDocument.h"
#include "InteractionBenchmark.h"
#include "MainWindow.h"
#include "OffscreenRender.h"
#include "ViewSettings.h"
#include "Viewport.h"
#include "visibility/Error.h"

namespace {

using namespace sightline;
using namespace sightline::ui;

struct Arguments {
    std::string file;
    std::string screenshot;
    bool benchmark = false;
    int frames = 300;
    std::string size = "1280x720";
    int rays = 4096;
    bool showBlocked = false;
    std::string glBackend = "osmesa";
};

bool parseSize(const std::string& text, int& width, int& height)
{
    return std::sscanf(text.c_str(), "%dx%d", &width, &height) == 2 && width > 0 && height > 0 && width <= 16384 &&
           height <= 16384;
}

int screenshot(const Arguments& args, int width, int height)
{
    EditorDocument document;
    document.open(args.file);
    ViewStyle style;
    style.rayCap = args.rays;
    style.showBlocked = args.showBlocked;
    const Project& project = document.project();
    const Camera camera = projectView(document.editorSettings(), project.source, project.receiver);
    const OffscreenResult result = renderOffscreen(document, camera, style, width, height, gl::parseBackend(args.glBackend));
    if (!result.image.save(QString::fromStdString(args.screenshot), "PNG"))
        throw sightline::Error(args.screenshot + ": could not write the image");
    std::printf("wrote %s (%dx%d): %s; %llu rays drawn\n", args.screenshot.c_str(), width, height,
                visibilitySummary(result.visibility).toUtf8().constData(), static_cast<unsigned long long>(result.raysDrawn));
    return 0;
}

int benchmark(const Arguments& args, int width, int height)
{
    MainWindow window(EditorOptions{.offerRecovery = false});
    if (!window.openFile(QString::fromStdString(args.file)))
        return 1;
    window.viewport().style().rayCap = args.rays;
    window.viewport().style().showBlocked = args.showBlocked;
    const InteractionFigures f = runInteractionBenchmark(window, args.frames, width, height);
    std::printf("interaction benchmark: %s, %d frames at %dx%d, receiver dragged along a scripted path\n",
                args.file.c_str(), f.frames, f.width, f.height);
    std::printf("  sampler        %s\n", f.backend.c_str());
    std::printf("  rays           %llu per update (%llu drawn), %.1f%% visible on average\n",
                static_cast<unsigned long long>(f.rays), static_cast<unsigned long long>(f.raysDrawn), 100.0 * f.meanVisibleFraction);
    std::printf("  update rate    %.1f Hz median (frame %.1f ms median, %.1f ms 90th percentile)\n", f.medianHz,
                f.medianFrameMs, f.p90FrameMs);
    std::printf("  sampling       %.1f ms median per update\n", f.medianSampleMs);
    return 0;
}

} // namespace

int main(int argc, char** argv)
{
    CLI::App app{"Sightline: see which rays between two patches of a level are blocked, live.\n"
                 "Without options, opens the editor (on FILE if given)."};
    Arguments args;
    app.add_option("file", args.file, "Project (.json) or level (.glb .gltf .obj .ply .off .stl) to open");
    app.add_option("--screenshot", args.screenshot, "Render FILE's view (its saved camera, else across the shaft) to this PNG "
                                                    "without a display, then exit");
    app.add_flag("--benchmark-interaction", args.benchmark,
                 "Drag FILE's receiver along a scripted path in the editor and print the median update rate");
    app.add_option("--frames", args.frames, "Benchmark frames")->check(CLI::Range(1, 100000));
    app.add_option("--size", args.size, "Screenshot or benchmark viewport size, WxH");
    app.add_option("--rays", args.rays, "Most rays drawn (screenshot and benchmark)")->check(CLI::Range(1, 1 << 30));
    app.add_flag("--show-blocked", args.showBlocked, "Draw blocked rays too, in red (screenshot and benchmark)");
    app.add_option("--gl-backend", args.glBackend, "Screenshot: headless GL, osmesa or egl")->check(CLI::IsMember({"osmesa", "egl"}));
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e);
    }
    int width = 0, height = 0;
    if (!parseSize(args.size, width, height)) {
        std::fprintf(stderr, "sightline: --size must be WxH with sides from 1 to 16384, got '%s'\n", args.size.c_str());
        return 2;
    }
    if ((!args.screenshot.empty() || args.benchmark) && args.file.empty()) {
        std::fprintf(stderr, "sightline: --screenshot and --benchmark-interaction need a project file\n");
        return 2;
    }
    QCoreApplication::setOrganizationName("Sightline");
    QCoreApplication::setApplicationName("Sightline");
    try {
        if (!args.screenshot.empty()) {
            QCoreApplication core(argc, argv);   // no display needed: OSMesa renders
            return screenshot(args, width, height);
        }
        QSurfaceFormat format;
        format.setVersion(4, 5);
        format.setProfile(QSurfaceFormat::CoreProfile);
        format.setDepthBufferSize(24);
        format.setStencilBufferSize(8);
        format.setSwapInterval(0);   // measure and draw as fast as the frame is ready
        QSurfaceFormat::setDefaultFormat(format);
        QApplication application(argc, argv);
        if (args.benchmark)
            return benchmark(args, width, height);
        MainWindow window;
        window.show();
        if (!args.file.empty())
            window.openFile(QString::fromStdString(args.file));
        return application.exec();
    } catch (const std::exception& e) {
        std::fprintf(stderr, "sightline: %s\n", e.what());
        return 1;
    }
}
