#include "GltfTextures.h"

#include "base/Error.h"

namespace sightline::gltf {

const std::vector<RgbImage>* TextureImages::linear(int index, std::vector<std::string>& warnings)
{
    if (index < 0 || std::size_t(index) >= encoded.size())
        return nullptr;
    const std::string name = file_ + ": image " + std::to_string(index);
    const std::string& bytes = encoded[std::size_t(index)];
    if (bytes.empty() && !fromView)
        return nullptr;
    return decoded_.get(std::to_string(index), [&] {
        const std::string inView = bytes.empty() ? fromView(index) : std::string();
        if (bytes.empty() && inView.empty())
            throw Error(name + " has no bytes (its file was not found)");
        return decodeRgbImage(bytes.empty() ? inView : bytes, name);
    }, warnings);
}

} // namespace sightline::gltf
