#include "base/ImageCheck.h"

#include <algorithm>
#include <cstdint>
#include <cstring>

#include "base/ImageFile.h"
#include "base/Error.h"

namespace sightline::image {

namespace {

/// A read position over the bytes; reading past the end is an error, never a zero.
class Cursor {
public:
    Cursor(const std::string& bytes, std::size_t at, const std::string& name, const char* what)
        : bytes_(bytes), at_(at), name_(name), what_(what) {}

    bool atEnd() const { return at_ >= bytes_.size(); }
    std::size_t at() const { return at_; }
    std::size_t left() const { return atEnd() ? 0 : bytes_.size() - at_; }
    std::uint8_t next()
    {
        need(1);
        return std::uint8_t(bytes_[at_++]);
    }
    void skip(std::uint64_t n)
    {
        need(n);
        at_ += std::size_t(n);
    }
    void back() { --at_; }
    void need(std::uint64_t n) const
    {
        if (n > left())
            truncated();
    }
    [[noreturn]] void truncated() const
    {
        throw Error(name_ + ": truncated " + what_ + " (the file ends before the data its header declares)");
    }

private:
    const std::string& bytes_;
    std::size_t at_;
    const std::string& name_;
    const char* what_;
};

std::uint32_t le16(const std::string& b, std::size_t at) { return std::uint8_t(b[at]) | std::uint32_t(std::uint8_t(b[at + 1])) << 8; }
std::uint32_t le32(const std::string& b, std::size_t at) { return le16(b, at) | le16(b, at + 2) << 16; }
std::uint32_t be16(const std::string& b, std::size_t at) { return std::uint32_t(std::uint8_t(b[at])) << 8 | std::uint8_t(b[at + 1]); }
std::uint32_t be32(const std::string& b, std::size_t at) { return be16(b, at) << 16 | be16(b, at + 2); }

bool startsWith(const std::string& bytes, const char* prefix)
{
    return bytes.compare(0, std::strlen(prefix), prefix) == 0;
}

/// A header line as stb's HDR reader sees it: up to '\n', as a C string. Throws when the line has
/// no '\n' (stb would take the end of the file as an empty line).
std::string headerLine(const std::string& bytes, std::size_t& at, const std::string& name)
{
    const std::size_t end = bytes.find('\n', at);
    if (end == std::string::npos || end - at > 1000)
        throw Error(name + ": truncated or malformed Radiance HDR header (each header line must end in a newline, "
                           "and the header in a blank line)");
    std::string line = bytes.substr(at, end - at);
    at = end + 1;
    return line.substr(0, line.find('\0'));
}

/// Digits only, at most 9 of them: "-Y 0100 +X 8" is fine, "-Y -5" and "-Y 1e9" are not.
bool parseSide(const std::string& text, std::size_t& at, int& value)
{
    const std::size_t first = at;
    long long v = 0;
    while (at < text.size() && text[at] >= '0' && text[at] <= '9' && at - first < 9)
        v = v * 10 + (text[at++] - '0');
    value = int(v);
    return at > first && (at >= text.size() || text[at] < '0' || text[at] > '9');
}

void checkPng(const std::string& bytes, const std::string& name)
{
    Cursor c(bytes, 8, name, "PNG");
    for (;;) {
        c.need(8);
        const std::uint32_t length = be32(bytes, c.at());
        const bool end = bytes.compare(c.at() + 4, 4, "IEND") == 0;
        c.skip(8);
        c.skip(std::uint64_t(length) + 4);   // data and CRC
        if (end)
            return;
    }
}

void checkJpeg(const std::string& bytes, const std::string& name)
{
    Cursor c(bytes, 2, name, "JPEG");
    for (;;) {
        // Markers may be padded with extra 0xff bytes.
        if (c.next() != 0xff)
            throw Error(name + ": corrupt JPEG (expected a marker)");
        std::uint8_t marker = c.next();
        while (marker == 0xff)
            marker = c.next();
        if (marker == 0xd9)
            return;   // end of image
        if (marker == 0x01 || (marker >= 0xd0 && marker <= 0xd7))
            continue;   // standalone markers
        c.need(2);
        const std::uint32_t length = be16(bytes, c.at());
        if (length < 2)
            throw Error(name + ": corrupt JPEG (a segment shorter than its length field)");
        c.skip(length);
        if (marker != 0xda)
            continue;
        // Entropy-coded data up to the next marker: 0xff 0x00 is a stuffed byte, 0xff 0xd0..0xd7 a
        // restart; the marker's 0xff is left for the loop above.
        for (;;) {
            if (c.next() != 0xff)
                continue;
            c.need(1);
            const std::uint8_t after = std::uint8_t(bytes[c.at()]);
            if (after == 0x00 || (after >= 0xd0 && after <= 0xd7)) {
                c.skip(1);
            } else if (after != 0xff) {
                c.back();
                break;
            }
        }
    }
}

void checkBmp(const std::string& bytes, const std::string& name, int width, int height)
{
    if (bytes.size() < 30)
        Cursor(bytes, bytes.size(), name, "BMP").truncated();
    const std::uint32_t offset = le32(bytes, 10), header = le32(bytes, 14);
    std::uint32_t bits = 0, compression = 0;
    if (header == 12) {
        bits = le16(bytes, 24);
    } else {
        if (bytes.size() < 34)
            Cursor(bytes, bytes.size(), name, "BMP").truncated();
        bits = le16(bytes, 28);
        compression = le32(bytes, 30);
    }
    if (compression != 0 && compression != 3)
        return;   // run-length BMPs: stb refuses them itself
    const std::uint64_t stride = (std::uint64_t(width) * bits + 31) / 32 * 4;
    Cursor(bytes, 0, name, "BMP").need(std::uint64_t(offset) + stride * std::uint64_t(height));
}

void checkTga(const std::string& bytes, const std::string& name, int width, int height)
{
    Cursor c(bytes, 0, name, "TGA");
    c.need(18);
    const std::uint32_t id = std::uint8_t(bytes[0]), type = std::uint8_t(bytes[2]);
    const std::uint32_t paletteEntries = std::uint8_t(bytes[1]) ? le16(bytes, 5) : 0, paletteBits = std::uint8_t(bytes[7]);
    const std::uint32_t bits = std::uint8_t(bytes[16]);
    const std::uint64_t pixelBytes = (bits + 7) / 8;
    c.skip(18 + id + std::uint64_t(paletteEntries) * ((paletteBits + 7) / 8));
    const std::uint64_t pixels = std::uint64_t(width) * std::uint64_t(height);
    if (type < 8) {
        c.need(pixels * pixelBytes);
        return;
    }
    // Run-length packets: a header byte, then one pixel (a run) or n pixels (raw).
    for (std::uint64_t done = 0; done < pixels;) {
        const std::uint8_t packet = c.next();
        const std::uint64_t n = (packet & 0x7f) + 1u;
        c.skip(packet & 0x80 ? pixelBytes : n * pixelBytes);
        done += n;
    }
}

void checkPnm(const std::string& bytes, const std::string& name, int width, int height)
{
    // stb's header reading: whitespace and comments between fields, one byte after the maximum.
    std::size_t at = 2;
    const auto isSpace = [](char ch) { return ch == ' ' || ch == '\t' || ch == '\n' || ch == '\v' || ch == '\f' || ch == '\r'; };
    const auto skipSpace = [&] {
        for (;;) {
            while (at < bytes.size() && isSpace(bytes[at]))
                ++at;
            if (at >= bytes.size() || bytes[at] != '#')
                return;
            while (at < bytes.size() && bytes[at] != '\n' && bytes[at] != '\r')
                ++at;
        }
    };
    long long maximum = 0;
    const auto integer = [&] {
        long long v = 0;
        while (at < bytes.size() && bytes[at] >= '0' && bytes[at] <= '9' && v < 100000000)
            v = v * 10 + (bytes[at++] - '0');
        return v;
    };
    skipSpace();
    integer();
    skipSpace();
    integer();
    skipSpace();
    maximum = integer();
    const std::uint64_t channels = bytes[1] == '6' ? 3 : 1, sampleBytes = maximum > 255 ? 2 : 1;
    Cursor(bytes, 0, name, "PNM").need(std::uint64_t(at) + 1 + channels * sampleBytes * std::uint64_t(width) * std::uint64_t(height));
}

} // namespace

bool isRadianceHdr(const std::string& bytes)
{
    return startsWith(bytes, "#?RADIANCE\n") || startsWith(bytes, "#?RGBE\n");
}

void checkRadianceHdr(const std::string& bytes, const std::string& name, int& width, int& height)
{
    std::size_t at = 0;
    const std::string magic = headerLine(bytes, at, name);
    if (magic != "#?RADIANCE" && magic != "#?RGBE")
        throw Error(name + ": not a Radiance HDR image (it must start with #?RADIANCE)");
    bool rgbe = false;
    for (;;) {
        const std::string line = headerLine(bytes, at, name);
        if (line.empty())
            break;
        rgbe = rgbe || line == "FORMAT=32-bit_rle_rgbe";
    }
    if (!rgbe)
        throw Error(name + ": unsupported Radiance HDR format (only FORMAT=32-bit_rle_rgbe is read, not XYZE)");
    const std::string resolution = headerLine(bytes, at, name);
    std::size_t r = 3;
    bool ok = resolution.compare(0, 3, "-Y ") == 0 && parseSide(resolution, r, height);
    ok = ok && resolution.compare(r, 4, " +X ") == 0;
    r += 4;
    ok = ok && parseSide(resolution, r, width) && resolution.find_first_not_of(" \r", r) == std::string::npos;
    if (!ok)
        throw Error(name + ": unsupported Radiance HDR resolution line '" + resolution.substr(0, 40) +
                    "' (only '-Y H +X W', rows from the top, is read)");
    if (width < 1 || height < 1 || width > kMaxImageSide || height > kMaxImageSide)
        throw Error(name + ": Radiance HDR size " + std::to_string(width) + "x" + std::to_string(height) + " is outside 1.." +
                    std::to_string(kMaxImageSide) + " pixels a side");
    const std::uint64_t pixels = std::uint64_t(width) * std::uint64_t(height);
    if (pixels > kMaxImagePixels)
        throw Error(name + ": Radiance HDR " + std::to_string(width) + "x" + std::to_string(height) + " would take " +
                    std::to_string(pixels * 24 >> 20) + " MB to load; at most " + std::to_string(kMaxImagePixels >> 20) +
                    " Mpixels are read");

    // The smallest data that can hold the declared pixels: 4 bytes a pixel flat; a run-length
    // scanline its 4-byte marker and, per channel, a 2-byte run per 127 pixels.
    const bool runLength = width >= 8 && width < 32768;
    const std::uint64_t flatRow = 4 * std::uint64_t(width), rleRow = 4 + 4 * 2 * ((std::uint64_t(width) + 126) / 127);
    const std::uint64_t least = std::uint64_t(height) * (runLength ? std::min(flatRow, rleRow) : flatRow);
    const std::uint64_t data = bytes.size() - at;
    if (data < least)
        throw Error(name + ": truncated Radiance HDR: " + std::to_string(width) + "x" + std::to_string(height) + " needs at least " +
                    std::to_string(least) + " bytes of pixel data, the file has " + std::to_string(data));
    Cursor c(bytes, at, name, "Radiance HDR");
    // stb reads a file as flat when its first scanline has no run-length marker (2, 2, then the
    // width's high byte, below 128).
    const auto marked = [&] {
        return c.left() >= 4 && bytes[c.at()] == 2 && bytes[c.at() + 1] == 2 && (std::uint8_t(bytes[c.at() + 2]) & 0x80) == 0;
    };
    if (!runLength || !marked()) {
        c.need(flatRow * std::uint64_t(height));
        return;
    }
    for (int y = 0; y < height; ++y) {
        if (!marked()) {
            c.need(4);
            throw Error(name + ": corrupt Radiance HDR: scanline " + std::to_string(y) +
                        " is flat among run-length ones (not read)");
        }
        c.skip(2);
        const int length = int(c.next()) << 8 | c.next();
        if (length != width)
            throw Error(name + ": corrupt Radiance HDR: scanline " + std::to_string(y) + " declares " + std::to_string(length) +
                        " pixels, the image " + std::to_string(width));
        for (int channel = 0; channel < 4; ++channel)
            for (int x = 0; x < width;) {
                const int count = c.next();
                const int n = count > 128 ? count - 128 : count;
                if (n == 0 || n > width - x)
                    throw Error(name + ": corrupt Radiance HDR: scanline " + std::to_string(y) + " has a run of " +
                                std::to_string(n) + " at pixel " + std::to_string(x) + " of " + std::to_string(width) +
                                " (runs must be 1 or more and end within the scanline)");
                c.skip(count > 128 ? 1 : std::uint64_t(n));
                x += n;
            }
    }
}

void checkNotTruncated(const std::string& bytes, const std::string& name, int width, int height)
{
    if (startsWith(bytes, "\x89PNG\r\n\x1a\n"))
        return checkPng(bytes, name);
    if (bytes.size() >= 2 && std::uint8_t(bytes[0]) == 0xff && std::uint8_t(bytes[1]) == 0xd8)
        return checkJpeg(bytes, name);
    if (startsWith(bytes, "BM"))
        return checkBmp(bytes, name, width, height);
    if (startsWith(bytes, "P5") || startsWith(bytes, "P6"))
        return checkPnm(bytes, name, width, height);
    if (startsWith(bytes, "GIF8") || startsWith(bytes, "8BPS") || startsWith(bytes, "\x53\x80\xf6\x34"))
        throw Error(name + ": GIF, PSD and PIC images are not read; save it as PNG");
    checkTga(bytes, name, width, height);   // stb's last guess, without a signature
}

} // namespace sightline::image
