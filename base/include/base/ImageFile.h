#pragma once
// Small 8-bit images a project refers to: a light's colour texture, a receiver's height map, a
// glTF material's base colour texture. Read with stb_image (PNG, JPEG, BMP, TGA, ...); values stay
// as stored (no sRGB decoding here: a light texture is taken as the light's colours, a height
// map's grey level as a height; the glTF importer decodes its textures' sRGB itself).

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

namespace sightline {

struct RgbImage {
    int width = 0, height = 0;
    std::vector<glm::vec3> pixels;   ///< row-major, top row first, channels in [0, 1]

    /// The pixel under texture coordinates (s, t) in [0, 1]^2 with t = 0 at the bottom row (a
    /// patch's v direction points up the image), nearest texel.
    glm::vec3 nearest(double s, double t) const;
    /// Bilinear between texel centres, clamped at the borders; same (s, t) convention.
    glm::vec3 bilinear(double s, double t) const;
};

/// The largest image read: a side, and pixels in all (each costs 15 bytes while loading).
inline constexpr int kMaxImageSide = 16384;
inline constexpr std::uint64_t kMaxImagePixels = std::uint64_t(1) << 25;
/// The largest image file read (also for AO environments): the largest image at 4 bytes a pixel
/// (flat RGBE, 32-bit BMP) with room for compression overhead and metadata.
inline constexpr std::uint64_t kMaxImageFileBytes = std::uint64_t(192) << 20;

/// Throws sightline::Error with the file name when the file is missing, not a regular file
/// (base/InputFile.h), not a readable image, larger than the limits above, or shorter than
/// its header declares (a truncated file is an error, never black pixels). A Radiance HDR is
/// read too (its RGBE values clamped to [0, 1]), checked as AoEnvironment's are.
RgbImage loadRgbImage(const std::filesystem::path& file);

/// The same for an image's bytes already in memory (a glTF's embedded image); `name` starts every
/// error message.
RgbImage decodeRgbImage(const std::string& bytes, const std::string& name);

} // namespace sightline
