#include "visibility/NpyWriter.h"

#include <bit>
#include <cstring>
#include <fstream>
#include <iterator>
#include <regex>

#include "visibility/AtomicFile.h"
#include "visibility/Error.h"

namespace sightline {

static_assert(std::endian::native == std::endian::little,
              "the mask layout copies little-endian words as bytes");

namespace {
constexpr char kMagic[] = "\x93NUMPY";

int bytesPerRow(int sourceCount) { return (sourceCount + 7) / 8; }
} // namespace

std::string encodeMaskNpy(const HiddenSampleMap& map)
{
    const int rowBytes = bytesPerRow(map.sourceCount());
    std::string header = "{'descr': '|u1', 'fortran_order': False, 'shape': (" +
                         std::to_string(map.receiverNb()) + ", " + std::to_string(map.receiverNa()) +
                         ", " + std::to_string(rowBytes) + "), }";
    // Format 1.0: magic(6) + version(2) + header length(2) + header, padded with spaces and ended
    // by '\n' so that the data starts on a multiple of 64 bytes.
    const std::size_t unpadded = 10 + header.size() + 1;
    header.append((64 - unpadded % 64) % 64, ' ');
    header.push_back('\n');

    std::string out(kMagic, 6);
    out.push_back('\x01');
    out.push_back('\x00');
    out.push_back(static_cast<char>(header.size() & 0xff));
    out.push_back(static_cast<char>(header.size() >> 8));
    out += header;

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
    std::ifstream in(file, std::ios::binary);
    if (!in)
        throw Error(file.string() + ": cannot open");
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (bytes.size() < 10 || bytes.compare(0, 6, kMagic, 6) != 0 || bytes[6] != 1)
        throw Error(file.string() + ": not a NumPy format 1.0 file");
    const std::size_t headerLength = std::size_t(std::uint8_t(bytes[8])) | std::size_t(std::uint8_t(bytes[9])) << 8;
    if (bytes.size() < 10 + headerLength)
        throw Error(file.string() + ": truncated .npy header");
    const std::string header = bytes.substr(10, headerLength);
    static const std::regex shapeRe(R"('shape':\s*\((\d+),\s*(\d+),\s*(\d+),?\))");
    std::smatch m;
    if (header.find("'|u1'") == std::string::npos || header.find("'fortran_order': False") == std::string::npos ||
        !std::regex_search(header, m, shapeRe))
        throw Error(file.string() + ": not a C-order |u1 array of 3 dimensions");
    const int nb = std::stoi(m[1]), na = std::stoi(m[2]), rowBytes = std::stoi(m[3]);
    if (rowBytes != bytesPerRow(sourceCount) || na < 1 || nb < 1)
        throw Error(file.string() + ": shape does not match " + std::to_string(sourceCount) + " source samples");
    HiddenSampleMap map(sourceCount, na, nb);
    const std::size_t dataStart = 10 + headerLength;
    if (bytes.size() != dataStart + std::size_t(rowBytes) * std::size_t(na) * std::size_t(nb))
        throw Error(file.string() + ": data size does not match the shape");
    for (int j = 0; j < map.receiverCount(); ++j) {
        std::memcpy(map.row(j).data(), bytes.data() + dataStart + std::size_t(j) * std::size_t(rowBytes),
                    std::size_t(rowBytes));
        // Keep the invariant: no bits past the source count.
        if (sourceCount % 64 != 0)
            map.row(j).back() &= (std::uint64_t(1) << (sourceCount % 64)) - 1;
    }
    return map;
}

} // namespace sightline
