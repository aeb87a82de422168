#pragma once
// Small images the importer tests write (stb_image_write).

#include <string>
#include <vector>

#include <stb/stb_image_write.h>

namespace sightline::test {

/// A PNG of `width` x `height` RGB pixels, top row first.
inline std::string pngBytes(int width, int height, const std::vector<unsigned char>& rgb)
{
    std::string out;
    stbi_write_png_to_func(
        [](void* context, void* data, int size) { static_cast<std::string*>(context)->append(static_cast<const char*>(data), std::size_t(size)); },
        &out, width, height, 3, rgb.data(), width * 3);
    return out;
}

/// The textures' test image: 2 x 2, top row red and green, bottom row blue and sRGB 188 grey
/// (linear one half).
inline std::string fourColourPng() { return pngBytes(2, 2, {255, 0, 0, 0, 255, 0, 0, 0, 255, 188, 188, 188}); }

} // namespace sightline::test
