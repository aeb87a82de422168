#include "editor/PvsDebugger.h"

#include <algorithm>
#include <chrono>
#include <exception>
#include <new>

#include "project/PvsSetup.h"
#include "base/Error.h"
#include "base/InputFile.h"
#include "visibility/pvs/FirstHitCaster.h"
#include "visibility/pvs/PvsFile.h"
#include "visibility/pvs/PvsObjects.h"
#include "visibility/pvs/Sha256.h"
#include "visibility/pvs/ViewCells.h"

namespace sightline::ui {

std::string editorPvsSeed(const Scene& scene)
{
    const WorldTriangles world = worldTriangles(scene);
    return pvs::sha256Hex(std::string_view(reinterpret_cast<const char*>(world.vertices.data()),
                                           world.vertices.size() * sizeof(glm::vec3)));
}

std::string pvsBakeKey(const Project& project)
{
    try {
        PvsSetup setup = parsePvsSetup(project, "project");
        setup.settings.maxDistance = 0.0;
        std::string key = setup.settings.canonical();
        key.append(setup.groupByName ? " by-name" : "").append(setup.gridCells ? " grid" : " listed");
        for (const float v : {setup.grid.cellSize, setup.grid.height, setup.grid.lift})
            key.append(" ").append(std::to_string(v));
        for (const Bounds& b : setup.cells)
            for (int k = 0; k < 3; ++k)
                key.append(" ").append(std::to_string(b.min[k])).append(" ").append(std::to_string(b.max[k]));
        return key;
    } catch (const std::exception& e) {
        std::string key = "error: ";
        return key.append(e.what());
    }
}

void applyDistanceCutoff(const std::vector<Bounds>& cells, const std::vector<pvs::PvsObject>& objects, double maxDistance,
                         pvs::VisibilityRows& rows)
{
    if (!(maxDistance > 0.0))
        return;
    for (std::size_t c = 0; c < cells.size() && c < rows.cellCount(); ++c)
        for (std::size_t o = 0; o < objects.size() && o < rows.objectCount(); ++o) {
            if (!rows.visible(c, o) || objects[o].bounds.empty())
                continue;
            double d2 = 0.0;
            for (int k = 0; k < 3; ++k) {
                const double gap = std::max({0.0, double(cells[c].min[k]) - double(objects[o].bounds.max[k]),
                                             double(objects[o].bounds.min[k]) - double(cells[c].max[k])});
                d2 += gap * gap;
            }
            if (d2 > maxDistance * maxDistance)
                rows.set(c, o, false);
        }
}

std::vector<std::uint8_t> culledInstances(const std::vector<pvs::PvsObject>& objects, const std::uint8_t* row,
                                          std::size_t instanceCount)
{
    std::vector<std::uint8_t> culled(instanceCount, 0);
    for (std::size_t o = 0; o < objects.size(); ++o) {
        if ((row[o / 8] >> (o % 8)) & 1u)
            continue;
        const pvs::PvsObject& object = objects[o];
        if (object.instances.empty()) {
            if (object.instance < instanceCount)
                culled[object.instance] = 1;
        } else {
            for (std::uint32_t i : object.instances)
                if (i < instanceCount)
                    culled[i] = 1;
        }
    }
    return culled;
}

PvsDebugger::PvsDebugger(Deliver deliver) : deliver_(std::move(deliver)) {}

PvsDebugger::~PvsDebugger() { stop(); }

void PvsDebugger::stop()
{
    if (cancel_)
        cancel_->store(true);
    if (thread_.joinable())
        thread_.join();
    cancel_.reset();
}

void PvsDebugger::start(std::uint64_t generation, std::shared_ptr<const Scene> scene, Project project, std::string what)
{
    stop();
    cancel_ = std::make_shared<std::atomic<bool>>(false);
    thread_ = std::thread([this, generation, scene = std::move(scene), project = std::move(project), what = std::move(what),
                           cancel = cancel_] {
        const auto start = std::chrono::steady_clock::now();
        const auto ms = [&] { return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count(); };
        const auto fail = [&](std::string error) {
            PvsDebugEvent event;
            event.generation = generation;
            event.finished = true;
            event.error = std::move(error);
            deliver_(std::move(event));
        };
        try {
            PvsSetup setup = parsePvsSetup(project, what);
            if (setup.gridCells) {
                const pvs::FirstHitCaster caster(*scene);
                setup.cells = pvs::gridCells(*scene, caster, setup.grid);
            }
            pvs::validateCells(setup.cells, what + ": pvs cells");
            PvsDebugEvent begun;
            begun.generation = generation;
            begun.started = true;
            begun.cells = setup.cells;
            begun.objects = pvs::sceneObjects(*scene, setup.groupByName);
            const pvs::PvsBaker baker(*scene, begun.cells, begun.objects, editorPvsSeed(*scene), setup.settings);
            begun.ms = ms();
            deliver_(begun);
            pvs::PvsProgress progress;
            progress.cancel = cancel.get();
            progress.onCell = [&](pvs::PvsPass pass, std::size_t cell, const std::vector<std::uint8_t>& row) {
                PvsDebugEvent event;
                event.generation = generation;
                event.cell = cell;
                event.pass = pass;
                event.row = row;
                event.ms = ms();
                deliver_(std::move(event));
            };
            pvs::PvsData data;
            data.sceneSha256 = editorPvsSeed(*scene);
            data.cells = begun.cells;
            data.objects = begun.objects;
            data.rows = baker.bake({}, progress);
            PvsDebugEvent done;
            done.generation = generation;
            done.finished = true;
            done.ms = ms();
            deliver_(std::move(done));
            // The gap list: the dense reference in its random cells (no panoramas: only the
            // pairs it sees and the bake culled, with the witness ray of each).
            pvs::ReferenceSettings reference;
            reference.views = 0;
            reference.cancel = cancel.get();
            const pvs::AccuracyReport report = pvs::measureAccuracy(*scene, data, reference);
            PvsDebugEvent checked;
            checked.generation = generation;
            checked.checked = true;
            checked.gaps = report.gaps;
            checked.referenceCells = report.cells.size();
            checked.referenceVisible = report.referenceVisible;
            checked.missed = report.missed;
            checked.ms = ms();
            deliver_(std::move(checked));
        } catch (const pvs::PvsCancelled&) {
        } catch (const std::bad_alloc&) {
            fail("out of memory baking the PVS");
        } catch (const std::exception& e) {
            fail(e.what());
        }
    });
}

pvs::PvsData readBakedPvs(const std::filesystem::path& file, const Project& project, const Scene& scene)
{
    const std::string name = file.filename().string();
    const std::string bytes = readInputFile(file, name);
    const std::size_t first = bytes.find_first_not_of(" \t\r\n");
    const bool json = first != std::string::npos && bytes[first] == '{';   // a .pvs starts with its magic
    pvs::PvsData data = json ? pvs::decodePvsJson(bytes, name) : pvs::decodePvs(bytes, name);
    const std::string again = " (bake it again: P, or sightline-cli pvs bake)";
    if (project.scene.empty())
        throw Error(name + " is a PVS of a scene file; this project has none");
    const std::filesystem::path sceneFile = project.resolve(project.scene, "scene");
    if (pvs::sha256Hex(readInputFile(sceneFile, sceneFile.filename().string())) != data.sceneSha256)
        throw Error(name + " was baked from another scene than " + sceneFile.filename().string() +
                    " (its SHA-256 differs: the level was edited or is another one)" + again);
    const PvsSetup setup = parsePvsSetup(project, project.name);
    const std::vector<pvs::PvsObject> objects = pvs::sceneObjects(scene, setup.groupByName);
    if (objects.size() != data.objects.size())
        throw Error(name + " holds " + std::to_string(data.objects.size()) + " objects, the level as it is now " +
                    std::to_string(objects.size()) + " (occluders added or removed since the bake, or other grouping)" + again);
    for (std::size_t o = 0; o < objects.size(); ++o) {
        const Bounds &now = objects[o].bounds, &baked = data.objects[o].bounds;
        bool moved = objects[o].name != data.objects[o].name || now.empty() != baked.empty();
        for (int k = 0; k < 3 && !moved && !now.empty(); ++k)
            moved = std::abs(now.min[k] - baked.min[k]) > 1e-3f || std::abs(now.max[k] - baked.max[k]) > 1e-3f;
        if (moved)
            throw Error(name + ": object " + std::to_string(o) + " ('" + objects[o].name +
                        "') is not where the bake saw it (moved or renamed since)" + again);
    }
    return data;
}

} // namespace sightline::ui
