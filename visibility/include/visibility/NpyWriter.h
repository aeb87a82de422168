#pragma once
// NumPy .npy files. The hidden-samples map (format 1.0), the mask contract of docs/design.md §4:
// dtype '|u1', shape (nb_r, na_r, ceil(S / 8)); receiver sample (a, b) at [b][a]; source bit i is
// bit i % 8 (least significant first) of byte i / 8; a set bit means blocked.

#include <filesystem>
#include <string>
#include <vector>

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

/// A 2-D float32 array as .npy (dtype '<f4', C order, shape (rows, columns)): importance maps and
/// light fractions, sample (a, b) at [b][a]. `values` holds rows * columns floats, row-major.
std::string encodeFloatNpy(const std::vector<float>& values, int rows, int columns);
/// Writes atomically; throws sightline::Error on failure.
void writeFloatNpy(const std::vector<float>& values, int rows, int columns, const std::filesystem::path& file);

/// A float32 array of any shape (dtype '<f4', C order): per-point irradiance (N, 3), per-sample
/// colours (nb, na, 3). `values` holds the product of `shape` floats.
std::string encodeFloatNpy(const std::vector<float>& values, const std::vector<std::size_t>& shape);
void writeFloatNpy(const std::vector<float>& values, const std::vector<std::size_t>& shape, const std::filesystem::path& file);

struct FloatArray {
    int rows = 0, columns = 0;
    std::vector<float> values;
};
/// Reads a 2-D '<f4' C-order array (tests, round trips). Throws sightline::Error on anything else.
FloatArray readFloatNpy(const std::filesystem::path& file);

} // namespace sightline
