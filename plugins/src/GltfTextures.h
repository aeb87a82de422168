#pragma once
// A glTF file's images for its base colour textures (TextureMean.h gives each triangle the mean of
// its texture): kept encoded as the loader met them and decoded on first use.

#include <functional>
#include <set>
#include <string>
#include <vector>

#include "TextureMean.h"
#include "base/ImageFile.h"

namespace sightline::gltf {

/// A glTF file's images as its loader met them: encoded bytes kept instead of decoded (most images
/// of a level are not base colour textures), decoded on first use through base/ImageFile.h's
/// checks to linear RGB and its mip chain (texture::DecodedTextures, within its budget).
class TextureImages {
public:
    explicit TextureImages(std::string file) : file_(std::move(file)) {}

    /// Per image index: its bytes, empty where the loader got none (a file not found, which
    /// tinygltf reports as a warning of its own, or an image in a bufferView).
    std::vector<std::string> encoded;
    /// An image's bytes from its bufferView, for those `encoded` lacks (empty where it has none);
    /// throws sightline::Error where the view does not lie inside its buffer.
    std::function<std::string(int image)> fromView;

    /// Image `index` as texture::linearMips' chain, or null where it has no bytes or cannot be
    /// decoded (a warning the first time, naming the image).
    const std::vector<RgbImage>* linear(int index, std::vector<std::string>& warnings);

    /// True the first time it is asked about a material: one warning a material, however many
    /// primitives use it.
    bool firstWarningFor(int material) { return warnedMaterials_.insert(material).second; }

private:
    std::set<int> warnedMaterials_;
    std::string file_;
    texture::DecodedTextures decoded_;
};

} // namespace sightline::gltf
