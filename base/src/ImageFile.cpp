#include "base/ImageFile.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include <stb/stb_image.h>

#include "base/ImageCheck.h"
#include "base/Error.h"
#include "base/InputFile.h"

namespace sightline {

namespace {
int clampIndex(int i, int n) { return std::clamp(i, 0, n - 1); }
} // namespace

glm::vec3 RgbImage::nearest(double s, double t) const
{
    const int x = clampIndex(int(std::floor(s * width)), width);
    const int y = clampIndex(int(std::floor((1.0 - t) * height)), height);
    return pixels[std::size_t(y) * std::size_t(width) + std::size_t(x)];
}

glm::vec3 RgbImage::bilinear(double s, double t) const
{
    const double fx = s * width - 0.5, fy = (1.0 - t) * height - 0.5;
    const int x0 = int(std::floor(fx)), y0 = int(std::floor(fy));
    const float wx = float(fx - x0), wy = float(fy - y0);
    auto at = [&](int x, int y) {
        return pixels[std::size_t(clampIndex(y, height)) * std::size_t(width) + std::size_t(clampIndex(x, width))];
    };
    return (1.0f - wy) * ((1.0f - wx) * at(x0, y0) + wx * at(x0 + 1, y0)) +
           wy * ((1.0f - wx) * at(x0, y0 + 1) + wx * at(x0 + 1, y0 + 1));
}

RgbImage loadRgbImage(const std::filesystem::path& file)
{
    // Read whole (a FIFO or a folder is refused by readInputFile), then checked and decoded from
    // these very bytes.
    return decodeRgbImage(readInputFile(file, "image", kMaxImageFileBytes), file.string());
}

RgbImage decodeRgbImage(const std::string& bytes, const std::string& name)
{
    // Checked before stb sees them: stb trusts a header's size and reads missing data as black
    // (ImageCheck.h).
    if (bytes.size() > kMaxImageFileBytes)
        throw Error(name + ": image of " + std::to_string(bytes.size() >> 20) + " MB; at most " +
                    std::to_string(kMaxImageFileBytes >> 20) + " MB are read");
    const auto* data8 = reinterpret_cast<const stbi_uc*>(bytes.data());
    const int size = int(bytes.size());
    int width = 0, height = 0, channels = 0;
    if (image::isRadianceHdr(bytes)) {
        image::checkRadianceHdr(bytes, name, width, height);
    } else {
        if (!stbi_info_from_memory(data8, size, &width, &height, &channels))
            throw Error(name + ": not a readable image (unknown format)");
        if (width < 1 || height < 1 || width > kMaxImageSide || height > kMaxImageSide)
            throw Error(name + ": image size " + std::to_string(width) + "x" + std::to_string(height) +
                        " is outside 1.." + std::to_string(kMaxImageSide) + " pixels a side");
        // Each pixel costs 3 decoded bytes plus 12 as floats; refuse before stb allocates.
        const std::uint64_t pixels = std::uint64_t(width) * std::uint64_t(height);
        if (pixels > kMaxImagePixels)
            throw Error(name + ": image " + std::to_string(width) + "x" + std::to_string(height) + " would take " +
                        std::to_string(pixels * 15 >> 20) + " MB to load; at most " + std::to_string(kMaxImagePixels >> 20) +
                        " Mpixels are read (a texture or height map needs far fewer)");
        image::checkNotTruncated(bytes, name, width, height);
    }
    unsigned char* data = stbi_load_from_memory(data8, size, &width, &height, &channels, 3);
    if (!data)
        throw Error(name + ": cannot decode image: " + stbi_failure_reason());
    RgbImage image;
    image.width = width;
    image.height = height;
    image.pixels.resize(std::size_t(width) * std::size_t(height));
    for (std::size_t k = 0; k < image.pixels.size(); ++k)
        image.pixels[k] = glm::vec3(data[3 * k], data[3 * k + 1], data[3 * k + 2]) / 255.0f;
    stbi_image_free(data);
    return image;
}

} // namespace sightline
