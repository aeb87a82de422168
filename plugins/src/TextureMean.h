#pragma once
// The albedo a textured material gives a triangle: the mean of its colour texture over the
// triangle's texture coordinates, after the texture's values are decoded from sRGB to linear
// (8-bit colour textures are sRGB: glTF 2.0 §3.9.2 says so of base colour textures, and OBJ's
// map_Kd images are the same kind of file), its coordinates wrapped as the material says. Albedos
// are per triangle (Mesh::albedo in visibility/Scene.h), and what a diffuse bounce off a triangle
// reflects on average weighs each point of it alike: hence the plain mean over its area.

#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "base/ImageFile.h"

namespace sightline::texture {

/// Wrap modes (the GL enums glTF uses).
inline constexpr int kWrapRepeat = 10497, kWrapClamp = 33071, kWrapMirror = 33648;

struct Wrap {
    int s = kWrapRepeat, t = kWrapRepeat;
};

/// An sRGB-encoded channel in [0, 1] as linear (IEC 61966-2-1).
float srgbToLinear(float c);

/// An image and its box-filtered halvings down to 1 x 1 (a mip chain): level k + 1's texel is the
/// mean of level k's 2 x 2 block (the block's last row or column repeated where a side is odd).
std::vector<RgbImage> mipChain(RgbImage image);

/// The image's sRGB values as linear, with its mip chain: what meanOverTriangle samples.
std::vector<RgbImage> linearMips(RgbImage image);

/// The mean of a texture (`mips`: linearMips' chain) over the triangle abc of texture space, where
/// (0, 0) is the image's top-left corner and (1, 1) its bottom-right (glTF's convention; OBJ's v
/// runs the other way): bilinear samples at the centroids of the n x n subdivision of the triangle
/// into equal triangles, about two a texel along each side (n at most 16), from the finest level
/// whose texels are at least twice the samples' spacing, so that a triangle over many repeats of
/// the texture averages all of it (the whole image's mean where its area overflows a double).
/// Coordinates must be finite.
glm::vec3 meanOverTriangle(const std::vector<RgbImage>& mips, const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c, Wrap wrap);

} // namespace sightline::texture
