#include "visibility/MaskNpy.h"

#include <bit>
#include <cstdint>
#include <cstring>
#include <regex>

#include "base/AtomicFile.h"
#include "base/Error.h"
#include "base/NpyFile.h"

namespace sightline {

static_assert(std::endian::native == std::endian::little,
              "the mask layout copies little-endian words as bytes");

namespace {
int bytesPerRow(int sourceCount) { return (sourceCount + 7) / 8; }
} // namespace

std::string encodeMaskNpy(const HiddenSampleMap& map)
{
    const int rowBytes = bytesPerRow(map.sourceCount());
    std::string out = npy::preamble("|u1", std::to_string(map.receiverNb()) + ", " + std::to_string(map.receiverNa()) +
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
    const npy::File array = npy::read(file);
    const std::string& bytes = array.bytes;
    const std::string& header = array.header;
    static const std::regex shapeRe(R"('shape':\s*\((\d+),\s*(\d+),\s*(\d+),?\))");
    std::smatch m;
    if (header.find("'|u1'") == std::string::npos || header.find("'fortran_order': False") == std::string::npos ||
        !std::regex_search(header, m, shapeRe))
        throw Error(file.string() + ": not a C-order |u1 array of 3 dimensions");
    const int nb = npy::dimension(m[1], array, file), na = npy::dimension(m[2], array, file), rowBytes = npy::dimension(m[3], array, file);
    if (sourceCount < 1 || rowBytes != bytesPerRow(sourceCount) || na < 1 || nb < 1)
        throw Error(file.string() + ": shape does not match " + std::to_string(sourceCount) + " source samples");
    npy::checkDataSize(array, std::uint64_t(na) * std::uint64_t(nb), std::uint64_t(rowBytes), file);
    HiddenSampleMap map(sourceCount, na, nb);
    const std::size_t dataStart = array.dataStart;
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
