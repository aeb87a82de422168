#pragma once
// NumPy .npy files, format 1.0: float32 arrays written and read, and the pieces every .npy reader
// shares (the preamble, the checked header, dimensions refused before any arithmetic can overflow).

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace sightline {

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

namespace npy {

/// Magic, version 1.0, header length and the header for `descr` and `shape` (e.g. "2, 3"), padded
/// with spaces and ended by '\n' so that the data starts on a multiple of 64 bytes.
std::string preamble(const std::string& descr, const std::string& shape);

/// A file's bytes and its header, after the checks every reader needs (magic, version, a header of
/// at most 4096 bytes that the file holds whole).
struct File {
    std::string bytes;
    std::string header;
    std::size_t dataStart = 0;
};
File read(const std::filesystem::path& file);

/// A dimension of a shape as written (digits only). Anything past the file's own size cannot match
/// its data, so it is refused before any arithmetic can overflow.
int dimension(const std::string& digits, const File& npy, const std::filesystem::path& file);

/// Refuses data whose size is not `count` items of `itemBytes`, before anything is allocated.
void checkDataSize(const File& npy, std::uint64_t count, std::uint64_t itemBytes, const std::filesystem::path& file);

} // namespace npy
} // namespace sightline
