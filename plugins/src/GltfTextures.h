#pragma once
// The albedo a glTF material with a base colour texture gives each triangle: its baseColorFactor
// times the mean of the texture over the triangle's texture coordinates, the texture's values
// decoded from sRGB to linear first (glTF 2.0 §3.9.2: the texture is sRGB, the factor linear), its
// coordinates wrapped as the texture's sampler says. Albedos are per triangle (Mesh::albedo in
// visibility/Scene.h), and what a diffuse bounce off a triangle reflects on average weighs each
// point of it alike: hence the plain mean over its area.

#include <set>
#include <string>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "base/ImageFile.h"

namespace sightline::gltf {

/// glTF sampler wrap modes (the GL enums glTF uses).
inline constexpr int kWrapRepeat = 10497, kWrapClamp = 33071, kWrapMirror = 33648;

struct TextureWrap {
    int s = kWrapRepeat, t = kWrapRepeat;
};

/// An sRGB-encoded channel in [0, 1] as linear (IEC 61966-2-1).
float srgbToLinear(float c);

/// An image and its box-filtered halvings down to 1 x 1 (a mip chain): level k + 1's texel is the
/// mean of level k's 2 x 2 block (the block's last row or column repeated where a side is odd).
std::vector<RgbImage> mipChain(RgbImage image);

/// The mean of a texture (`mips`: mipChain of linear RGB) over the triangle abc of texture space,
/// where (0, 0) is the image's top-left corner and (1, 1) its bottom-right (glTF's convention):
/// bilinear samples at the centroids of the n x n subdivision of the triangle into equal
/// triangles, about two a texel along each side (n at most 16), from the finest level whose texels
/// are at least twice the samples' spacing, so that a triangle over many repeats of the texture
/// averages all of it. Coordinates must be finite.
glm::vec3 meanOverTriangle(const std::vector<RgbImage>& mips, const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c,
                           TextureWrap wrap);

/// A glTF file's images as its loader met them: encoded bytes kept instead of decoded (most images
/// of a level are not base colour textures), each decoded to linear RGB once, on first use, through
/// base/ImageFile.h's checks.
class TextureImages {
public:
    explicit TextureImages(std::string file) : file_(std::move(file)) {}

    /// Per image index: its bytes, empty where the loader got none (a file not found, which
    /// tinygltf reports as a warning of its own).
    std::vector<std::string> encoded;

    /// Image `index` as linear RGB with its mip chain, or null where it has no bytes or cannot be
    /// decoded (a warning the first time, naming the image).
    const std::vector<RgbImage>* linear(int index, std::vector<std::string>& warnings);

    /// True the first time it is asked about a material: one warning a material, however many
    /// primitives use it.
    bool firstWarningFor(int material) { return warnedMaterials_.insert(material).second; }

private:
    std::set<int> warnedMaterials_;
    std::string file_;
    std::vector<std::vector<RgbImage>> decoded_;   ///< per image, its mip chain; empty: none
    std::vector<char> tried_;
};

} // namespace sightline::gltf
