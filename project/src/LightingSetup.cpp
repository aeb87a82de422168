#include "project/LightingSetup.h"

#include <cmath>

#include "base/ImageFile.h"
#include "base/Error.h"
#include "base/NpyFile.h"

namespace sightline {

using nlohmann::json;

namespace {

[[noreturn]] void fail(const std::string& what, const std::string& key, const std::string& problem)
{
    throw Error(what + ": '" + key + "' " + problem);
}

std::string pathKey(const json& object, const std::string& what, const std::string& key)
{
    if (!object.at(key).is_string() || object.at(key).get<std::string>().empty())
        fail(what, key, "must be a file path");
    return object.at(key).get<std::string>();
}

} // namespace

AreaLight projectLight(const Project& project, const Patch& source, const std::string& what)
{
    if (!project.extra.contains("light"))
        return AreaLight::white(source.sampleCount());
    const json& light = project.extra.at("light");
    if (!light.is_object() || !light.contains("texture"))
        fail(what, "light", "must be an object with a texture");
    int levels = 8;
    if (light.contains("levels")) {
        if (!light.at("levels").is_number_integer() || light.at("levels").get<long long>() < 1 ||
            light.at("levels").get<long long>() > 255)
            fail(what, "light.levels", "must be an integer in [1, 255]");
        levels = light.at("levels").get<int>();
    }
    const RgbImage texture = loadRgbImage(project.resolve(pathKey(light, what, "texture"), "light.texture"));
    return AreaLight::fromTexture(texture, source, levels);
}

ReceiverHeights projectReceiverHeights(const Project& project, const Patch& receiver, const std::string& what)
{
    ReceiverHeights heights;
    if (!project.extra.contains("receiver_heights"))
        return heights;
    const json& spec = project.extra.at("receiver_heights");
    if (!spec.is_object() || (spec.contains("image") == spec.contains("npy")))
        fail(what, "receiver_heights", "must be an object with either image (and metres) or npy");
    heights.metres.resize(std::size_t(receiver.sampleCount()));
    if (spec.contains("npy")) {
        const FloatArray array = readFloatNpy(project.resolve(pathKey(spec, what, "npy"), "receiver_heights.npy"));
        if (array.rows != receiver.nb || array.columns != receiver.na)
            fail(what, "receiver_heights.npy", "has shape (" + std::to_string(array.rows) + ", " +
                                                   std::to_string(array.columns) + "); the receiver's grid needs (" +
                                                   std::to_string(receiver.nb) + ", " + std::to_string(receiver.na) + ")");
        for (std::size_t j = 0; j < heights.metres.size(); ++j)
            heights.metres[j] = double(array.values[j]);
        return heights;
    }
    if (!spec.contains("metres") || !spec.at("metres").is_number() || !std::isfinite(spec.at("metres").get<double>()))
        fail(what, "receiver_heights.metres", "must be a finite number (the height of white)");
    const double metres = spec.at("metres").get<double>();
    const RgbImage image = loadRgbImage(project.resolve(pathKey(spec, what, "image"), "receiver_heights.image"));
    for (int b = 0; b < receiver.nb; ++b) {
        for (int a = 0; a < receiver.na; ++a) {
            const glm::vec3 c = image.bilinear((a + 0.5) / receiver.na, (b + 0.5) / receiver.nb);
            heights.metres[std::size_t(b * receiver.na + a)] = double(c.r + c.g + c.b) / 3.0 * metres;
        }
    }
    return heights;
}

ReceiverHeights validatedPairHeights(const Project& project)
{
    validatePatchPair(project.source, project.receiver);
    ReceiverHeights heights = projectReceiverHeights(project, project.receiver, project.name);
    validateReceiverHeights(project.source, project.receiver, heights);
    return heights;
}

} // namespace sightline
