// glTF 2.0 importer (.gltf/.glb) on top of tinygltf.
//
// tinygltf parses the container and JSON; everything that touches bytes is done here with our own
// bounds checks (accessor -> bufferView -> buffer, strides, sparse substitution), because a scene
// file is untrusted input and tinygltf does not check accessor ranges. Policy decisions:
//  - no required extension is honoured: any `extensionsRequired` entry refuses the file;
//  - textures are never decoded (a no-op image loader), and a missing image is only a warning;
//  - external files are read only from inside the glTF file's folder (FsCallbacks guard), and every
//    file through readInputFile (a regular file within the size limit);
//  - the JSON is depth-checked and its indices and node forest validated (GltfValidation.h) before
//    tinygltf sees it, since tinygltf silently drops what it cannot convert;
//  - what the nodes expand to is counted before expanding it (SceneLimits.h), and the hierarchy is
//    walked with an explicit stack, so neither a wide nor a deep file exhausts memory or the stack.
// Each glTF mesh becomes one sightline::Mesh (its triangle primitives merged); each node that
// references it becomes an Instance, so instancing survives the import. A mesh with a material on
// some primitive keeps each triangle's base colour as its albedo: the material's factor, times the
// mean of its base colour texture over the triangle where it has one (TextureMean.h); a primitive
// without a material takes glTF's default, white; KHR_texture_transform moves its coordinates. Where
// a texture cannot be read (its image missing or broken, no texture coordinates) its triangles'
// albedo is unknown, with a warning.

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <limits>
#include <sstream>
#include <string_view>

#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>
#include <tiny_gltf.h>

#include "BuiltinFormats.h"
#include "GltfTextures.h"
#include "GltfValidation.h"
#include "TextureMean.h"
#include "plugins/GltfLights.h"
#include "plugins/MeshTopology.h"
#include "plugins/JsonText.h"
#include "base/Error.h"
#include "base/PathRule.h"
#include "base/InputFile.h"
#include "visibility/Scene.h"
#include "visibility/SceneLimits.h"

namespace sightline {

namespace {

namespace fs = std::filesystem;

/// tinygltf errors are newline-separated stacks; a user gets the first non-blank line.
std::string firstLine(const std::string& text)
{
    std::size_t begin = 0;
    while (begin < text.size()) {
        std::size_t end = text.find_first_of("\r\n", begin);
        if (end == std::string::npos)
            end = text.size();
        std::string line = text.substr(begin, end - begin);
        if (line.find_first_not_of(" \t") != std::string::npos)
            return line;
        begin = end + 1;
    }
    return "unknown error";
}

std::uint32_t readU32(std::string_view bytes, std::size_t at)
{
    std::uint32_t v = 0;
    std::memcpy(&v, bytes.data() + at, 4); // GLB is little-endian, as is every platform we build for
    return v;
}

bool isGlb(std::string_view bytes) { return bytes.size() >= 4 && bytes.substr(0, 4) == "glTF"; }

constexpr std::uint32_t kChunkJson = 0x4E4F534Au; // "JSON"

/// The JSON chunk of a GLB container, after checking the whole container (glTF 2.0 §4.4): version 2
/// (tinygltf does not check it, and a glTF 1.0 binary is another format), a total length equal to the
/// file's size, a JSON chunk first, and every chunk inside the file. tinygltf trusts these fields.
std::string_view glbJsonChunk(std::string_view bytes, const std::string& what)
{
    if (bytes.size() < 20)
        throw Error(what + ": truncated GLB header (" + std::to_string(bytes.size()) + " bytes)");
    const std::uint32_t version = readU32(bytes, 4);
    if (version != 2)
        throw Error(what + ": GLB container version " + std::to_string(version) +
                    " is not supported (only glTF 2.0)");
    if (readU32(bytes, 8) != bytes.size())
        throw Error(what + ": GLB header gives a length of " + std::to_string(readU32(bytes, 8)) +
                    " bytes, but the file has " + std::to_string(bytes.size()));
    std::size_t at = 12;
    std::string_view json;
    for (int chunk = 0; at < bytes.size(); ++chunk) {
        if (bytes.size() - at < 8)
            throw Error(what + ": GLB chunk " + std::to_string(chunk) + " header is cut off at byte " +
                        std::to_string(at));
        const std::uint64_t length = readU32(bytes, at);
        if (length > bytes.size() - at - 8)
            throw Error(what + ": GLB chunk " + std::to_string(chunk) + " claims " + std::to_string(length) +
                        " bytes, past the end of the file");
        if (chunk == 0) {
            if (readU32(bytes, at + 4) != kChunkJson)
                throw Error(what + ": the first GLB chunk is not JSON");
            json = bytes.substr(at + 8, length);
        }
        at += 8 + length;
    }
    if (json.empty())
        throw Error(what + ": GLB has no JSON chunk");
    return json;
}

/// Refuses what Sightline will not honour before any bytes are loaded: required extensions, and
/// buffer URIs that are absolute or resolve outside the file's folder.
void preflight(std::string_view json, const fs::path& folder, const std::string& what)
{
    const nlohmann::json doc = parseJsonText(json, what);
    if (!doc.is_object())
        throw Error(what + ": JSON root is not an object");
    gltf::checkIndices(doc, what);
    gltf::checkNodeForest(doc, what);
    if (auto it = doc.find("extensionsRequired"); it != doc.end() && it->is_array() && !it->empty())
        throw Error(what + ": requires glTF extension " + (it->front().is_string() ? it->front().get<std::string>() : "?") +
                    ", which Sightline does not support");
    const auto buffers = doc.find("buffers");
    if (buffers == doc.end() || !buffers->is_array())
        return;
    for (const auto& buffer : *buffers) {
        if (!buffer.is_object() || !buffer.contains("uri") || !buffer["uri"].is_string())
            continue;
        const std::string uri = buffer["uri"].get<std::string>();
        if (uri.rfind("data:", 0) == 0)
            continue;
        const fs::path path(uri);
        if (path.is_absolute() || path.has_root_name() || path.has_root_directory())
            throw Error(what + ": buffer URI '" + uri + "' is an absolute path; only files beside the glTF are read");
        if (!resolvesInside(folder / path, folder))
            throw Error(what + ": buffer URI '" + uri + "' resolves outside the glTF file's folder; refused");
    }
}

/// File access for tinygltf's external buffers and images: only inside `folder`. This also covers
/// what the preflight cannot see (percent-encoded URIs). tinygltf looks for a file first under the
/// base folder we give it (absolute), then under "." - the process's working folder, never wanted.
struct FsGuard {
    fs::path folder;
    std::string refused; ///< first path that was refused, for the error message
    std::string failed;  ///< first readInputFile refusal (a FIFO, a file past the size limit), whole

    static bool exists(const std::string& path, void* self)
    {
        auto* guard = static_cast<FsGuard*>(self);
        const std::string prefix = guard->folder.string() + "/";
        if (path.compare(0, prefix.size(), prefix) != 0)
            return false; // the working-folder fallback
        if (!resolvesInside(path, guard->folder)) {
            if (guard->refused.empty())
                guard->refused = path.substr(prefix.size());
            return false;
        }
        std::error_code ec;
        return fs::is_regular_file(path, ec);
    }
    static std::string expand(const std::string& path, void*) { return path; } // no ~ or $VAR expansion
    static bool read(std::vector<unsigned char>* out, std::string* err, const std::string& path, void* self)
    {
        if (!exists(path, self)) {
            *err = "not readable here";
            return false;
        }
        // tinygltf is C code in spirit: report through its error string, not an exception through it.
        auto* guard = static_cast<FsGuard*>(self);
        try {
            const std::string bytes = readInputFile(path, "glTF buffer or image");
            out->assign(bytes.begin(), bytes.end());
            return true;
        } catch (const std::exception& e) {
            if (guard->failed.empty())
                guard->failed = e.what();
            *err = e.what();
            return false;
        }
    }
    static bool write(std::string* err, const std::string&, const std::vector<unsigned char>&, void*)
    {
        *err = "writing is disabled";
        return false;
    }
};

/// Every image accepted without decoding it: its bytes are kept (in `keep`, a vector of strings
/// by image index, where not null) for the base colour textures decoded later (GltfTextures.h).
/// An image in a bufferView is not read here: tinygltf hands over its bytes without checking that
/// the view lies inside its buffer, so they are fetched later through viewBytes' checks.
bool keepImageBytes(tinygltf::Image* image, const int index, std::string*, std::string*, int, int, const unsigned char* bytes,
                    int size, void* keep)
{
    image->image.clear();
    if (keep && index >= 0 && image->bufferView < 0 && bytes && size > 0) {
        auto& images = *static_cast<std::vector<std::string>*>(keep);
        if (images.size() <= std::size_t(index))
            images.resize(std::size_t(index) + 1);
        images[std::size_t(index)].assign(reinterpret_cast<const char*>(bytes), std::size_t(size));
    }
    return true;
}

/// The file's model; with `images`, its images' encoded bytes by index.
tinygltf::Model parseModel(const fs::path& file, std::vector<std::string>& warnings, std::vector<std::string>* images = nullptr)
{
    const std::string what = file.string();
    const std::string bytes = readInputFile(file, "glTF scene");
    const fs::path folder = fs::weakly_canonical(fs::absolute(file)).parent_path();
    const bool glb = isGlb(bytes);
    if (!glb && file.extension() == ".glb")
        throw Error(what + ": not a GLB file (it does not start with the magic 'glTF')");
    preflight(glb ? glbJsonChunk(bytes, what) : std::string_view(bytes), folder, what);

    FsGuard guard{folder, {}, {}};
    tinygltf::TinyGLTF loader;
    loader.SetFsCallbacks({&FsGuard::exists, &FsGuard::expand, &FsGuard::read, &FsGuard::write, &guard});
    loader.SetImageLoader(&keepImageBytes, images);

    tinygltf::Model model;
    std::string err;
    std::string warn;
    bool ok = false;
    if (bytes.size() > std::numeric_limits<unsigned int>::max())
        throw Error(what + ": file too large for glTF");
    const auto size = static_cast<unsigned int>(bytes.size());
    if (glb)
        ok = loader.LoadBinaryFromMemory(&model, &err, &warn, reinterpret_cast<const unsigned char*>(bytes.data()),
                                         size, folder.string());
    else
        ok = loader.LoadASCIIFromString(&model, &err, &warn, bytes.data(), size, folder.string());
    std::istringstream warnLines(warn); // one entry per tinygltf warning line
    for (std::string line; std::getline(warnLines, line);)
        if (line.find_first_not_of(" \t\r") != std::string::npos)
            warnings.push_back(what + ": " + firstLine(line));
    if (!ok) {
        if (!guard.refused.empty())
            throw Error(what + ": refused to read '" + guard.refused + "': it resolves outside the glTF file's folder");
        if (!guard.failed.empty())
            throw Error(what + ": " + guard.failed);
        throw Error(what + ": " + firstLine(err));
    }
    return model;
}

// ---- accessor reading, every byte bounds-checked ---------------------------------------------------

const tinygltf::BufferView& bufferView(const tinygltf::Model& model, int index, const std::string& what)
{
    if (index < 0 || static_cast<std::size_t>(index) >= model.bufferViews.size())
        throw Error(what + " names missing bufferView " + std::to_string(index));
    return model.bufferViews[static_cast<std::size_t>(index)];
}

/// Pointer to `length` bytes at `offset` inside bufferView `index`, or an Error.
const unsigned char* viewBytes(const tinygltf::Model& model, int index, std::uint64_t offset, std::uint64_t length,
                               const std::string& what)
{
    const tinygltf::BufferView& view = bufferView(model, index, what);
    if (view.buffer < 0 || static_cast<std::size_t>(view.buffer) >= model.buffers.size())
        throw Error(what + ": bufferView " + std::to_string(index) + " names missing buffer " +
                    std::to_string(view.buffer));
    const tinygltf::Buffer& buffer = model.buffers[static_cast<std::size_t>(view.buffer)];
    // Comparisons by subtraction so that hostile offsets cannot wrap around.
    if (view.byteOffset > buffer.data.size() || view.byteLength > buffer.data.size() - view.byteOffset)
        throw Error(what + ": bufferView " + std::to_string(index) + " overruns buffer " + std::to_string(view.buffer) +
                    " (" + std::to_string(buffer.data.size()) + " bytes)");
    if (offset > view.byteLength || length > view.byteLength - offset)
        throw Error(what + " overruns bufferView " + std::to_string(index) + " (" + std::to_string(view.byteLength) +
                    " bytes)");
    return buffer.data.data() + view.byteOffset + offset;
}

std::uint32_t readIndex(const unsigned char* p, int componentType)
{
    switch (componentType) {
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
        return *p;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
        std::uint16_t v;
        std::memcpy(&v, p, 2);
        return v;
    }
    default: {
        std::uint32_t v;
        std::memcpy(&v, p, 4);
        return v;
    }
    }
}

int indexSize(int componentType)
{
    switch (componentType) {
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return 1;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return 2;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: return 4;
    default: return 0;
    }
}

/// glTF 2.0 §3.6.2.4: an accessor's offset within its bufferView, its offset within the buffer and the
/// view's byteStride are multiples of its component size. Data that breaks this is not what its writer
/// meant (a shifted float is a different number), so it is refused, not read.
void checkAlignment(const tinygltf::BufferView& view, int viewIndex, std::uint64_t byteOffset, int componentSize,
                    const std::string& where)
{
    const auto size = static_cast<std::uint64_t>(componentSize);
    const std::string component = "its component size (" + std::to_string(size) + " bytes)";
    if (byteOffset % size != 0)
        throw Error(where + ": byteOffset " + std::to_string(byteOffset) + " is not a multiple of " + component);
    if ((view.byteOffset + byteOffset) % size != 0)
        throw Error(where + ": starts at byte " + std::to_string(view.byteOffset + byteOffset) + " of buffer " +
                    std::to_string(view.buffer) + " (bufferView " + std::to_string(viewIndex) + " byteOffset " +
                    std::to_string(view.byteOffset) + "), not a multiple of " + component);
    if (view.byteStride % size != 0)
        throw Error(where + ": bufferView " + std::to_string(viewIndex) + " byteStride " +
                    std::to_string(view.byteStride) + " is not a multiple of " + component);
}

/// Element bytes of an accessor, tightly packed, strides resolved and sparse values substituted.
std::vector<unsigned char> accessorBytes(const tinygltf::Model& model, int index, std::size_t& elementSize,
                                         const std::string& what)
{
    if (index < 0 || static_cast<std::size_t>(index) >= model.accessors.size())
        throw Error(what + " names missing accessor " + std::to_string(index));
    const tinygltf::Accessor& acc = model.accessors[static_cast<std::size_t>(index)];
    const std::string where = what + " accessor " + std::to_string(index);
    const int componentSize = tinygltf::GetComponentSizeInBytes(static_cast<std::uint32_t>(acc.componentType));
    const int components = tinygltf::GetNumComponentsInType(static_cast<std::uint32_t>(acc.type));
    if (componentSize <= 0 || components <= 0)
        throw Error(where + " has an invalid component type or type");
    elementSize = static_cast<std::size_t>(componentSize) * static_cast<std::size_t>(components);

    // Without a bufferView the base is zeros; cap it so a hostile count cannot exhaust memory.
    constexpr std::uint64_t maxElements = 1u << 28;
    if (acc.bufferView < 0 && acc.count > maxElements)
        throw Error(where + " has an implausible count " + std::to_string(acc.count));

    std::vector<unsigned char> out;
    if (acc.bufferView >= 0 && acc.count > 0) {
        const tinygltf::BufferView& view = bufferView(model, acc.bufferView, where);
        if (acc.count > view.byteLength) // also keeps the span below from overflowing
            throw Error(where + ": " + std::to_string(acc.count) + " elements overrun bufferView " +
                        std::to_string(acc.bufferView) + " (" + std::to_string(view.byteLength) + " bytes)");
        const std::size_t byteStride = view.byteStride;
        const std::size_t stride = byteStride ? byteStride : elementSize;
        if (stride < elementSize)
            throw Error(where + ": byteStride " + std::to_string(stride) + " is smaller than an element (" +
                        std::to_string(elementSize) + " bytes)");
        checkAlignment(view, acc.bufferView, acc.byteOffset, componentSize, where);
        const std::uint64_t span = std::uint64_t(stride) * (acc.count - 1) + elementSize;
        const unsigned char* base = viewBytes(model, acc.bufferView, acc.byteOffset, span, where);
        out.resize(acc.count * elementSize);
        for (std::size_t i = 0; i < acc.count; ++i)
            std::memcpy(out.data() + i * elementSize, base + i * stride, elementSize);
    } else {
        out.assign(acc.count * elementSize, 0);
    }

    if (acc.sparse.isSparse) {
        const auto& sp = acc.sparse;
        const int idxSize = indexSize(sp.indices.componentType);
        if (sp.count < 0 || sp.indices.byteOffset < 0 || sp.values.byteOffset < 0 || idxSize == 0)
            throw Error(where + ": invalid sparse description");
        const auto n = static_cast<std::uint64_t>(sp.count);
        checkAlignment(bufferView(model, sp.indices.bufferView, where + " sparse indices"), sp.indices.bufferView,
                       static_cast<std::uint64_t>(sp.indices.byteOffset), idxSize, where + " sparse indices");
        checkAlignment(bufferView(model, sp.values.bufferView, where + " sparse values"), sp.values.bufferView,
                       static_cast<std::uint64_t>(sp.values.byteOffset), componentSize, where + " sparse values");
        const unsigned char* indices = viewBytes(model, sp.indices.bufferView,
                                                 static_cast<std::uint64_t>(sp.indices.byteOffset),
                                                 n * static_cast<std::uint64_t>(idxSize), where + " sparse indices");
        const unsigned char* values = viewBytes(model, sp.values.bufferView,
                                                static_cast<std::uint64_t>(sp.values.byteOffset), n * elementSize,
                                                where + " sparse values");
        for (std::uint64_t i = 0; i < n; ++i) {
            const std::uint32_t target = readIndex(indices + i * static_cast<std::uint64_t>(idxSize),
                                                   sp.indices.componentType);
            if (target >= acc.count)
                throw Error(where + ": sparse index " + std::to_string(target) + " >= count " +
                            std::to_string(acc.count));
            std::memcpy(out.data() + std::size_t(target) * elementSize, values + i * elementSize, elementSize);
        }
    }
    return out;
}

std::vector<glm::vec3> readVec3(const tinygltf::Model& model, int index, const std::string& what)
{
    const tinygltf::Accessor& acc = model.accessors.at(static_cast<std::size_t>(index)); // checked by caller
    if (acc.type != TINYGLTF_TYPE_VEC3 || acc.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT)
        throw Error(what + " accessor " + std::to_string(index) + " must be VEC3 float");
    std::size_t elementSize = 0;
    const std::vector<unsigned char> bytes = accessorBytes(model, index, elementSize, what);
    std::vector<glm::vec3> out(acc.count);
    if (!bytes.empty())   // no copy from an empty accessor's null data
        std::memcpy(out.data(), bytes.data(), bytes.size());
    return out;
}

/// The bytes of image `index` where it lies in a bufferView (empty where it does not), checked to lie
/// inside the view's buffer.
std::string imageInBufferView(const tinygltf::Model& model, int index, const std::string& file)
{
    const tinygltf::Image& image = model.images.at(std::size_t(index));
    if (image.bufferView < 0)
        return {};
    const std::string what = file + ": image " + std::to_string(index);
    const std::uint64_t length = bufferView(model, image.bufferView, what).byteLength;
    const unsigned char* bytes = viewBytes(model, image.bufferView, 0, length, what);
    return std::string(reinterpret_cast<const char*>(bytes), length);
}

/// Texture coordinates: VEC2 of floats, or of normalised unsigned bytes or shorts (glTF 2.0
/// §3.7.2.1), every one finite.
std::vector<glm::dvec2> readTexCoords(const tinygltf::Model& model, int index, const std::string& what)
{
    if (index < 0 || static_cast<std::size_t>(index) >= model.accessors.size())
        throw Error(what + " names missing accessor " + std::to_string(index));
    const tinygltf::Accessor& acc = model.accessors[static_cast<std::size_t>(index)];
    const int type = acc.componentType;
    const bool normalised = acc.normalized && (type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE || type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT);
    if (acc.type != TINYGLTF_TYPE_VEC2 || !(type == TINYGLTF_COMPONENT_TYPE_FLOAT || normalised))
        throw Error(what + " accessor " + std::to_string(index) + " must be VEC2 float or normalised unsigned byte or short");
    std::size_t elementSize = 0;
    const std::vector<unsigned char> bytes = accessorBytes(model, index, elementSize, what);
    std::vector<glm::dvec2> out(acc.count);
    for (std::size_t i = 0; i < out.size(); ++i)
        for (int c = 0; c < 2; ++c) {
            const unsigned char* p = bytes.data() + i * elementSize + std::size_t(c) * (elementSize / 2);
            double value = 0.0;
            if (type == TINYGLTF_COMPONENT_TYPE_FLOAT) {
                float f = 0.0f;
                std::memcpy(&f, p, sizeof f);
                value = f;
            } else if (type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE) {
                value = *p / 255.0;
            } else {
                std::uint16_t u = 0;
                std::memcpy(&u, p, sizeof u);
                value = u / 65535.0;
            }
            if (!std::isfinite(value))
                throw Error(what + " accessor " + std::to_string(index) + ": texture coordinate " + std::to_string(i) + " is not finite");
            out[i][c] = value;
        }
    return out;
}

/// Vertex indices of a primitive: its index accessor, or 0..vertexCount-1 when it has none.
std::vector<std::uint32_t> readIndices(const tinygltf::Model& model, const tinygltf::Primitive& prim,
                                       std::size_t vertexCount, const std::string& what)
{
    std::vector<std::uint32_t> out;
    if (prim.indices < 0) {
        out.resize(vertexCount);
        for (std::size_t i = 0; i < vertexCount; ++i)
            out[i] = static_cast<std::uint32_t>(i);
        return out;
    }
    std::size_t elementSize = 0;
    const std::vector<unsigned char> bytes = accessorBytes(model, prim.indices, elementSize, what + " indices");
    const tinygltf::Accessor& acc = model.accessors[static_cast<std::size_t>(prim.indices)];
    if (acc.type != TINYGLTF_TYPE_SCALAR || indexSize(acc.componentType) == 0)
        throw Error(what + " indices must be unsigned byte, short or int scalars");
    out.resize(acc.count);
    for (std::size_t i = 0; i < acc.count; ++i) {
        out[i] = readIndex(bytes.data() + i * elementSize, acc.componentType);
        if (out[i] >= vertexCount)
            throw Error(what + ": index " + std::to_string(out[i]) + " is out of range (" +
                        std::to_string(vertexCount) + " vertices)");
    }
    return out;
}

/// Triangle list from TRIANGLES, TRIANGLE_STRIP or TRIANGLE_FAN (vertex order as in the glTF spec §3.7.2.1).
std::vector<std::uint32_t> triangulate(const std::vector<std::uint32_t>& v, int mode)
{
    std::vector<std::uint32_t> tris;
    const std::size_t n = v.size();
    if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
        for (std::size_t i = 0; i + 2 < n; ++i) {
            const bool odd = i % 2 == 1;
            tris.insert(tris.end(), {v[i], v[i + (odd ? 2 : 1)], v[i + (odd ? 1 : 2)]});
        }
    } else if (mode == TINYGLTF_MODE_TRIANGLE_FAN) {
        for (std::size_t i = 0; i + 2 < n; ++i)
            tris.insert(tris.end(), {v[i + 1], v[i + 2], v[0]});
    } else {
        tris.assign(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(n - n % 3));
    }
    return tris;
}

bool isTriangleMode(int mode)
{
    // tinygltf uses -1 for an absent mode; the glTF default is TRIANGLES.
    return mode == -1 || mode == TINYGLTF_MODE_TRIANGLES || mode == TINYGLTF_MODE_TRIANGLE_STRIP ||
           mode == TINYGLTF_MODE_TRIANGLE_FAN;
}

/// The base colour factor of a primitive's material (linear RGB; alpha ignored), white for a
/// primitive without a material (glTF's default material).
glm::vec3 baseColourFactor(const tinygltf::Model& model, const tinygltf::Primitive& prim, const std::string& what)
{
    if (prim.material < 0)
        return glm::vec3(1.0f);
    // The index was checked before tinygltf read the file (GltfValidation.h).
    const tinygltf::PbrMetallicRoughness& pbr = model.materials.at(std::size_t(prim.material)).pbrMetallicRoughness;
    const std::vector<double>& factor = pbr.baseColorFactor;
    if (factor.size() != 4 || !std::all_of(factor.begin(), factor.end(), [](double f) { return f >= 0.0 && f <= 1.0; }))
        throw Error(what + ": material " + std::to_string(prim.material) + "'s baseColorFactor must be four numbers in [0, 1]");
    return glm::vec3(float(factor[0]), float(factor[1]), float(factor[2]));
}

/// KHR_texture_transform's matrix, translation x rotation x scale, applied to (u, v, 1); its
/// texCoord, where it names one, replaces `texCoord`. Throws sightline::Error (the extension's
/// message) where a value is not a finite number of the right shape.
glm::dmat3 textureTransform(const tinygltf::Value& ext, int& texCoord)
{
    const auto number = [&](const tinygltf::Value& v, const char* key) {
        if (!v.IsNumber() || !std::isfinite(v.GetNumberAsDouble()))
            throw Error(std::string("KHR_texture_transform's ") + key + " must be finite numbers");
        return v.GetNumberAsDouble();
    };
    const auto pair = [&](const char* key, glm::dvec2 fallback) {
        if (!ext.Has(key))
            return fallback;
        const tinygltf::Value& v = ext.Get(key);
        if (!v.IsArray() || v.ArrayLen() != 2)
            throw Error(std::string("KHR_texture_transform's ") + key + " must be two numbers");
        return glm::dvec2(number(v.Get(0), key), number(v.Get(1), key));
    };
    const glm::dvec2 offset = pair("offset", glm::dvec2(0.0)), scale = pair("scale", glm::dvec2(1.0));
    const double rotation = ext.Has("rotation") ? number(ext.Get("rotation"), "rotation") : 0.0;
    if (ext.Has("texCoord")) {
        const tinygltf::Value& t = ext.Get("texCoord");
        if (!t.IsInt() || t.GetNumberAsInt() < 0)
            throw Error("KHR_texture_transform's texCoord must be a non-negative integer");
        texCoord = t.GetNumberAsInt();
    }
    // Columns: u' = ox + cos sx u + sin sy v, v' = oy - sin sx u + cos sy v.
    const double c = std::cos(rotation), s = std::sin(rotation);
    return glm::dmat3(glm::dvec3(c * scale.x, -s * scale.x, 0.0), glm::dvec3(s * scale.y, c * scale.y, 0.0), glm::dvec3(offset, 1.0));
}

/// Each triangle's albedo from a textured material: the factor times the texture's mean over the
/// triangle (TextureMean.h), or kUnknownAlbedo for all where the texture cannot be read (with a
/// warning). `tris` indexes the primitive's own vertices.
std::vector<glm::vec3> texturedAlbedos(const tinygltf::Model& model, const tinygltf::Primitive& prim, const std::vector<std::uint32_t>& tris,
                                       std::size_t vertexCount, const glm::vec3& factor, gltf::TextureImages& images,
                                       const std::string& what, std::vector<std::string>& warnings)
{
    const std::size_t triangles = tris.size() / 3;
    const tinygltf::TextureInfo& info = model.materials.at(std::size_t(prim.material)).pbrMetallicRoughness.baseColorTexture;
    const std::string material = "material " + std::to_string(prim.material) + "'s base colour texture";
    if (std::size_t(info.index) >= model.textures.size())
        throw Error(what + ": " + material + " names missing texture " + std::to_string(info.index));
    const std::vector<glm::vec3> unknown(triangles, kUnknownAlbedo);
    const auto unread = [&](const std::string& why) {
        if (images.firstWarningFor(prim.material))
            warnings.push_back(what + ": " + material + " not read (" + why + "); its albedo is unknown");
        return unknown;
    };
    int texCoord = info.texCoord;
    glm::dmat3 transform(1.0);
    if (const auto ext = info.extensions.find("KHR_texture_transform"); ext != info.extensions.end()) {
        try {
            transform = textureTransform(ext->second, texCoord);
        } catch (const Error& e) {
            return unread(e.what());
        }
    }
    const tinygltf::Texture& texture = model.textures[std::size_t(info.index)];
    const std::vector<RgbImage>* image = images.linear(texture.source, warnings);
    if (!image)
        return unread(texture.source < 0 ? "the texture has no image in glTF's own formats" : "image " + std::to_string(texture.source) + " unreadable");
    texture::Wrap wrap;
    if (texture.sampler >= 0 && std::size_t(texture.sampler) < model.samplers.size())
        wrap = {model.samplers[std::size_t(texture.sampler)].wrapS, model.samplers[std::size_t(texture.sampler)].wrapT};
    const std::string attribute = "TEXCOORD_" + std::to_string(texCoord);
    const auto uv = prim.attributes.find(attribute);
    if (uv == prim.attributes.end())
        return unread("no " + attribute);
    std::vector<glm::dvec2> coords;
    try {
        coords = readTexCoords(model, uv->second, what + " " + attribute);
    } catch (const Error& e) {
        return unread(e.what());
    }
    if (coords.size() != vertexCount)
        return unread(attribute + " holds " + std::to_string(coords.size()) + " coordinates for " + std::to_string(vertexCount) + " vertices");
    for (glm::dvec2& coord : coords) {
        coord = glm::dvec2(transform * glm::dvec3(coord, 1.0));
        if (!std::isfinite(coord.x) || !std::isfinite(coord.y))
            return unread("KHR_texture_transform takes a coordinate beyond a double's range");
    }
    std::vector<glm::vec3> albedo(triangles);
    for (std::size_t t = 0; t < triangles; ++t)
        albedo[t] = factor * texture::meanOverTriangle(*image, coords[tris[3 * t]], coords[tris[3 * t + 1]], coords[tris[3 * t + 2]], wrap);
    return albedo;
}

/// `images`: null where textures are not read (a textured material's albedo is then unknown).
Mesh convertMesh(const tinygltf::Model& model, std::size_t meshIndex, const std::string& file, gltf::TextureImages* images,
                 std::vector<std::string>& warnings)
{
    const tinygltf::Mesh& src = model.meshes[meshIndex];
    Mesh mesh;
    mesh.name = src.name.empty() ? "mesh " + std::to_string(meshIndex) : src.name;
    // Written by our exporter (or by hand, or by another tool): a claim, checked below.
    mesh.watertight = src.extras.IsObject() && src.extras.Has("watertight") &&
                      src.extras.Get("watertight").IsBool() && src.extras.Get("watertight").Get<bool>();
    bool allNormals = true, anyMaterial = false;
    for (std::size_t p = 0; p < src.primitives.size(); ++p) {
        const tinygltf::Primitive& prim = src.primitives[p];
        const std::string what = file + ": mesh " + std::to_string(meshIndex) + " primitive " + std::to_string(p);
        if (!isTriangleMode(prim.mode)) {
            warnings.push_back(what + ": mode " + std::to_string(prim.mode) + " (points/lines) ignored");
            continue;
        }
        const auto pos = prim.attributes.find("POSITION");
        if (pos == prim.attributes.end()) {
            warnings.push_back(what + ": no POSITION attribute, ignored");
            continue;
        }
        if (pos->second < 0 || static_cast<std::size_t>(pos->second) >= model.accessors.size())
            throw Error(what + " POSITION names missing accessor " + std::to_string(pos->second));
        const std::vector<glm::vec3> positions = readVec3(model, pos->second, what + " POSITION");
        const std::vector<std::uint32_t> tris =
            triangulate(readIndices(model, prim, positions.size(), what), prim.mode);

        std::vector<glm::vec3> normals;
        const auto nrm = prim.attributes.find("NORMAL");
        if (nrm != prim.attributes.end() && nrm->second >= 0 &&
            static_cast<std::size_t>(nrm->second) < model.accessors.size()) {
            try {
                normals = readVec3(model, nrm->second, what + " NORMAL");
            } catch (const Error& e) {
                warnings.push_back(std::string(e.what()) + "; normals ignored"); // display-only data
            }
        }
        allNormals = allNormals && normals.size() == positions.size();

        const auto offset = static_cast<std::uint32_t>(mesh.positions.size());
        mesh.positions.insert(mesh.positions.end(), positions.begin(), positions.end());
        if (allNormals)
            mesh.normals.insert(mesh.normals.end(), normals.begin(), normals.end());
        for (std::uint32_t i : tris)
            mesh.indices.push_back(offset + i);
        anyMaterial = anyMaterial || prim.material >= 0;
        const glm::vec3 factor = baseColourFactor(model, prim, what);
        if (prim.material >= 0 && model.materials[std::size_t(prim.material)].pbrMetallicRoughness.baseColorTexture.index >= 0) {
            const std::vector<glm::vec3> albedo = images ? texturedAlbedos(model, prim, tris, positions.size(), factor, *images, what, warnings)
                                                         : std::vector<glm::vec3>(tris.size() / 3, kUnknownAlbedo);
            mesh.albedo.insert(mesh.albedo.end(), albedo.begin(), albedo.end());
        } else {
            mesh.albedo.insert(mesh.albedo.end(), tris.size() / 3, factor);
        }
    }
    if (!allNormals)
        mesh.normals.clear();
    if (!anyMaterial)
        mesh.albedo.clear();   // the run's own albedo (lighting/Indirect.h), not glTF's white
    // Culling trusts the flag (§7): on an open or inward mesh it would drop real blockers.
    if (mesh.watertight && !meshTopology(mesh).closedAndOutward()) {
        mesh.watertight = false;
        warnings.push_back(file + ": mesh " + std::to_string(meshIndex) + " ('" + mesh.name +
                           "') is flagged watertight in its extras but is not closed and outward-facing; "
                           "loaded without the flag");
    }
    return mesh;
}

glm::mat4 localTransform(const tinygltf::Node& node, const std::string& what)
{
    if (!node.matrix.empty()) {
        if (node.matrix.size() != 16)
            throw Error(what + ": matrix must have 16 numbers");
        glm::dmat4 m;
        std::memcpy(glm::value_ptr(m), node.matrix.data(), sizeof(m)); // both column-major
        // glTF 2.0 §5.25: a node's matrix must be decomposable to TRS. A projective last row was
        // dropped without a word (positions are transformed as points, w ignored): another shape.
        if (m[0][3] != 0.0 || m[1][3] != 0.0 || m[2][3] != 0.0 || m[3][3] != 1.0)
            throw Error(what + ": matrix must be affine (elements 3, 7, 11, 15 equal to 0, 0, 0, 1; glTF requires a TRS matrix)");
        return glm::mat4(m);
    }
    glm::dvec3 t(0.0), s(1.0);
    glm::dquat r(1.0, 0.0, 0.0, 0.0);
    if (!node.translation.empty()) {
        if (node.translation.size() != 3)
            throw Error(what + ": translation must have 3 numbers");
        t = glm::make_vec3(node.translation.data());
    }
    if (!node.rotation.empty()) {
        if (node.rotation.size() != 4)
            throw Error(what + ": rotation must have 4 numbers");
        const auto& q = node.rotation; // glTF stores x, y, z, w
        r = glm::dquat(q[3], q[0], q[1], q[2]);
    }
    if (!node.scale.empty()) {
        if (node.scale.size() != 3)
            throw Error(what + ": scale must have 3 numbers");
        s = glm::make_vec3(node.scale.data());
    }
    const glm::dmat4 trs = glm::translate(glm::dmat4(1.0), t) * glm::mat4_cast(r) * glm::scale(glm::dmat4(1.0), s);
    return glm::mat4(trs);
}

/// Walks the node hierarchy from the roots in depth-first pre-order (a node before its children,
/// children in their order), calling visit(node index, node, world transform) once a node. An
/// explicit stack instead of recursion: a legal chain of nodes is as deep as the file is long. The
/// preflight refused anything but disjoint trees with distinct roots, so a node reached twice (or
/// missing) means that check was bypassed: refused rather than looped over.
template <typename Visit>
void walkNodes(const tinygltf::Model& model, const std::vector<int>& roots, const std::string& file, Visit&& visit)
{
    struct Pending {
        int node;
        glm::dmat4 parent;
    };
    std::vector<bool> reached(model.nodes.size(), false);
    std::vector<Pending> stack;
    for (auto root = roots.rbegin(); root != roots.rend(); ++root)
        stack.push_back({*root, glm::dmat4(1.0)});
    while (!stack.empty()) {
        const Pending next = stack.back();
        stack.pop_back();
        if (next.node < 0 || static_cast<std::size_t>(next.node) >= model.nodes.size())
            throw Error(file + ": reference to missing node " + std::to_string(next.node));
        const auto n = static_cast<std::size_t>(next.node);
        if (reached[n])
            throw Error(file + ": node " + std::to_string(next.node) + " is reached twice; glTF nodes must form strict trees");
        reached[n] = true;
        const tinygltf::Node& node = model.nodes[n];
        const glm::dmat4 world = next.parent * glm::dmat4(localTransform(node, file + ": node " + std::to_string(next.node)));
        visit(next.node, node, world);
        for (auto child = node.children.rbegin(); child != node.children.rend(); ++child)
            stack.push_back({*child, world});
    }
}

/// Emits one Instance per mesh reference, in walkNodes' order, placed by the accumulated transforms.
class SceneBuilder {
public:
    /// `images`: null where textures are not read (textured materials' albedos unknown).
    SceneBuilder(const tinygltf::Model& model, gltf::TextureImages* images, std::string file, std::vector<std::string>& warnings)
        : model_(model), images_(images), file_(std::move(file)), warnings_(warnings), meshSlot_(model.meshes.size(), -1)
    {
    }

    void build(const std::vector<int>& roots)
    {
        walkNodes(model_, roots, file_, [&](int nodeIndex, const tinygltf::Node& node, const glm::dmat4& world) {
            if (node.mesh < 0)
                return;
            if (static_cast<std::size_t>(node.mesh) >= model_.meshes.size())
                throw Error(file_ + ": node " + std::to_string(nodeIndex) + " names missing mesh " + std::to_string(node.mesh));
            const std::string name = node.name.empty() ? "node " + std::to_string(nodeIndex) : node.name;
            scene_.instances.push_back(Instance{name, meshSlot(static_cast<std::size_t>(node.mesh)), glm::mat4(world)});
        });
    }

    Scene take() { return std::move(scene_); }

private:
    /// Converts each referenced glTF mesh once; later references reuse it (instancing).
    std::uint32_t meshSlot(std::size_t gltfMesh)
    {
        if (meshSlot_[gltfMesh] < 0)
            meshSlot_[gltfMesh] = scene_.addMesh(convertMesh(model_, gltfMesh, file_, images_, warnings_));
        return static_cast<std::uint32_t>(meshSlot_[gltfMesh]);
    }

    const tinygltf::Model& model_;
    gltf::TextureImages* images_;
    std::string file_;
    std::vector<std::string>& warnings_;
    std::vector<std::int64_t> meshSlot_;
    Scene scene_;
};

// ---- what a file expands to, counted before expanding it -------------------------------------------

/// Sums that stick at the maximum instead of wrapping, so a count past every limit stays past it.
std::uint64_t addSaturated(std::uint64_t a, std::uint64_t b)
{
    return a > std::numeric_limits<std::uint64_t>::max() - b ? std::numeric_limits<std::uint64_t>::max() : a + b;
}

std::uint64_t accessorCount(const tinygltf::Model& model, int index)
{
    return index >= 0 && static_cast<std::size_t>(index) < model.accessors.size()
               ? model.accessors[static_cast<std::size_t>(index)].count
               : 0; // a bad reference is refused when the mesh is converted
}

/// The triangles convertMesh will produce, from accessor counts alone (no bytes are read).
std::uint64_t meshTriangles(const tinygltf::Model& model, const tinygltf::Mesh& mesh)
{
    std::uint64_t triangles = 0;
    for (const tinygltf::Primitive& prim : mesh.primitives) {
        const auto pos = prim.attributes.find("POSITION");
        if (!isTriangleMode(prim.mode) || pos == prim.attributes.end())
            continue;
        const std::uint64_t n = prim.indices >= 0 ? accessorCount(model, prim.indices) : accessorCount(model, pos->second);
        const bool stripOrFan = prim.mode == TINYGLTF_MODE_TRIANGLE_STRIP || prim.mode == TINYGLTF_MODE_TRIANGLE_FAN;
        triangles = addSaturated(triangles, stripOrFan ? (n >= 3 ? n - 2 : 0) : n / 3);
    }
    return triangles;
}

struct Expansion {
    std::uint64_t instances = 0;
    std::uint64_t triangles = 0;
};

/// What the roots expand to: mesh instances and their triangles, counted on the node graph. Each
/// node's subtree total is computed once (post-order, explicit stack) and reused by every reference to
/// it, so the count stays linear in the file even where the expansion would be exponential.
Expansion countExpansion(const tinygltf::Model& model, const std::vector<int>& roots, const std::string& what)
{
    std::vector<std::uint64_t> triangles(model.meshes.size());
    for (std::size_t m = 0; m < model.meshes.size(); ++m)
        triangles[m] = meshTriangles(model, model.meshes[m]);

    enum : unsigned char { kUnseen, kOpen, kDone };
    std::vector<unsigned char> state(model.nodes.size(), kUnseen);
    std::vector<Expansion> subtree(model.nodes.size());
    const auto valid = [&](int n) { return n >= 0 && static_cast<std::size_t>(n) < model.nodes.size(); };
    std::vector<std::pair<std::size_t, std::size_t>> stack; // node, next child to descend into
    for (int root : roots) {
        if (!valid(root) || state[static_cast<std::size_t>(root)] == kDone)
            continue;
        stack.push_back({static_cast<std::size_t>(root), 0});
        state[static_cast<std::size_t>(root)] = kOpen;
        while (!stack.empty()) {
            auto& [n, next] = stack.back();
            const tinygltf::Node& node = model.nodes[n];
            if (next < node.children.size()) {
                const int child = node.children[next++];
                if (!valid(child) || state[static_cast<std::size_t>(child)] == kDone)
                    continue;
                if (state[static_cast<std::size_t>(child)] == kOpen)
                    throw Error(what + ": node " + std::to_string(child) + " is its own ancestor (a cycle in the node hierarchy)");
                state[static_cast<std::size_t>(child)] = kOpen;
                stack.push_back({static_cast<std::size_t>(child), 0});
                continue;
            }
            Expansion total;
            if (node.mesh >= 0 && static_cast<std::size_t>(node.mesh) < model.meshes.size())
                total = {1, triangles[static_cast<std::size_t>(node.mesh)]};
            for (int child : node.children)
                if (valid(child)) {
                    total.instances = addSaturated(total.instances, subtree[static_cast<std::size_t>(child)].instances);
                    total.triangles = addSaturated(total.triangles, subtree[static_cast<std::size_t>(child)].triangles);
                }
            subtree[n] = total;
            state[n] = kDone;
            stack.pop_back();
        }
    }
    Expansion scene;
    for (int root : roots)
        if (valid(root)) {
            scene.instances = addSaturated(scene.instances, subtree[static_cast<std::size_t>(root)].instances);
            scene.triangles = addSaturated(scene.triangles, subtree[static_cast<std::size_t>(root)].triangles);
        }
    return scene;
}

std::string countText(std::uint64_t n)
{
    return n == std::numeric_limits<std::uint64_t>::max() ? "more than 18 quintillion" : std::to_string(n);
}

/// The vertices converting every mesh once would copy: each primitive copies its whole POSITION
/// accessor, however few triangles index it (primitives may share one accessor).
std::uint64_t meshVertices(const tinygltf::Model& model)
{
    std::uint64_t vertices = 0;
    for (const tinygltf::Mesh& mesh : model.meshes)
        for (const tinygltf::Primitive& prim : mesh.primitives)
            if (const auto pos = prim.attributes.find("POSITION"); isTriangleMode(prim.mode) && pos != prim.attributes.end())
                vertices = addSaturated(vertices, accessorCount(model, pos->second));
    return vertices;
}

/// Refuses a file whose nodes would place more than SceneLimits.h allows, before anything is expanded.
void checkExpansion(const tinygltf::Model& model, const std::vector<int>& roots, const std::string& what)
{
    if (const std::uint64_t vertices = meshVertices(model); vertices > kMaxSceneVertices)
        throw Error(what + ": its meshes hold " + countText(vertices) + " vertices in all, more than the limit of " +
                    std::to_string(kMaxSceneVertices));
    const Expansion e = countExpansion(model, roots, what);
    if (e.instances > kMaxSceneInstances)
        throw Error(what + ": the node hierarchy places " + countText(e.instances) +
                    " mesh instances, more than the limit of " + std::to_string(kMaxSceneInstances));
    if (e.triangles > kMaxSceneTriangles)
        throw Error(what + ": the node hierarchy places " + countText(e.triangles) +
                    " triangles in all, more than the limit of " + std::to_string(kMaxSceneTriangles));
}

/// Root nodes of the default scene, else scene 0, else every node that is nobody's child.
std::vector<int> rootNodes(const tinygltf::Model& model)
{
    if (!model.scenes.empty()) {
        const bool hasDefault = model.defaultScene >= 0 && static_cast<std::size_t>(model.defaultScene) < model.scenes.size();
        return model.scenes[hasDefault ? static_cast<std::size_t>(model.defaultScene) : 0].nodes;
    }
    std::vector<bool> isChild(model.nodes.size(), false);
    for (const tinygltf::Node& node : model.nodes)
        for (int child : node.children)
            if (child >= 0 && static_cast<std::size_t>(child) < isChild.size())
                isChild[static_cast<std::size_t>(child)] = true;
    std::vector<int> roots;
    for (std::size_t i = 0; i < model.nodes.size(); ++i)
        if (!isChild[i])
            roots.push_back(static_cast<int>(i));
    return roots;
}

class GltfImporter final : public SceneImporter {
public:
    std::string name() const override { return "glTF 2.0"; }
    std::vector<std::string> extensions() const override { return {".gltf", ".glb"}; }

    Scene load(const fs::path& file, std::vector<std::string>& warnings, const SceneLoadOptions& options) const override
    {
        try {
            gltf::TextureImages images(file.string());
            const tinygltf::Model model = parseModel(file, warnings, options.textureAlbedos ? &images.encoded : nullptr);
            images.encoded.resize(model.images.size());
            images.fromView = [&](int index) { return imageInBufferView(model, index, file.string()); };
            const std::vector<int> roots = rootNodes(model);
            checkExpansion(model, roots, file.string());
            SceneBuilder builder(model, options.textureAlbedos ? &images : nullptr, file.string(), warnings);
            builder.build(roots);
            Scene scene = builder.take();
            validate(scene, file.string());
            return scene;
        } catch (const Error&) {
            throw;
        } catch (const std::exception& e) { // e.g. bad_alloc on a hostile file: still one clean line
            throw Error(file.string() + ": " + firstLine(e.what()));
        }
    }
};

} // namespace

std::unique_ptr<SceneImporter> makeGltfImporter() { return std::make_unique<GltfImporter>(); }

std::vector<PunctualLight> loadGltfLights(const fs::path& file, std::vector<std::string>* warnings)
{
    std::string extension = file.extension().string();
    std::transform(extension.begin(), extension.end(), extension.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    if (extension != ".gltf" && extension != ".glb")
        return {};
    std::vector<std::string> ignored;
    std::vector<PunctualLight> lights;
    try {
        const tinygltf::Model model = parseModel(file, warnings ? *warnings : ignored);
        const std::vector<int> roots = rootNodes(model);
        checkExpansion(model, roots, file.string());
        walkNodes(model, roots, file.string(), [&](int nodeIndex, const tinygltf::Node& node, const glm::dmat4& world) {
            const auto ext = node.extensions.find("KHR_lights_punctual");
            if (ext == node.extensions.end())
                return;
            const std::string what = file.string() + ": node " + std::to_string(nodeIndex);
            const tinygltf::Value& light = ext->second.Get("light");
            if (!light.IsInt() || light.GetNumberAsInt() < 0 || std::size_t(light.GetNumberAsInt()) >= model.lights.size())
                throw Error(what + ": KHR_lights_punctual.light must index the file's " + std::to_string(model.lights.size()) +
                            " lights");
            const tinygltf::Light& source = model.lights[std::size_t(light.GetNumberAsInt())];
            PunctualLight out;
            out.type = source.type;
            if (out.type != "point" && out.type != "spot" && out.type != "directional")
                throw Error(what + ": unknown KHR_lights_punctual type '" + source.type + "'");
            out.name = !source.name.empty() ? source.name : node.name;
            if (source.color.size() == 3)
                out.colour = {source.color[0], source.color[1], source.color[2]};
            out.intensity = source.intensity;
            out.range = source.range;
            out.innerAngle = source.spot.innerConeAngle;
            out.outerAngle = source.spot.outerConeAngle;
            out.position = glm::dvec3(world * glm::dvec4(0.0, 0.0, 0.0, 1.0));
            const glm::dvec3 direction(world * glm::dvec4(0.0, 0.0, -1.0, 0.0));
            const double length = glm::length(direction);
            if (!(length > 0.0) || !std::isfinite(length))
                throw Error(what + ": its transform collapses the light's direction");
            out.direction = direction / length;
            lights.push_back(out);
        });
    } catch (const Error&) {
        throw;
    } catch (const std::exception& e) {
        throw Error(file.string() + ": " + firstLine(e.what()));
    }
    return lights;
}

} // namespace sightline
