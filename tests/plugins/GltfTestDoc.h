#pragma once
// Builds small glTF documents for the importer tests: one binary buffer grown view by view, written
// as a .gltf with a data URI, a .gltf beside a .bin, or a .glb.

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "TestFiles.h"

namespace sightline::test {

using nlohmann::json;

inline constexpr int kU8 = 5121, kU16 = 5123, kU32 = 5125, kF32 = 5126;

inline std::string base64(const std::string& in)
{
    static const char* table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    for (std::size_t i = 0; i < in.size(); i += 3) {
        std::uint32_t n = std::uint32_t(static_cast<unsigned char>(in[i])) << 16;
        if (i + 1 < in.size())
            n |= std::uint32_t(static_cast<unsigned char>(in[i + 1])) << 8;
        if (i + 2 < in.size())
            n |= static_cast<unsigned char>(in[i + 2]);
        out += table[(n >> 18) & 63];
        out += table[(n >> 12) & 63];
        out += i + 1 < in.size() ? table[(n >> 6) & 63] : '=';
        out += i + 2 < in.size() ? table[n & 63] : '=';
    }
    return out;
}

template <class T>
std::string bytesOf(const std::vector<T>& v)
{
    return std::string(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
}

/// A minimal glTF document with one binary buffer, built up view by view.
struct GltfDoc {
    json doc = {{"asset", {{"version", "2.0"}}}, {"bufferViews", json::array()}, {"accessors", json::array()}};
    std::string bin;

    int view(const std::string& bytes, int stride = 0)
    {
        while (bin.size() % 4)
            bin += '\0';
        json v = {{"buffer", 0}, {"byteOffset", bin.size()}, {"byteLength", bytes.size()}};
        if (stride)
            v["byteStride"] = stride;
        bin += bytes;
        doc["bufferViews"].push_back(v);
        return static_cast<int>(doc["bufferViews"].size() - 1);
    }
    int accessor(json a)
    {
        doc["accessors"].push_back(std::move(a));
        return static_cast<int>(doc["accessors"].size() - 1);
    }
    int positions(const std::vector<float>& xyz)
    {
        return accessor({{"bufferView", view(bytesOf(xyz))}, {"componentType", kF32}, {"count", xyz.size() / 3},
                         {"type", "VEC3"}});
    }
    template <class T>
    int indices(const std::vector<T>& values, int componentType)
    {
        return accessor({{"bufferView", view(bytesOf(values))}, {"componentType", componentType},
                         {"count", values.size()}, {"type", "SCALAR"}});
    }
    /// One mesh per call; returns its index.
    int mesh(json primitives)
    {
        doc["meshes"].push_back({{"primitives", std::move(primitives)}});
        return static_cast<int>(doc["meshes"].size() - 1);
    }
    /// A single scene whose roots are `nodes`.
    void scene(json nodes, json roots)
    {
        doc["nodes"] = std::move(nodes);
        doc["scenes"] = json::array({{{"nodes", std::move(roots)}}});
        doc["scene"] = 0;
    }

    /// .gltf with the buffer as a data URI.
    std::filesystem::path writeEmbedded(const std::filesystem::path& file)
    {
        doc["buffers"] = json::array({{{"byteLength", bin.size()},
                                       {"uri", "data:application/octet-stream;base64," + base64(bin)}}});
        return writeFile(file, doc.dump());
    }
    /// .gltf with the buffer in a separate file named by `uri` (relative to the .gltf's folder).
    std::filesystem::path writeExternal(const std::filesystem::path& file, const std::string& uri)
    {
        doc["buffers"] = json::array({{{"byteLength", bin.size()}, {"uri", uri}}});
        if (!std::filesystem::path(uri).is_absolute())
            writeFile(file.parent_path() / uri, bin);
        return writeFile(file, doc.dump());
    }
    /// .glb with the buffer in the BIN chunk.
    std::filesystem::path writeGlb(const std::filesystem::path& file, std::uint32_t version = 2)
    {
        doc["buffers"] = json::array({{{"byteLength", bin.size()}}});
        std::string text = doc.dump();
        while (text.size() % 4)
            text += ' ';
        std::string body = bin;
        while (body.size() % 4)
            body += '\0';
        auto u32 = [](std::uint32_t v) { return std::string(reinterpret_cast<const char*>(&v), 4); };
        const auto total = static_cast<std::uint32_t>(12 + 8 + text.size() + 8 + body.size());
        return writeFile(file, "glTF" + u32(version) + u32(total) + u32(static_cast<std::uint32_t>(text.size())) +
                                   "JSON" + text + u32(static_cast<std::uint32_t>(body.size())) +
                                   std::string("BIN\0", 4) + body);
    }
};

/// The unit right triangle as one indexed mesh under one node.
inline GltfDoc triangleDoc()
{
    GltfDoc g;
    const int pos = g.positions({0, 0, 0, 1, 0, 0, 0, 1, 0});
    const int idx = g.indices(std::vector<std::uint16_t>{0, 1, 2}, kU16);
    g.mesh(json::array({{{"attributes", {{"POSITION", pos}}}, {"indices", idx}}}));
    g.scene(json::array({{{"mesh", 0}}}), {0});
    return g;
}

} // namespace sightline::test
