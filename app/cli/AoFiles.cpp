#include "cli/AoFiles.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <sstream>

#include <glm/geometric.hpp>
#include <tiny_gltf.h>

#include "base/AtomicFile.h"
#include "report/PngFile.h"
#include "base/Error.h"

namespace sightline::cli {

namespace {

glm::vec3 clamped(const glm::vec3& c)
{
    if (std::isnan(c.r) || std::isnan(c.g) || std::isnan(c.b))
        return glm::vec3(0.0f);
    return glm::clamp(c, glm::vec3(0.0f), glm::vec3(1.0f));
}

int addView(tinygltf::Model& model, const void* data, std::size_t bytes, int target)
{
    std::vector<unsigned char>& buffer = model.buffers[0].data;
    tinygltf::BufferView view;
    view.buffer = 0;
    view.byteOffset = buffer.size();   // every element is 4-byte aligned
    view.byteLength = bytes;
    view.target = target;
    const auto* p = static_cast<const unsigned char*>(data);
    buffer.insert(buffer.end(), p, p + bytes);
    model.bufferViews.push_back(view);
    return int(model.bufferViews.size() - 1);
}

int addAccessor(tinygltf::Model& model, const void* data, std::size_t count, int type, int components, int componentType,
                int target)
{
    const std::size_t size = componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT ? 4 : 4;
    tinygltf::Accessor accessor;
    accessor.bufferView = addView(model, data, count * std::size_t(components) * size, target);
    accessor.componentType = componentType;
    accessor.type = type;
    accessor.count = count;
    model.accessors.push_back(accessor);
    return int(model.accessors.size() - 1);
}

int addPositions(tinygltf::Model& model, const std::vector<glm::vec3>& positions)
{
    const int index = addAccessor(model, positions.data(), positions.size(), TINYGLTF_TYPE_VEC3, 3,
                                  TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TARGET_ARRAY_BUFFER);
    glm::vec3 lo(positions.front()), hi(positions.front());
    for (const glm::vec3& p : positions) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    model.accessors[std::size_t(index)].minValues = {lo.x, lo.y, lo.z};
    model.accessors[std::size_t(index)].maxValues = {hi.x, hi.y, hi.z};
    return index;
}

/// The rotation (x, y, z, w) that turns -Z onto the unit vector `to`: a light node's, whose light
/// shines along its -Z.
std::vector<double> rotationFromMinusZ(const glm::dvec3& to)
{
    const glm::dvec3 from(0.0, 0.0, -1.0);
    const double w = 1.0 + glm::dot(from, to);
    if (w < 1e-12)
        return {1.0, 0.0, 0.0, 0.0};   // opposite: half a turn about X
    const glm::dvec3 axis = glm::cross(from, to);
    const double norm = std::sqrt(w * w + glm::dot(axis, axis));
    return {axis.x / norm, axis.y / norm, axis.z / norm, w / norm};
}

/// The lights as KHR_lights_punctual (tinygltf writes the model's list and extensionsUsed), a node
/// each under the scene.
void addLights(tinygltf::Model& model, const std::vector<PunctualLight>& lights)
{
    for (const PunctualLight& light : lights) {
        tinygltf::Light out;
        out.name = light.name;
        out.type = light.type;
        out.color = {light.colour.x, light.colour.y, light.colour.z};
        out.intensity = light.intensity;
        out.range = light.range;
        if (light.type == "spot")
            out.spot.innerConeAngle = light.innerAngle, out.spot.outerConeAngle = light.outerAngle;
        tinygltf::Node node;
        node.name = light.name;
        node.translation = {light.position.x, light.position.y, light.position.z};
        if (light.type != "point")
            node.rotation = rotationFromMinusZ(light.direction);
        node.extensions["KHR_lights_punctual"] =
            tinygltf::Value(tinygltf::Value::Object{{"light", tinygltf::Value(int(model.lights.size()))}});
        model.lights.push_back(out);
        model.scenes[0].nodes.push_back(int(model.nodes.size()));
        model.nodes.push_back(node);
    }
}

void saveModel(tinygltf::Model& model, tinygltf::Primitive primitive, const std::filesystem::path& file,
               const std::vector<PunctualLight>& lights = {})
{
    model.asset.version = "2.0";
    model.asset.generator = "Sightline (sightline-cli ao)";
    primitive.mode = TINYGLTF_MODE_TRIANGLES;
    tinygltf::Mesh mesh;
    mesh.name = "ambient-occlusion";
    mesh.primitives.push_back(primitive);
    model.meshes.push_back(mesh);
    tinygltf::Node node;
    node.mesh = 0;
    node.name = "ambient-occlusion";
    model.nodes.push_back(node);
    tinygltf::Scene scene;
    scene.name = "scene";
    scene.nodes.push_back(0);
    model.scenes.push_back(scene);
    model.defaultScene = 0;
    addLights(model, lights);
    std::string ext = file.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    if (ext != ".glb" && ext != ".gltf")
        throw Error(file.string() + ": glTF output must end in .glb or .gltf");
    const bool binary = ext == ".glb";
    tinygltf::TinyGLTF writer;
    std::ostringstream stream;
    if (!writer.WriteGltfSceneToStream(&model, stream, !binary, binary))
        throw Error(file.string() + ": serialising glTF failed");
    writeFileAtomically(file, stream.str());
}

} // namespace

unsigned char srgbByte(float linear)
{
    const float c = std::isnan(linear) ? 0.0f : std::clamp(linear, 0.0f, 1.0f);
    const float s = c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
    return static_cast<unsigned char>(std::lround(s * 255.0f));
}

void writeAoNpy(const std::vector<float>& values, const std::filesystem::path& file, int columns)
{
    const std::string shape = columns > 0 ? "(" + std::to_string(values.size() / std::size_t(columns)) + ", " +
                                                std::to_string(columns) + ")"
                                          : "(" + std::to_string(values.size()) + ",)";
    std::string header = "{'descr': '<f4', 'fortran_order': False, 'shape': " + shape + ", }";
    // Magic (6) + version (2) + length (2) + header, padded with spaces to a multiple of 64, '\n' last.
    const std::size_t total = (10 + header.size() + 1 + 63) / 64 * 64;
    header.append(total - 10 - header.size() - 1, ' ');
    header += '\n';
    std::string bytes("\x93NUMPY\x01\x00", 8);
    bytes += char(header.size() & 0xff);
    bytes += char(header.size() >> 8);
    bytes += header;
    const std::size_t at = bytes.size();
    bytes.resize(at + values.size() * 4);
    std::memcpy(bytes.data() + at, values.data(), values.size() * 4);   // x86-64 and ARM64 are little-endian
    writeFileAtomically(file, bytes);
}

void writeColouredPly(const AoOccluders& occluders, const std::vector<glm::vec3>& colours, const std::filesystem::path& file)
{
    std::string out = "ply\nformat binary_little_endian 1.0\ncomment Sightline ambient occlusion (sightline-cli ao)\n"
                      "element vertex " + std::to_string(occluders.vertices.size()) +
                      "\nproperty float x\nproperty float y\nproperty float z\n"
                      "property uchar red\nproperty uchar green\nproperty uchar blue\n"
                      "element face " + std::to_string(occluders.triangleCount()) +
                      "\nproperty list uchar uint vertex_indices\nend_header\n";
    out.reserve(out.size() + occluders.vertices.size() * 15 + occluders.triangleCount() * 13);
    for (std::size_t i = 0; i < occluders.vertices.size(); ++i) {
        char record[15];
        std::memcpy(record, &occluders.vertices[i], 12);
        const glm::vec3 c = colours[i];
        record[12] = char(srgbByte(c.r));
        record[13] = char(srgbByte(c.g));
        record[14] = char(srgbByte(c.b));
        out.append(record, 15);
    }
    for (std::size_t t = 0; t < occluders.triangleCount(); ++t) {
        char record[13];
        record[0] = 3;
        std::memcpy(record + 1, &occluders.indices[3 * t], 12);
        out.append(record, 13);
    }
    writeFileAtomically(file, out);
}

void writeColouredGltf(const AoOccluders& occluders, const std::vector<glm::vec3>& colours, const std::filesystem::path& file)
{
    if (occluders.vertices.empty() || occluders.indices.empty())
        throw Error(file.string() + ": nothing to write (no triangles)");
    tinygltf::Model model;
    model.buffers.emplace_back();
    tinygltf::Primitive primitive;
    primitive.attributes["POSITION"] = addPositions(model, occluders.vertices);
    std::vector<glm::vec3> linear(colours.size());
    std::transform(colours.begin(), colours.end(), linear.begin(), clamped);
    primitive.attributes["COLOR_0"] = addAccessor(model, linear.data(), linear.size(), TINYGLTF_TYPE_VEC3, 3,
                                                  TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TARGET_ARRAY_BUFFER);
    primitive.indices = addAccessor(model, occluders.indices.data(), occluders.indices.size(), TINYGLTF_TYPE_SCALAR, 1,
                                    TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
    saveModel(model, primitive, file);
}

void writeLightmappedGltf(const AoOccluders& occluders, const std::vector<glm::vec2>& cornerUvs, const std::string& lightmapUri,
                          const std::filesystem::path& file, LightmapUse use, const std::vector<PunctualLight>& lights)
{
    if (occluders.indices.empty())
        throw Error(file.string() + ": nothing to write (no triangles)");
    std::vector<glm::vec3> positions;
    for (std::uint32_t t = 0; t < occluders.triangleCount(); ++t)
        for (int c = 0; c < 3; ++c)
            positions.push_back(occluders.vertices[occluders.indices[3 * std::size_t(t) + std::size_t(c)]]);
    std::vector<glm::vec2> uv1 = cornerUvs;
    tinygltf::Model model;
    model.buffers.emplace_back();
    tinygltf::Primitive primitive;
    primitive.attributes["POSITION"] = addPositions(model, positions);
    std::vector<glm::vec2> uv0(uv1.size(), glm::vec2(0.0f));   // occlusionTexture may use set 1 only where set 0 exists
    primitive.attributes["TEXCOORD_0"] = addAccessor(model, uv0.data(), uv0.size(), TINYGLTF_TYPE_VEC2, 2,
                                                     TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TARGET_ARRAY_BUFFER);
    primitive.attributes["TEXCOORD_1"] = addAccessor(model, uv1.data(), uv1.size(), TINYGLTF_TYPE_VEC2, 2,
                                                     TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TARGET_ARRAY_BUFFER);
    tinygltf::Image image;
    image.uri = lightmapUri;
    image.mimeType = "image/png";
    model.images.push_back(image);
    tinygltf::Sampler sampler;
    sampler.magFilter = TINYGLTF_TEXTURE_FILTER_LINEAR;
    sampler.minFilter = TINYGLTF_TEXTURE_FILTER_LINEAR;
    sampler.wrapS = sampler.wrapT = TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE;
    model.samplers.push_back(sampler);
    tinygltf::Texture texture;
    texture.source = 0;
    texture.sampler = 0;
    model.textures.push_back(texture);
    tinygltf::Material material;
    if (use == LightmapUse::Occlusion) {
        material.name = "baked-ambient-occlusion";
        material.occlusionTexture.index = 0;
        material.occlusionTexture.texCoord = 1;
    } else {
        // glTF has no light-map slot; an emissive texture shows the bake in any viewer.
        material.name = "baked-irradiance";
        material.emissiveTexture.index = 0;
        material.emissiveTexture.texCoord = 1;
        material.emissiveFactor = {1.0, 1.0, 1.0};
        material.pbrMetallicRoughness.baseColorFactor = {0.0, 0.0, 0.0, 1.0};
    }
    model.materials.push_back(material);
    primitive.material = 0;
    saveModel(model, primitive, file, lights);
}

void writeLightmappedGltf(const AoOccluders& occluders, const AoTexelLayout& layout, const std::string& lightmapUri,
                          const std::filesystem::path& file)
{
    std::vector<glm::vec2> uvs;
    for (std::uint32_t t = 0; t < occluders.triangleCount(); ++t)
        for (int c = 0; c < 3; ++c)
            uvs.push_back(layout.tiles[t].width ? layout.uv(occluders, t, c) : glm::vec2(0.0f));
    writeLightmappedGltf(occluders, uvs, lightmapUri, file, LightmapUse::Occlusion);
}

void writeAtlasPng(int width, int height, const std::vector<glm::vec3>& pixels, const std::filesystem::path& file)
{
    std::vector<unsigned char> rgb(std::size_t(width) * std::size_t(height) * 3, 0);
    for (std::size_t k = 0; k < pixels.size() && k < std::size_t(width) * std::size_t(height); ++k) {
        rgb[3 * k] = srgbByte(pixels[k].r);
        rgb[3 * k + 1] = srgbByte(pixels[k].g);
        rgb[3 * k + 2] = srgbByte(pixels[k].b);
    }
    saveRgbPng(width, height, rgb, file);
}

void writeLightmapPng(const AoTexelLayout& layout, const std::vector<glm::vec3>& texelColours, const std::filesystem::path& file)
{
    std::vector<glm::vec3> pixels(std::size_t(layout.width) * std::size_t(layout.height), glm::vec3(0.0f));
    for (const AoTexelTile& tile : layout.tiles)
        for (int t = 0; t < tile.height; ++t)
            for (int s = 0; s < tile.width; ++s)
                pixels[std::size_t(tile.y + t) * std::size_t(layout.width) + std::size_t(tile.x + s)] =
                    texelColours[tile.firstPoint + std::size_t(t) * std::size_t(tile.width) + std::size_t(s)];
    writeAtlasPng(layout.width, layout.height, pixels, file);
}

} // namespace sightline::cli
