#pragma once
// The albedo a textured material gives a triangle: the mean of its colour texture over the
// triangle's texture coordinates, after the texture's values are decoded from sRGB to linear
// (8-bit colour textures are sRGB: glTF 2.0 §3.9.2 says so of base colour textures, and OBJ's
// map_Kd images are the same kind of file), its coordinates wrapped as the material says. Albedos
// are per triangle (Mesh::albedo in visibility/Scene.h), and what a diffuse bounce off a triangle
// reflects on average weighs each point of it alike: hence the plain mean over its area.

#include <cstddef>
#include <functional>
#include <set>
#include <string>
#include <unordered_map>
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

/// The finest level kept of a texture: a side of at most this many texels. A triangle's mean needs
/// no finer ones (what it would change is the colour's variation within one kept texel), and the
/// level's whole chain stays under 5 MB however large the image.
inline constexpr int kMaxKeptSide = 512;

/// The image's sRGB values as linear, with its mip chain from the first level no side of which
/// passes kMaxKeptSide: what meanOverTriangle samples.
std::vector<RgbImage> linearMips(RgbImage image);

/// Textures decoded to linearMips' chains on first use and kept while their total stays within a
/// budget; past it, the kept ones are dropped and decoded again when asked for (a level may name
/// hundreds of textures). One that cannot be decoded is remembered, and said once.
class DecodedTextures {
public:
    static constexpr std::size_t kBudgetBytes = std::size_t(256) << 20;

    explicit DecodedTextures(std::size_t budgetBytes = kBudgetBytes) : budget_(budgetBytes) {}

    /// The chain under `key`, decoding it with `decode` (which throws sightline::Error for a
    /// texture it cannot read) where it is not kept; null where decoding failed (now: a warning
    /// with its message; before: nothing more).
    const std::vector<RgbImage>* get(const std::string& key, const std::function<RgbImage()>& decode, std::vector<std::string>& warnings);

private:
    std::unordered_map<std::string, std::vector<RgbImage>> kept_;
    std::set<std::string> failed_;
    std::size_t budget_;
    std::size_t bytes_ = 0;
};

/// The mean of a texture (`mips`: linearMips' chain) over the triangle abc of texture space, where
/// (0, 0) is the image's top-left corner and (1, 1) its bottom-right (glTF's convention; OBJ's v
/// runs the other way): bilinear samples at the centroids of the n x n subdivision of the triangle
/// into equal triangles, about two a texel along each side (n at most 16), from the finest level
/// whose texels are at least twice the samples' spacing, so that a triangle over many repeats of
/// the texture averages all of it (the whole image's mean where its area overflows a double).
/// Coordinates must be finite.
glm::vec3 meanOverTriangle(const std::vector<RgbImage>& mips, const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c, Wrap wrap);

} // namespace sightline::texture
