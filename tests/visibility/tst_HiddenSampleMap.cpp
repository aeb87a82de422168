#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>

#include <gtest/gtest.h>

#include "base/Error.h"
#include "visibility/HiddenSampleMap.h"
#include "visibility/MaskNpy.h"

using namespace sightline;

TEST(HiddenSampleMap, SetAndCountBits)
{
    HiddenSampleMap map(100, 3, 2);
    EXPECT_EQ(map.wordsPerRow(), 2);
    EXPECT_EQ(map.rayCount(), 600u);
    map.setBlocked(0, 0);
    map.setBlocked(0, 99);
    map.setBlocked(5, 64);
    map.setBlocked(5, 64);
    EXPECT_TRUE(map.blocked(0, 99));
    EXPECT_FALSE(map.blocked(0, 98));
    EXPECT_EQ(map.blockedCount(0), 2);
    EXPECT_EQ(map.blockedCount(5), 1);
    EXPECT_EQ(map.blockedCount(), 3u);

    HiddenSampleMap other(100, 3, 2);
    other.setBlocked(0, 0);
    other.setBlocked(1, 1);
    EXPECT_EQ(map.differenceCount(other), 3u);   // (0,99), (5,64), (1,1)
    EXPECT_THROW(map.differenceCount(HiddenSampleMap(99, 3, 2)), std::invalid_argument);
}

TEST(HiddenSampleMap, RolesSwapTransposesTheRays)
{
    // 3 source samples (a 3x1 grid) and a 5x2 receiver grid; swapped: 10 source samples and a
    // 3x1 receiver grid.
    HiddenSampleMap map(3, 5, 2);
    map.setBlocked(0, 2);
    map.setBlocked(7, 0);
    map.setBlocked(9, 1);
    map.setBlocked(9, 2);
    const HiddenSampleMap swapped = map.withRolesSwapped(3, 1);
    EXPECT_EQ(swapped.sourceCount(), 10);
    EXPECT_EQ(swapped.receiverNa(), 3);
    EXPECT_EQ(swapped.receiverNb(), 1);
    EXPECT_EQ(swapped.blockedCount(), 4u);
    EXPECT_TRUE(swapped.blocked(2, 0));
    EXPECT_TRUE(swapped.blocked(0, 7));
    EXPECT_TRUE(swapped.blocked(1, 9));
    EXPECT_TRUE(swapped.blocked(2, 9));
    EXPECT_FALSE(swapped.blocked(0, 2));
    // Twice is the identity, across word boundaries too (100 source samples in a 10x10 grid, a
    // 7x10 receiver grid).
    HiddenSampleMap wide(100, 7, 10);
    for (int j = 0; j < 70; ++j)
        for (int i = (j * 7) % 3; i < 100; i += 3 + j % 5)
            wide.setBlocked(j, i);
    const HiddenSampleMap back = wide.withRolesSwapped(10, 10).withRolesSwapped(7, 10);
    EXPECT_EQ(back.sourceCount(), 100);
    EXPECT_EQ(back.receiverNa(), 7);
    EXPECT_EQ(back.receiverNb(), 10);
    EXPECT_EQ(back.blockedCount(), wide.blockedCount());
    for (int j = 0; j < 70; ++j)
        for (int i = 0; i < 100; ++i)
            ASSERT_EQ(back.blocked(j, i), wide.blocked(j, i)) << j << " " << i;
    EXPECT_THROW((void)map.withRolesSwapped(4, 2), std::invalid_argument);
}

TEST(NpyWriter, LayoutFollowsTheMaskContract)
{
    // 12 source samples -> 2 bytes per receiver; receiver grid 3 (na) x 2 (nb).
    HiddenSampleMap map(12, 3, 2);
    map.setBlocked(1, 9);    // receiver (a=1, b=0): byte 1, bit 1
    map.setBlocked(5, 0);    // receiver (a=2, b=1): byte 0, bit 0
    map.setBlocked(5, 11);   // byte 1, bit 3
    const std::string bytes = encodeMaskNpy(map);

    ASSERT_GE(bytes.size(), 10u);
    EXPECT_EQ(bytes.substr(0, 6), std::string("\x93NUMPY", 6));
    EXPECT_EQ(bytes[6], 1);
    EXPECT_EQ(bytes[7], 0);
    const std::size_t headerLength = std::size_t(std::uint8_t(bytes[8])) | std::size_t(std::uint8_t(bytes[9])) << 8;
    EXPECT_EQ((10 + headerLength) % 64, 0u);
    const std::string header = bytes.substr(10, headerLength);
    EXPECT_NE(header.find("'descr': '|u1'"), std::string::npos);
    EXPECT_NE(header.find("'shape': (2, 3, 2)"), std::string::npos) << header;
    EXPECT_EQ(header.back(), '\n');

    const std::string data = bytes.substr(10 + headerLength);
    ASSERT_EQ(data.size(), 2u * 3u * 2u);
    // [b][a][byte]: receiver j = b * na + a at offset j * 2.
    for (std::size_t k = 0; k < data.size(); ++k) {
        std::uint8_t expected = 0;
        if (k == 1 * 2 + 1)
            expected = 1u << 1;
        if (k == 5 * 2 + 0)
            expected = 1u << 0;
        if (k == 5 * 2 + 1)
            expected = 1u << 3;
        EXPECT_EQ(std::uint8_t(data[k]), expected) << "byte " << k;
    }
}

TEST(NpyWriter, RoundTripAndBadFiles)
{
    const auto folder = std::filesystem::temp_directory_path() / "sightline_npy_test";
    std::filesystem::create_directories(folder);
    HiddenSampleMap map(1024, 7, 5);
    for (int j = 0; j < map.receiverCount(); ++j)
        for (int i = j; i < 1024; i += 37)
            map.setBlocked(j, i);
    writeMaskNpy(map, folder / "m.npy");
    EXPECT_EQ(readMaskNpy(folder / "m.npy", 1024), map);
    EXPECT_THROW(readMaskNpy(folder / "m.npy", 512), Error);
    std::ofstream(folder / "bad.npy") << "not numpy";
    EXPECT_THROW(readMaskNpy(folder / "bad.npy", 1024), Error);
    EXPECT_THROW(writeMaskNpy(map, folder / "missing-folder" / "m.npy"), Error);
    std::filesystem::remove_all(folder);
}

namespace {

/// A .npy file with this header dictionary and data, padded as NumPy pads it.
std::string npyWith(std::string header, const std::string& data)
{
    while ((10 + header.size() + 1) % 64 != 0)
        header += ' ';
    header += '\n';
    std::string bytes = "\x93NUMPY\x01";
    bytes += '\0';
    bytes += char(header.size() & 0xff);
    bytes += char(header.size() >> 8);
    return bytes + header + data;
}

std::string npyError(const std::string& bytes, bool mask)
{
    const auto file = std::filesystem::temp_directory_path() / "sightline_npy_bad_shape.npy";
    std::ofstream(file, std::ios::binary) << bytes;
    try {
        if (mask)
            readMaskNpy(file, 8);
        else
            readFloatNpy(file);
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

} // namespace

// Found by fuzz_npy: a shape's digits overflowed std::stoi (an exception that is not an Error), a
// huge shape allocated its map before the data size was checked, and an empty float array copied
// from a null pointer.
TEST(NpyWriter, ShapesAreCheckedBeforeAnythingIsAllocated)
{
    const std::string mask = "{'descr': '|u1', 'fortran_order': False, 'shape': (%, 1, 1), }";
    auto with = [](std::string text, const std::string& value) { return text.replace(text.find('%'), 1, value); };
    EXPECT_NE(npyError(npyWith(with(mask, "99999999999999999999"), "x"), true).find("shape dimension"),
              std::string::npos);
    EXPECT_NE(npyError(npyWith(with(mask, "60"), "x"), true).find("data size does not match"), std::string::npos);
    const std::string floats = "{'descr': '<f4', 'fortran_order': False, 'shape': (0, 3), }";
    EXPECT_NE(npyError(npyWith(floats, ""), false).find("empty array"), std::string::npos);
    EXPECT_EQ(npyError(npyWith(with(mask, "2"), std::string(2, '\0')), true), "");   // a good one loads
    // A long header only fed the (recursive) shape regex: refused by its length.
    const std::string spaced = "{'descr': '|u1', 'fortran_order': False, 'shape':" + std::string(60000, ' ') + "(2, 1, 1), }";
    EXPECT_NE(npyError(npyWith(spaced, std::string(2, '\0')), true).find("at most 4096"), std::string::npos);
}
