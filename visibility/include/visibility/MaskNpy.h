#pragma once
// The hidden-samples map as a NumPy .npy file (format 1.0), the mask contract of docs/design.md §4:
// dtype '|u1', shape (nb_r, na_r, ceil(S / 8)); receiver sample (a, b) at [b][a]; source bit i is
// bit i % 8 (least significant first) of byte i / 8; a set bit means blocked.

#include <filesystem>
#include <string>
#include <vector>

#include "base/NpyFile.h"   // the float arrays, for the callers that write both
#include "visibility/HiddenSampleMap.h"

namespace sightline {

/// The whole file's bytes (header + data).
std::string encodeMaskNpy(const HiddenSampleMap& map);
/// Writes atomically; throws sightline::Error on failure.
void writeMaskNpy(const HiddenSampleMap& map, const std::filesystem::path& file);
/// Reads a file written by writeMaskNpy (or by NumPy with the same dtype and shape) back, for
/// tests and round trips; `sourceCount` is the S the third dimension was made from. Throws
/// sightline::Error on anything else.
HiddenSampleMap readMaskNpy(const std::filesystem::path& file, int sourceCount);

} // namespace sightline
