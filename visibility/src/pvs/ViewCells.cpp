#include "visibility/pvs/ViewCells.h"

#include <cmath>
#include <sstream>

#include "base/Error.h"
#include "visibility/ExactSegment.h"
#include "visibility/pvs/FirstHitCaster.h"

namespace sightline::pvs {

namespace {
std::string vec(const glm::vec3& p)
{
    std::ostringstream s;
    s << "[" << p.x << ", " << p.y << ", " << p.z << "]";
    return s.str();
}
} // namespace

std::vector<Bounds> gridCells(const Scene& scene, const FirstHitCaster& caster, const GridCellSettings& settings)
{
    for (const auto& [name, value] : {std::pair{"cell_size", settings.cellSize}, std::pair{"cell_height", settings.height}})
        if (!std::isfinite(value) || value <= 0.0f)
            throw Error(std::string("pvs.") + name + " must be a positive number of metres, got " + std::to_string(value));
    if (!std::isfinite(settings.lift) || settings.lift < 0.0f)
        throw Error("pvs.cell_lift must be a non-negative number of metres, got " + std::to_string(settings.lift));
    const Bounds world = scene.bounds();
    if (world.empty())
        throw Error("pvs: the scene is empty, there are no floors to put view cells on");
    const double nx = std::ceil((double(world.max.x) - world.min.x) / settings.cellSize);
    const double nz = std::ceil((double(world.max.z) - world.min.z) / settings.cellSize);
    if (nx * nz > 1e6)
        throw Error("pvs.cell_size " + std::to_string(settings.cellSize) + " m gives " + std::to_string(std::llround(nx * nz)) +
                    " grid columns (at most 1,000,000): use larger cells");
    const float top = world.max.y;
    const float need = settings.lift + settings.height;
    std::vector<Bounds> cells;
    for (int ix = 0; ix < std::max(1, int(nx)); ++ix)
        for (int iz = 0; iz < std::max(1, int(nz)); ++iz) {
            const float x0 = world.min.x + ix * settings.cellSize, z0 = world.min.z + iz * settings.cellSize;
            const glm::vec3 centre{x0 + 0.5f * settings.cellSize, top + 1.0f, z0 + 0.5f * settings.cellSize};
            // Walk down the column: each hit is a surface; the space above an up-facing one, up to
            // the previous hit (or the scene's top), is its clearance.
            float ceiling = top;
            float y = centre.y;
            std::vector<Bounds> column;
            for (int guard = 0; guard < 4096; ++guard) {
                const float span = y - (world.min.y - 1.0f);
                const RayHit hit = caster.cast({centre.x, y, centre.z}, {0.0f, -1.0f, 0.0f}, span);
                if (hit.instance < 0)
                    break;
                const float surface = y - hit.t;
                const float len = glm::length(hit.normal);
                const bool facesUp = len > 0.0f && std::abs(hit.normal.y) >= 0.7f * len;
                if (facesUp && ceiling - surface >= need) {
                    Bounds cell;
                    cell.min = {x0, surface + settings.lift, z0};
                    cell.max = {x0 + settings.cellSize, surface + settings.lift + settings.height, z0 + settings.cellSize};
                    column.push_back(cell);
                }
                ceiling = surface;
                // Step past this surface (a relative step: coordinates may be large).
                y = std::nextafter(surface, -INFINITY) - 1e-4f * std::max(1.0f, std::abs(surface));
            }
            // Lowest floor first.
            cells.insert(cells.end(), column.rbegin(), column.rend());
        }
    return cells;
}

void validateCells(const std::vector<Bounds>& cells, const std::string& what)
{
    if (cells.empty())
        throw Error(what + ": no view cells (the grid found no floor with room for a cell, or the list is empty)");
    for (std::size_t c = 0; c < cells.size(); ++c) {
        const Bounds& b = cells[c];
        const std::string name = what + "[" + std::to_string(c) + "]";
        for (int k = 0; k < 3; ++k) {
            if (!std::isfinite(b.min[k]) || !std::isfinite(b.max[k]))
                throw Error(name + ": a coordinate is not finite (min " + vec(b.min) + ", max " + vec(b.max) + ")");
            if (std::abs(b.min[k]) > kMaxCoordinateMetres || std::abs(b.max[k]) > kMaxCoordinateMetres)
                throw Error(name + ": a coordinate lies beyond 1e6 m");
            if (b.min[k] > b.max[k])
                throw Error(name + ": inverted box (min " + vec(b.min) + " is above max " + vec(b.max) + " on axis " +
                            "xyz"[k] + ")");
            if (b.min[k] == b.max[k])
                throw Error(name + ": empty box (zero size on axis " + std::string(1, "xyz"[k]) + ")");
        }
    }
}

} // namespace sightline::pvs
