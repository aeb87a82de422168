#include "visibility/pvs/PvsData.h"

#include <algorithm>
#include <bit>
#include <string>

#include <glm/vector_relational.hpp>

#include "base/Error.h"

namespace sightline::pvs {

namespace {

std::size_t checkedTableBytes(std::size_t cellCount, std::size_t objectCount)
{
    const std::size_t rowBytes = (objectCount + 7) / 8;
    if (rowBytes != 0 && cellCount > kMaxRowTableBytes / rowBytes)
        throw Error("pvs: " + std::to_string(cellCount) + " cells x " + std::to_string(objectCount) +
                    " objects need more than the 1 GiB a table of rows may take; use fewer or larger cells, or group "
                    "objects by name");
    return cellCount * rowBytes;
}

} // namespace

VisibilityRows::VisibilityRows(std::size_t cellCount, std::size_t objectCount)
    : cells_(cellCount), objects_(objectCount), bytes_(checkedTableBytes(cellCount, objectCount), 0)
{
}

void VisibilityRows::set(std::size_t cell, std::size_t object, bool value)
{
    std::uint8_t& byte = bytes_[cell * rowBytes() + object / 8];
    const std::uint8_t bit = std::uint8_t(1u << (object % 8));
    byte = value ? std::uint8_t(byte | bit) : std::uint8_t(byte & ~bit);
}

std::vector<std::uint32_t> VisibilityRows::visibleObjects(std::size_t cell) const
{
    std::vector<std::uint32_t> out;
    for (std::size_t o = 0; o < objects_; ++o)
        if (visible(cell, o))
            out.push_back(std::uint32_t(o));
    return out;
}

std::size_t VisibilityRows::visibleCount(std::size_t cell) const
{
    std::size_t n = 0;
    for (std::size_t k = 0; k < rowBytes(); ++k)
        n += std::size_t(std::popcount(row(cell)[k]));
    return n;
}

std::size_t VisibilityRows::visibleCount() const
{
    std::size_t n = 0;
    for (std::uint8_t b : bytes_)
        n += std::size_t(std::popcount(b));
    return n;
}

std::optional<std::size_t> cellAt(const std::vector<Bounds>& cells, const glm::dvec3& point)
{
    for (std::size_t c = 0; c < cells.size(); ++c) {
        const Bounds& box = cells[c];
        if (!box.empty() && glm::all(glm::greaterThanEqual(point, glm::dvec3(box.min))) &&
            glm::all(glm::lessThanEqual(point, glm::dvec3(box.max))))
            return c;
    }
    return std::nullopt;
}

std::vector<std::uint32_t> instancesVisibleFrom(const VisibilityRows& rows, const std::vector<PvsObject>& objects,
                                                std::size_t cell)
{
    std::vector<std::uint32_t> out;
    for (std::uint32_t o : rows.visibleObjects(cell))
        out.insert(out.end(), objects.at(o).instances.begin(), objects.at(o).instances.end());
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
}

} // namespace sightline::pvs
