// glTF 2.0 exporter: a Scene to .glb (one binary buffer in the BIN chunk) or .gltf (the same buffer
// embedded as a base64 data URI), so the result is always a single self-contained file.
//
// Instancing is preserved: one glTF mesh per sightline::Mesh, one root node with a `matrix` per
// Instance, one scene. The file is serialised in memory and written with writeFileAtomically.

#include <algorithm>
#include <cctype>
#include <cstring>
#include <sstream>

#include <glm/gtc/type_ptr.hpp>
#include <tiny_gltf.h>

#include "BuiltinFormats.h"
#include "base/AtomicFile.h"
#include "base/Error.h"

namespace sightline {

namespace {

/// Appends raw bytes to the single buffer and returns a bufferView over them.
int addView(tinygltf::Model& model, const void* data, std::size_t bytes, int target)
{
    std::vector<unsigned char>& buffer = model.buffers[0].data;
    tinygltf::BufferView view;
    view.buffer = 0;
    view.byteOffset = buffer.size(); // every element is 4-byte aligned, so no padding is needed
    view.byteLength = bytes;
    view.target = target;
    const auto* p = static_cast<const unsigned char*>(data);
    buffer.insert(buffer.end(), p, p + bytes);
    model.bufferViews.push_back(view);
    return static_cast<int>(model.bufferViews.size() - 1);
}

int addAccessor(tinygltf::Model& model, int view, int componentType, int type, std::size_t count)
{
    tinygltf::Accessor acc;
    acc.bufferView = view;
    acc.byteOffset = 0;
    acc.componentType = componentType;
    acc.type = type;
    acc.count = count;
    model.accessors.push_back(acc);
    return static_cast<int>(model.accessors.size() - 1);
}

int addVec3(tinygltf::Model& model, const std::vector<glm::vec3>& values, bool withBounds)
{
    const int view = addView(model, values.data(), values.size() * sizeof(glm::vec3), TINYGLTF_TARGET_ARRAY_BUFFER);
    const int index = addAccessor(model, view, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, values.size());
    if (withBounds) { // required for POSITION by the spec
        glm::vec3 lo = values.front(), hi = values.front();
        for (const glm::vec3& v : values) {
            lo = glm::min(lo, v);
            hi = glm::max(hi, v);
        }
        model.accessors[static_cast<std::size_t>(index)].minValues = {lo.x, lo.y, lo.z};
        model.accessors[static_cast<std::size_t>(index)].maxValues = {hi.x, hi.y, hi.z};
    }
    return index;
}

/// A mesh without triangles gets no primitive: glTF accessors cannot be empty.
tinygltf::Mesh exportMesh(tinygltf::Model& model, const Mesh& mesh)
{
    tinygltf::Mesh out;
    out.name = mesh.name;
    // Sightline's own flag travels in the mesh's extras (glTF's place for application data).
    if (mesh.watertight)
        out.extras = tinygltf::Value(tinygltf::Value::Object{{"watertight", tinygltf::Value(true)}});
    if (mesh.indices.empty() || mesh.positions.empty())
        return out;
    tinygltf::Primitive prim;
    prim.mode = TINYGLTF_MODE_TRIANGLES;
    prim.attributes["POSITION"] = addVec3(model, mesh.positions, true);
    if (mesh.normals.size() == mesh.positions.size())
        prim.attributes["NORMAL"] = addVec3(model, mesh.normals, false);
    const int view = addView(model, mesh.indices.data(), mesh.indices.size() * sizeof(std::uint32_t),
                             TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
    prim.indices = addAccessor(model, view, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, TINYGLTF_TYPE_SCALAR,
                               mesh.indices.size());
    out.primitives.push_back(prim);
    return out;
}

tinygltf::Model toModel(const Scene& scene)
{
    tinygltf::Model model;
    model.asset.version = "2.0";
    model.asset.generator = "Sightline";
    model.buffers.emplace_back();
    for (const Mesh& mesh : scene.meshes)
        model.meshes.push_back(exportMesh(model, mesh));
    if (model.buffers[0].data.empty())
        model.buffers.clear(); // a zero-length buffer is invalid glTF

    tinygltf::Scene root;
    root.name = "scene"; // tinygltf writes a scene with no nodes and no name as null, which it then refuses
    for (const Instance& instance : scene.instances) {
        tinygltf::Node node;
        node.name = instance.name;
        node.mesh = static_cast<int>(instance.mesh);
        const float* m = glm::value_ptr(instance.transform); // column-major, as glTF wants
        node.matrix.assign(m, m + 16);
        model.nodes.push_back(node);
        root.nodes.push_back(static_cast<int>(model.nodes.size() - 1));
    }
    model.scenes.push_back(root);
    model.defaultScene = 0;
    return model;
}

class GltfExporter final : public SceneExporter {
public:
    std::string name() const override { return "glTF 2.0"; }
    std::vector<std::string> extensions() const override { return {".gltf", ".glb"}; }

    void save(const Scene& scene, const std::filesystem::path& file) const override
    {
        validate(scene, file.string()); // never write a file we could not read back
        std::string ext = file.extension().string();
        std::transform(ext.begin(), ext.end(), ext.begin(),
                       [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
        const bool binary = ext == ".glb";

        const tinygltf::Model model = toModel(scene);
        tinygltf::TinyGLTF writer;
        std::ostringstream stream;
        if (!writer.WriteGltfSceneToStream(&model, stream, /*prettyPrint=*/!binary, binary))
            throw Error(file.string() + ": serialising glTF failed");
        writeFileAtomically(file, stream.str());
    }
};

} // namespace

std::unique_ptr<SceneExporter> makeGltfExporter() { return std::make_unique<GltfExporter>(); }

} // namespace sightline
