#include "GltfTextures.h"

#include "TextureMean.h"
#include "base/Error.h"

namespace sightline::gltf {

const std::vector<RgbImage>* TextureImages::linear(int index, std::vector<std::string>& warnings)
{
    if (index < 0 || std::size_t(index) >= encoded.size())
        return nullptr;
    const std::size_t i = std::size_t(index);
    if (decoded_.size() < encoded.size())
        decoded_.resize(encoded.size()), tried_.resize(encoded.size(), 0);
    if (!tried_[i]) {
        tried_[i] = 1;
        try {
            std::string bytes = std::move(encoded[i]);   // decoded or not, not needed again
            std::string().swap(encoded[i]);
            if (bytes.empty() && fromView)
                bytes = fromView(index);
            if (!bytes.empty())
                decoded_[i] = texture::linearMips(decodeRgbImage(bytes, file_ + ": image " + std::to_string(index)));
        } catch (const Error& e) {
            warnings.push_back(std::string(e.what()) + "; the materials it colours keep unknown albedos");
        }
    }
    return decoded_[i].empty() ? nullptr : &decoded_[i];
}

} // namespace sightline::gltf
