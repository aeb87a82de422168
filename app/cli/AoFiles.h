#pragma once
// The files `sightline-cli ao` writes for a designer's engine: the AO as float32
// .npy (docs/design.md §4), a PLY with vertex colours, a glTF binary with the AO (or the relit colour)
// baked into COLOR_0, and for the texel mode the light-map atlas PNG with the glTF's TEXCOORD_1
// and occlusionTexture pointing at it. All are written atomically (base/AtomicFile.h).
//
// Colour encoding: glTF COLOR_0 is linear (as the glTF spec says); PLY and PNG bytes are sRGB
// encoded (Sattler et al. §5: "standard gamma correction"). Values are clamped to [0, 1]; points
// without AO (NaN: a vertex of no face) are written black, as MeshLab shades them.

#include <filesystem>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "lighting/ao/AoGeometry.h"
#include "lighting/ao/AoTexels.h"
#include "plugins/GltfLights.h"

namespace sightline::cli {

/// float32 .npy of shape (n,) or, with `columns` > 0, (values.size() / columns, columns).
void writeAoNpy(const std::vector<float>& values, const std::filesystem::path& file, int columns = 0);
/// Binary little-endian PLY: the occluders' vertices (world space, instance order) with uchar
/// red, green, blue, and their triangles.
void writeColouredPly(const AoOccluders& occluders, const std::vector<glm::vec3>& colours, const std::filesystem::path& file);
/// glTF (.glb or .gltf): one mesh, world-space positions, COLOR_0 per vertex.
void writeColouredGltf(const AoOccluders& occluders, const std::vector<glm::vec3>& colours, const std::filesystem::path& file);
/// What a baked map stands for in the glTF's material: AO (occlusionTexture) or irradiance
/// (emissiveTexture over a black base colour: glTF has no light-map slot).
enum class LightmapUse { Occlusion, Emissive };
/// glTF with a baked map: every triangle's corners unshared, TEXCOORD_1 from `cornerUvs` (three a
/// triangle, in order), a material using the PNG `lightmapUri` (relative to the glTF) as `use` says;
/// `lights` as KHR_lights_punctual, one node each (at its position, its -Z along its direction), as
/// the importer reads them (plugins/GltfLights.h).
void writeLightmappedGltf(const AoOccluders& occluders, const std::vector<glm::vec2>& cornerUvs, const std::string& lightmapUri,
                          const std::filesystem::path& file, LightmapUse use, const std::vector<PunctualLight>& lights = {});
/// The AO light map's glTF: TEXCOORD_1 from `layout`, the occlusionTexture.
void writeLightmappedGltf(const AoOccluders& occluders, const AoTexelLayout& layout, const std::string& lightmapUri,
                          const std::filesystem::path& file);
/// An atlas of linear [0, 1] colours (row-major, row 0 at the top) as an 8-bit sRGB PNG.
void writeAtlasPng(int width, int height, const std::vector<glm::vec3>& pixels, const std::filesystem::path& file);
/// The atlas as an 8-bit sRGB PNG: RGB colours per texel (gutter black), row 0 at the top.
void writeLightmapPng(const AoTexelLayout& layout, const std::vector<glm::vec3>& texelColours, const std::filesystem::path& file);

/// Linear [0, 1] -> sRGB byte.
unsigned char srgbByte(float linear);

} // namespace sightline::cli
