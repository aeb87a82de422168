#pragma once
// A potentially visible set: view cells, the objects they may see, one bit row per cell.
//
// Rows are bitsets over objects, least significant bit first (object o is bit o % 8 of byte o / 8),
// the layout of the Quake-family visibility rows (PvsFile.h). Everything here is plain data, so
// the bake, the file formats, the merge of shards and the editor's debugger all share it.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "visibility/Scene.h"

namespace sightline::pvs {

/// What the level's instances are to a PVS: an object is one instance or, grouped by name, every
/// instance of one name. `instance` is the first (lowest) instance index, the number docs/design.md §4's
/// .pvs.json writes; `instances` lists all of them, sorted.
struct PvsObject {
    std::string name;
    std::uint32_t instance = 0;
    std::vector<std::uint32_t> instances;
    Bounds bounds;
};

/// The most bytes one table of rows may take (cells x ceil(objects / 8)): 1 GiB, 8.6e9 pairs.
/// Bakes beyond it are refused before they start, and files declaring more are refused before
/// anything is allocated.
inline constexpr std::size_t kMaxRowTableBytes = std::size_t(1) << 30;

/// One bit row per cell over `objectCount` objects.
class VisibilityRows {
public:
    VisibilityRows() = default;
    /// Throws sightline::Error when the table would pass kMaxRowTableBytes.
    VisibilityRows(std::size_t cellCount, std::size_t objectCount);

    std::size_t cellCount() const { return cells_; }
    std::size_t objectCount() const { return objects_; }
    std::size_t rowBytes() const { return (objects_ + 7) / 8; }

    bool visible(std::size_t cell, std::size_t object) const
    {
        return (bytes_[cell * rowBytes() + object / 8] >> (object % 8)) & 1u;
    }
    void set(std::size_t cell, std::size_t object, bool value);
    const std::uint8_t* row(std::size_t cell) const { return bytes_.data() + cell * rowBytes(); }
    std::uint8_t* row(std::size_t cell) { return bytes_.data() + cell * rowBytes(); }
    /// Sorted object indices visible from `cell` (the editor's "what does this cell see").
    std::vector<std::uint32_t> visibleObjects(std::size_t cell) const;
    std::size_t visibleCount(std::size_t cell) const;
    std::size_t visibleCount() const;

    bool operator==(const VisibilityRows&) const = default;

private:
    std::size_t cells_ = 0, objects_ = 0;
    std::vector<std::uint8_t> bytes_;
};

/// A baked (or merged) PVS with what identifies its inputs: `sceneSha256` is the SHA-256 of the
/// scene file's bytes (hex), `settingsSha256` that of the canonical settings text
/// (PvsSettings.h: sample counts, mode, the assembled world geometry, the cells and objects), so a
/// part file of another scene or other settings is refused by comparing two strings.
struct PvsData {
    std::string sceneSha256;
    std::string settingsSha256;
    std::vector<Bounds> cells;
    std::vector<PvsObject> objects;
    VisibilityRows rows;
    /// Cell-to-cell rows (cells x cells: bit d of row c, cell d is visible from cell c), or empty
    /// (0 x 0) when not baked. The Quake formats' rows are over clusters: these.
    VisibilityRows cellRows;
    bool hasCellRows() const { return cellRows.cellCount() != 0; }
};

/// The first cell whose box holds `point` (boundaries included; the first of overlapping listed
/// boxes), if any: where a camera or a light stands, whose row it sees.
std::optional<std::size_t> cellAt(const std::vector<Bounds>& cells, const glm::dvec3& point);

/// The scene instances of the objects `rows` holds visible from `cell`, sorted (every instance
/// of a grouped object).
std::vector<std::uint32_t> instancesVisibleFrom(const VisibilityRows& rows, const std::vector<PvsObject>& objects,
                                                std::size_t cell);

} // namespace sightline::pvs
