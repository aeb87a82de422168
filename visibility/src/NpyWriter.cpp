#include "visibility/NpyWriter.h"

#include <bit>
#include <cstdint>
#include <cstring>
#include <regex>
#include <stdexcept>

#include "visibility/AtomicFile.h"
#include "visibility/Error.h"
#include "visibility/InputFile.h"

namespace sightline {

static_assert(std::endian::native == std::endian::little,
              "the mask layout copies little-endian words as bytes");

namespace {
constexpr char kMagic[] = "\x93NUMPY";

int bytesPerRow(int sourceCount) { return (sourceCount + 7) / 8; }

/// Format 1.0 preamble: magic(6) + version(2) + header length(2) + header, padded with spaces and
/// ended by '\n' so that the data starts on a multiple of 64 bytes.
std::string npyPreamble(const std::string& descr, const std::string& shape)
{
    std::string header = "{'descr': '" + descr + "', 'fortran_order': False, 'shape': (" + shape + "), }";
    const std::size_t unpadded = 10 + header.size() + 1;
    header.append((64 - unpadded % 64) % 64, ' ');
    header.push_back('\n');

    std::string out(kMagic, 6);
    out.push_back('\x01');
    out.push_back('\x00');
    out.push_back(static_cast<char>(header.size() & 0xff));
    out.push_back(static_cast<char>(header.size() >> 8));
    out += header;
    return out;
}

/// The file's bytes and its header (after the checks every reader needs).
struct NpyFile {
    std::string bytes;
    std::string header;
    std::size_t dataStart = 0;
};

NpyFile readNpy(const std::filesystem::path& file)
{
    NpyFile npy;
    npy.bytes = readInputFile(file, "NumPy array");
    const std::string& bytes = npy.bytes;
    if (bytes.size() < 10 || bytes.compare(0, 6, kMagic, 6) != 0 || bytes[6] != 1)
        throw Error(file.string() + ": not a NumPy format 1.0 file");
    const std::size_t headerLength = std::size_t(std::uint8_t(bytes[8])) | std::size_t(std::uint8_t(bytes[9])) << 8;
    // NumPy writes a few dozen bytes of header; a long one would only feed the shape regex
    // (libstdc++'s is recursive: tens of kilobytes of spaces would overflow the stack).
    if (headerLength > 4096)
        throw Error(file.string() + ": .npy header of " + std::to_string(headerLength) + " bytes (at most 4096 are read)");
    if (bytes.size() < 10 + headerLength)
        throw Error(file.string() + ": truncated .npy header");
    npy.header = bytes.substr(10, headerLength);
    npy.dataStart = 10 + headerLength;
    return npy;
}

/// A dimension of a shape as written (digits only, from the header's regex). Anything past the
/// file's own size cannot match its data, so it is refused before any arithmetic can overflow.
int dimension(const std::string& digits, const NpyFile& npy, const std::filesystem::path& file)
{
    if (digits.size() > 10 || std::stoull(digits) > npy.bytes.size() || std::stoull(digits) > 0x7fffffffull)
        throw Error(file.string() + ": shape dimension " + digits + " does not match the file's " +
                    std::to_string(npy.bytes.size()) + " bytes");
    return int(std::stoull(digits));
}

/// Refuses data whose size is not `count` items of `itemBytes`, before anything is allocated.
void checkDataSize(const NpyFile& npy, std::uint64_t count, std::uint64_t itemBytes, const std::filesystem::path& file)
{
    // Dividing first keeps a hostile shape from overflowing count * itemBytes.
    const std::uint64_t available = npy.bytes.size() - npy.dataStart;
    if (count > available / itemBytes || count * itemBytes != available)
        throw Error(file.string() + ": data size does not match the shape");
}
} // namespace

std::string encodeMaskNpy(const HiddenSampleMap& map)
{
    const int rowBytes = bytesPerRow(map.sourceCount());
    std::string out = npyPreamble("|u1", std::to_string(map.receiverNb()) + ", " + std::to_string(map.receiverNa()) +
                                             ", " + std::to_string(rowBytes));

    const std::size_t dataStart = out.size();
    out.resize(dataStart + std::size_t(rowBytes) * std::size_t(map.receiverCount()));
    char* dst = out.data() + dataStart;
    for (int j = 0; j < map.receiverCount(); ++j, dst += rowBytes)
        std::memcpy(dst, map.row(j).data(), std::size_t(rowBytes));
    return out;
}

void writeMaskNpy(const HiddenSampleMap& map, const std::filesystem::path& file)
{
    writeFileAtomically(file, encodeMaskNpy(map));
}

HiddenSampleMap readMaskNpy(const std::filesystem::path& file, int sourceCount)
{
    const NpyFile npy = readNpy(file);
    const std::string& bytes = npy.bytes;
    const std::string& header = npy.header;
    static const std::regex shapeRe(R"('shape':\s*\((\d+),\s*(\d+),\s*(\d+),?\))");
    std::smatch m;
    if (header.find("'|u1'") == std::string::npos || header.find("'fortran_order': False") == std::string::npos ||
        !std::regex_search(header, m, shapeRe))
        throw Error(file.string() + ": not a C-order |u1 array of 3 dimensions");
    const int nb = dimension(m[1], npy, file), na = dimension(m[2], npy, file), rowBytes = dimension(m[3], npy, file);
    if (sourceCount < 1 || rowBytes != bytesPerRow(sourceCount) || na < 1 || nb < 1)
        throw Error(file.string() + ": shape does not match " + std::to_string(sourceCount) + " source samples");
    checkDataSize(npy, std::uint64_t(na) * std::uint64_t(nb), std::uint64_t(rowBytes), file);
    HiddenSampleMap map(sourceCount, na, nb);
    const std::size_t dataStart = npy.dataStart;
    for (int j = 0; j < map.receiverCount(); ++j) {
        std::memcpy(map.row(j).data(), bytes.data() + dataStart + std::size_t(j) * std::size_t(rowBytes),
                    std::size_t(rowBytes));
        // Keep the invariant: no bits past the source count.
        if (sourceCount % 64 != 0)
            map.row(j).back() &= (std::uint64_t(1) << (sourceCount % 64)) - 1;
    }
    return map;
}

std::string encodeFloatNpy(const std::vector<float>& values, int rows, int columns)
{
    if (rows < 0 || columns < 0 || std::size_t(rows) * std::size_t(columns) != values.size())
        throw std::invalid_argument("encodeFloatNpy: shape does not match the value count");
    std::string out = npyPreamble("<f4", std::to_string(rows) + ", " + std::to_string(columns));
    const std::size_t dataStart = out.size();
    out.resize(dataStart + values.size() * sizeof(float));
    std::memcpy(out.data() + dataStart, values.data(), values.size() * sizeof(float));
    return out;
}

void writeFloatNpy(const std::vector<float>& values, int rows, int columns, const std::filesystem::path& file)
{
    writeFileAtomically(file, encodeFloatNpy(values, rows, columns));
}

std::string encodeFloatNpy(const std::vector<float>& values, const std::vector<std::size_t>& shape)
{
    std::size_t count = 1;
    std::string text;   // "2, 3, 3"; a 1-D shape keeps Python's comma: "5,"
    for (std::size_t k = 0; k < shape.size(); ++k) {
        count *= shape[k];
        text += (k ? ", " : "") + std::to_string(shape[k]);
    }
    if (shape.size() == 1)
        text += ",";
    if (shape.empty() || count != values.size())
        throw std::invalid_argument("encodeFloatNpy: shape does not match the value count");
    std::string out = npyPreamble("<f4", text);
    const std::size_t dataStart = out.size();
    out.resize(dataStart + values.size() * sizeof(float));
    if (!values.empty())
        std::memcpy(out.data() + dataStart, values.data(), values.size() * sizeof(float));
    return out;
}

void writeFloatNpy(const std::vector<float>& values, const std::vector<std::size_t>& shape, const std::filesystem::path& file)
{
    writeFileAtomically(file, encodeFloatNpy(values, shape));
}

FloatArray readFloatNpy(const std::filesystem::path& file)
{
    const NpyFile npy = readNpy(file);
    static const std::regex shapeRe(R"('shape':\s*\((\d+),\s*(\d+),?\))");
    std::smatch m;
    if (npy.header.find("'<f4'") == std::string::npos || npy.header.find("'fortran_order': False") == std::string::npos ||
        !std::regex_search(npy.header, m, shapeRe))
        throw Error(file.string() + ": not a C-order float32 array of 2 dimensions");
    FloatArray array;
    array.rows = dimension(m[1], npy, file);
    array.columns = dimension(m[2], npy, file);
    if (array.rows < 1 || array.columns < 1)   // nothing to read, and no data pointer to copy from
        throw Error(file.string() + ": an empty array (shape " + std::string(m[1]) + " x " + std::string(m[2]) + ")");
    const std::size_t count = std::size_t(array.rows) * std::size_t(array.columns);
    checkDataSize(npy, count, sizeof(float), file);
    array.values.resize(count);
    std::memcpy(array.values.data(), npy.bytes.data() + npy.dataStart, count * sizeof(float));
    return array;
}

} // namespace sightline
