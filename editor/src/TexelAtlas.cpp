#include "editor/TexelAtlas.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#ifdef __linux__
#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>
#endif

namespace sightline::ui {

TexelSurfaces texelSurfaces(const WorldTriangles& triangles, const std::vector<std::uint32_t>& instances)
{
    std::vector<std::uint8_t> wanted;
    for (std::uint32_t i : instances) {
        if (i >= wanted.size())
            wanted.resize(std::size_t(i) + 1, 0);
        wanted[i] = 1;
    }
    TexelSurfaces out;
    for (std::size_t t = 0; t < triangles.size(); ++t) {
        const std::uint32_t instance = triangles.instanceOf[t];
        if (!instances.empty() && (instance >= wanted.size() || !wanted[instance]))
            continue;
        for (std::size_t c = 0; c < 3; ++c) {
            out.surfaces.indices.push_back(std::uint32_t(out.surfaces.vertices.size()));
            out.surfaces.vertices.push_back(triangles.vertices[3 * t + c]);
            out.surfaces.bounds.extend(triangles.vertices[3 * t + c]);
        }
        out.worldTriangle.push_back(std::uint32_t(t));
    }
    return out;
}

std::vector<glm::vec2> cornerUvs(const WorldTriangles& triangles, const TexelSurfaces& sampled, const AoTexelLayout& layout)
{
    std::vector<glm::vec2> uvs(triangles.vertices.size(), glm::vec2(-1.0f));
    for (const AoTexelTile& tile : layout.tiles) {
        if (tile.width == 0 || tile.triangle >= sampled.worldTriangle.size())
            continue;
        const std::size_t t = sampled.worldTriangle[tile.triangle];
        for (std::size_t c = 0; c < 3; ++c) {
            const glm::vec3 d = triangles.vertices[3 * t + c] - tile.origin;
            const double s = double(tile.x) + double(glm::dot(d, tile.axisU)) * layout.density;
            const double r = double(tile.y) + double(glm::dot(d, tile.axisV)) * layout.density;
            uvs[3 * t + c] = glm::vec2(float(s / layout.width), float(r / layout.height));
        }
    }
    return uvs;
}

std::vector<std::uint32_t> atlasSources(const AoTexelLayout& layout)
{
    std::vector<std::uint32_t> sources(std::size_t(layout.width) * std::size_t(layout.height), kBlankPixel);
    const auto at = [&](int x, int y) -> std::uint32_t& {
        return sources[std::size_t(y) * std::size_t(layout.width) + std::size_t(x)];
    };
    for (const AoTexelTile& tile : layout.tiles)
        for (int t = 0; t < tile.height; ++t)
            for (int s = 0; s < tile.width; ++s)
                at(tile.x + s, tile.y + t) = std::uint32_t(tile.firstPoint + std::size_t(t) * std::size_t(tile.width) + std::size_t(s));
    // The gutters after every tile's texels, in the same order, so a gutter another tile's
    // texels lie under takes what the image would show there.
    for (const AoTexelTile& tile : layout.tiles) {
        if (tile.width == 0)
            continue;
        for (int t = -1; t <= tile.height; ++t)
            for (int s = -1; s <= tile.width; ++s) {
                if (t >= 0 && t < tile.height && s >= 0 && s < tile.width)
                    continue;
                const int gx = tile.x + s, gy = tile.y + t;
                if (gx < 0 || gy < 0 || gx >= layout.width || gy >= layout.height)
                    continue;
                at(gx, gy) = at(tile.x + std::clamp(s, 0, tile.width - 1), tile.y + std::clamp(t, 0, tile.height - 1));
            }
    }
    return sources;
}

std::vector<glm::vec3> gatherAtlas(const std::vector<std::uint32_t>& sources, const std::vector<glm::vec3>& values, glm::vec3 blank)
{
    std::vector<glm::vec3> map;
    gatherAtlas(sources, values, blank, map);
    return map;
}

void gatherAtlas(const std::vector<std::uint32_t>& sources, const std::vector<glm::vec3>& values, glm::vec3 blank,
                 std::vector<glm::vec3>& map)
{
    map.resize(sources.size());
    for (std::size_t p = 0; p < sources.size(); ++p) {
        const std::uint32_t k = sources[p];
        const glm::vec3 v = k < values.size() ? values[k] : blank;
        map[p] = std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z) ? v : blank;
    }
}

std::vector<glm::vec3> atlasImage(const AoTexelLayout& layout, const std::vector<glm::vec3>& colour, glm::vec3 blank)
{
    return gatherAtlas(atlasSources(layout), colour, blank);
}

void lowerThisThreadsPriority()
{
#ifdef __linux__
    setpriority(PRIO_PROCESS, pid_t(syscall(SYS_gettid)), 10);
#endif
}

} // namespace sightline::ui
