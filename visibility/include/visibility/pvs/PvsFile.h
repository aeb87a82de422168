#pragma once
// PVS files. Byte layouts are in docs/pvs.md; all integers little-endian.
//
//  - .pvs: Sightline's versioned binary: header, cell table (bounds), object table (instance ids,
//    names, bounds), row offsets, rows raw or zero-run-length encoded.
//  - .pvs.json: docs/design.md §4's form, for diffs and outside checks.
//  - Quake-family rows: the classic zero-run-length encoding (a zero byte is followed by a count
//    of zero bytes, 1-255; other bytes are copied) in a Quake 1 layout (per-leaf offsets) and a
//    Quake 2 / Source `dvis_t` layout (numclusters, bitofs[n][2], rows).
//  - PRT1: the cells' shared faces as portals, for TrenchBroom's portal overlay.
//  - Part files of a sharded bake, with a manifest: scene hash, settings, shard I/N.

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "visibility/pvs/PvsData.h"

namespace sightline::pvs {

inline constexpr std::uint32_t kPvsFileVersion = 2;   ///< 2 adds the optional cell-to-cell rows; 1 is read too
inline constexpr std::uint32_t kPartFileVersion = 3;  ///< 3 carries the SHA-256 of its own bytes
inline constexpr std::uint32_t kMaxShards = 1000000;   ///< the most shards a bake may be split into

/// Quake's visibility row compression. `decompress` expands one row of `rowBytes` bytes starting
/// at `data[offset]` and throws sightline::Error when the data runs out or a run overflows the row;
/// `end`, when given, receives the offset just past the row's encoding.
std::vector<std::uint8_t> compressZeroRuns(const std::uint8_t* row, std::size_t rowBytes);
std::vector<std::uint8_t> decompressZeroRuns(std::string_view data, std::size_t offset, std::size_t rowBytes,
                                             std::size_t* end = nullptr);

enum class RowEncoding : std::uint32_t { Raw = 0, ZeroRuns = 1 };

/// The .pvs file's bytes. Deterministic: only the data, no times or paths.
std::string encodePvs(const PvsData& data, RowEncoding encoding = RowEncoding::ZeroRuns);
/// Parses a .pvs; `what` names it in errors. Throws sightline::Error on a bad magic, another
/// version, any size or offset that does not fit, cells that validateCells refuses, object boxes
/// that are neither empty nor finite and ordered, or a row that does not decode to its size.
/// Declared counts are checked against the bytes that follow before anything is allocated for
/// them (at most 255 row bytes per byte of encoded rows, and kMaxRowTableBytes).
PvsData decodePvs(std::string_view bytes, const std::string& what);

/// docs/design.md §4's JSON text (sorted keys as listed, one cell or object per line: diffable).
std::string pvsJson(const PvsData& data);
/// Parses that text back (the editor opens a .pvs.json). Throws sightline::Error naming the key
/// for anything pvsJson would not write: another version, a missing or mistyped key, cells that
/// validateCells refuses, object boxes neither empty (null) nor finite and ordered, a row of
/// another length than the cells, object indices unsorted, repeated or out of range, or a table
/// past kMaxRowTableBytes (checked before it is allocated).
PvsData decodePvsJson(std::string_view text, const std::string& what);

struct EncodedSizes {
    std::size_t raw = 0;          ///< cells x row bytes
    std::size_t compressed = 0;   ///< zero-run-length rows
};
EncodedSizes encodedSizes(const VisibilityRows& rows);

/// Quake 1: u32 numleafs, i32 visofs[numleafs], then the compressed rows (offsets from the start
/// of the row data, as a BSP's leaf visofs into the vis lump). The CLI writes the cell-to-cell
/// rows (PvsData::cellRows): leaf k = cell k, row bit d = cell d.
std::string quake1Vis(const VisibilityRows& rows);
/// Quake 2 / Source vis lump (dvis_t): i32 numclusters, i32 bitofs[numclusters][2] (PVS, PHS;
/// offsets from the lump's start; the PHS offset points at the PVS row, Sightline bakes no
/// hearing set), then the compressed rows. The CLI writes the cell-to-cell rows: cluster k =
/// cell k, row bit d = cell d.
std::string quake2Vis(const VisibilityRows& rows);

/// PRT1 text: one portal per pair of cells whose boxes share a face of positive area (the shared
/// rectangle, 4 points). Coordinates are Quake's (Z up): (x, -z, y) times `scale` (units per
/// metre; 1 keeps metres, 1/0.0254 gives Quake's inch-like units).
std::string prt1(const std::vector<Bounds>& cells, double scale = 1.0);

/// A sharded bake's part: which cells it holds and their rows, plus everything merge needs
/// (cells, objects, hashes), so merging reads no scene.
struct PvsPart {
    PvsData data;                     ///< rows only for `cellIndices`; others zero
    std::uint32_t shard = 0, shardCount = 1;
    std::vector<std::uint32_t> cellIndices;   ///< sorted
};

/// The cells shard `shard` of `shardCount` bakes: c % shardCount == shard (interleaved, so
/// shards of a level with dense and empty regions cost about the same).
std::vector<std::size_t> shardCells(std::size_t cellCount, std::uint32_t shard, std::uint32_t shardCount);

/// A part carries the SHA-256 of its own bytes; `decodePart` verifies it before reading anything
/// else, so a damaged part (a flipped bit, a cut copy) is refused, not merged.
std::string encodePart(const PvsPart& part);
PvsPart decodePart(std::string_view bytes, const std::string& what);
/// The manifest beside a part (JSON): scene and settings hashes, shard, cell count, the part's
/// SHA-256 (of the whole file); merge and --resume check a part against it when it is there.
std::string partManifest(const PvsPart& part, const std::string& partSha256, const std::string& settingsText);

/// Joins parts into one PVS: all of one scene and settings, one cell and object table, shards
/// 0..N-1 of one N, each once.
/// Throws sightline::Error naming the first part that does not fit (`names` are their files).
PvsData mergeParts(const std::vector<PvsPart>& parts, const std::vector<std::string>& names);

} // namespace sightline::pvs
