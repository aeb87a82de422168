#include "base/NpyFile.h"

#include <bit>
#include <cstdint>
#include <cstring>
#include <regex>
#include <stdexcept>

#include "base/AtomicFile.h"
#include "base/Error.h"
#include "base/InputFile.h"

namespace sightline {

static_assert(std::endian::native == std::endian::little,
              "the arrays copy little-endian values as bytes");

namespace npy {

namespace {
constexpr char kMagic[] = "\x93NUMPY";
} // namespace

std::string preamble(const std::string& descr, const std::string& shape)
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

File read(const std::filesystem::path& file)
{
    File npy;
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

int dimension(const std::string& digits, const File& npy, const std::filesystem::path& file)
{
    if (digits.size() > 10 || std::stoull(digits) > npy.bytes.size() || std::stoull(digits) > 0x7fffffffull)
        throw Error(file.string() + ": shape dimension " + digits + " does not match the file's " +
                    std::to_string(npy.bytes.size()) + " bytes");
    return int(std::stoull(digits));
}

void checkDataSize(const File& npy, std::uint64_t count, std::uint64_t itemBytes, const std::filesystem::path& file)
{
    // Dividing first keeps a hostile shape from overflowing count * itemBytes.
    const std::uint64_t available = npy.bytes.size() - npy.dataStart;
    if (count > available / itemBytes || count * itemBytes != available)
        throw Error(file.string() + ": data size does not match the shape");
}

} // namespace npy

std::string encodeFloatNpy(const std::vector<float>& values, int rows, int columns)
{
    if (rows < 0 || columns < 0 || std::size_t(rows) * std::size_t(columns) != values.size())
        throw std::invalid_argument("encodeFloatNpy: shape does not match the value count");
    std::string out = npy::preamble("<f4", std::to_string(rows) + ", " + std::to_string(columns));
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
    std::string out = npy::preamble("<f4", text);
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
    const npy::File npyFile = npy::read(file);
    static const std::regex shapeRe(R"('shape':\s*\((\d+),\s*(\d+),?\))");
    std::smatch m;
    if (npyFile.header.find("'<f4'") == std::string::npos || npyFile.header.find("'fortran_order': False") == std::string::npos ||
        !std::regex_search(npyFile.header, m, shapeRe))
        throw Error(file.string() + ": not a C-order float32 array of 2 dimensions");
    FloatArray array;
    array.rows = npy::dimension(m[1], npyFile, file);
    array.columns = npy::dimension(m[2], npyFile, file);
    if (array.rows < 1 || array.columns < 1)   // nothing to read, and no data pointer to copy from
        throw Error(file.string() + ": an empty array (shape " + std::string(m[1]) + " x " + std::string(m[2]) + ")");
    const std::size_t count = std::size_t(array.rows) * std::size_t(array.columns);
    npy::checkDataSize(npyFile, count, sizeof(float), file);
    array.values.resize(count);
    std::memcpy(array.values.data(), npyFile.bytes.data() + npyFile.dataStart, count * sizeof(float));
    return array;
}

} // namespace sightline
