#include "visibility/GlBitmaskSampler.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "BitmaskRows.h"
#include "bitmask/Occluders.h"
#include "bitmask/Shaft.h"
#include "bitmask/TilePass.h"
#include "base/Error.h"
#include "visibility/HoughMaskTable.h"
#include "visibility/ShaftGeometry.h"
#include "visibility/gl/GlShaders.h"
#include "glsl/bitmask_common.glsl.h"
#include "glsl/bitmask_exact.frag.h"
#include "glsl/bitmask_regions.vert.h"
#include "glsl/bitmask_table.frag.h"

namespace sightline {

namespace {

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

constexpr int kMaxTargets = kMaxSourceSamples / 128;

/// One occluder as the shaders read it (std430): its vertices in the source frame as float pairs.
struct GpuPolygon {
    std::int32_t info[4];   // vertex count, closed (§7), shared factor (parallel patches), clip per sample
    float hi[8][4];         // s, t, d, and the shared factor d_R / (d_R - d)
    float lo[8][4];         // the residuals of s, t, d
};
static_assert(sizeof(GpuPolygon) == 272, "std430 layout of Polygon");

/// "#version" and the compile-time switches shared by the fragment shaders.
std::string fragmentSource(int targets, MaskMode mode)
{
    std::string declarations, outputs;
    for (int k = 0; k < targets; ++k) {
        const std::string n = std::to_string(k), w = std::to_string(4 * k);
        declarations.append("layout(location = ").append(n).append(") out uvec4 o").append(n).append(";\n");
        // o<k> = uvec4(mask[4k + 0 .. 4k + 3])
        outputs.append("o").append(n).append(" = uvec4(mask[").append(w).append("], mask[").append(w)
            .append(" + 1], mask[").append(w).append(" + 2], mask[").append(w).append(" + 3]);\n    ");
    }
    std::string body = mode == MaskMode::Table ? glsl::bitmask_table_frag : glsl::bitmask_exact_frag;
    body.replace(body.find("OUTPUTS"), 7, outputs);
    return "#version 450 core\n#define TARGETS " + std::to_string(targets) + "\n" + declarations + glsl::bitmask_common_glsl +
           gl::kSampleRangeGlsl + body;
}

/// The Hough table's masks as 32-bit words, `targets` RGBA32UI texels per entry: source bit b in
/// word b / 32, bit b % 32, the render targets' layout (docs/design.md §2: bit index b*na + a).
std::vector<std::uint32_t> packTable(const HoughMaskTable& table, int targets)
{
    const std::size_t wordsPerEntry = std::size_t(targets) * 4;
    std::vector<std::uint32_t> words(std::size_t(table.width()) * std::size_t(table.height()) * wordsPerEntry, 0);
    for (int k = 0; k < table.height(); ++k)
        for (int i = 0; i < table.width(); ++i) {
            const std::uint64_t* mask = table.texel(i, k);
            std::uint32_t* out = &words[(std::size_t(k) * std::size_t(table.width()) + std::size_t(i)) * wordsPerEntry];
            for (int w = 0; w < table.wordsPerMask(); ++w) {
                out[2 * w] = std::uint32_t(mask[w]);
                out[2 * w + 1] = std::uint32_t(mask[w] >> 32);
            }
        }
    return words;
}

/// A float and its rounding residual.
void split(double x, float& hi, float& lo)
{
    hi = float(x);
    lo = float(x - double(hi));
}

/// One sample() call's state between its stages: the shaft and its occluders, which of them the
/// GPU takes (as polygons in split floats, with their regions), the samples' coordinates.
struct GlCall {
    const Patch& source;
    const Patch& receiver;
    const GlBitmaskOptions& options;
    bool tableMode = false;
    bitmask::Shaft shaft;
    std::vector<char> closedInstance;   ///< per instance: watertight
    std::vector<char> onGpu;            ///< per occluder
    std::vector<GpuPolygon> polygons;
    std::vector<std::int32_t> regions;
    std::vector<float> samples;         ///< per receiver sample: source-frame coordinates (hi, lo) and jitter shift
    GlBitmaskStats stats;

    GlCall(const Patch& s, const Patch& r, const GlBitmaskOptions& o)
        : source(s), receiver(r), options(o), tableMode(o.mode == MaskMode::Table), shaft(s, r, o.jitter, nullptr)
    {
        shaft.floatKernel = detail::floatRowsAvailable();   // for the CPU's share
    }

    int targets() const { return (source.sampleCount() + 127) / 128; }
};


} // namespace

struct GlBitmaskSampler::Impl {
    const gl::Functions& gl;
    WorldTriangles triangles;
    struct InstanceInfo {
        bool watertight = false;
        Bounds bounds;
    };
    std::vector<InstanceInfo> instances;   // empty for a bare triangle soup
    GLuint programs[2][kMaxTargets + 1] = {};   // by mask mode and target count, compiled on first use
    GLuint vertexArray = 0;                // attribute-less: the vertex shader reads the regions
    GLuint polygonBuffer = 0, sampleBuffer = 0, flagBuffer = 0, regionBuffer = 0, regionTexture = 0;
    GLuint framebuffer = 0;
    GLuint textures[kMaxTargets] = {};
    int targetCount = 0, width = 0, height = 0;
    /// Table mode: the Hough table of the last source grid and resolution, as a buffer texture
    /// (RGBA32UI texels; a buffer holds the 8-texel entries of an 8192x8192 table where a 2D
    /// texture's side would not). The editor samples one grid many times: built once.
    struct TableKey {
        int na = 0, nb = 0, width = 0, height = 0;
        bool operator==(const TableKey&) const = default;
    };
    TableKey tableKey;
    GLuint tableBuffer = 0, tableTexture = 0;
    /// The CPU's share, kept between calls (bitmask/Occluders.h, TilePass.h).
    bitmask::OccluderSet occluders;
    bitmask::TileBins bins;

    explicit Impl(const gl::Functions& functions) : gl(functions) {}

    // The stages of a call (sample()).
    void prepareOccluders(GlCall& call);
    void takeGpuShare(GlCall& call);
    void bind(GlCall& call, GLuint program);
    void draw(const GlCall& call, GLuint program);
    std::vector<std::uint32_t> readBack(const GlCall& call, HiddenSampleMap& map);
    void cpuShare(GlCall& call, const std::vector<std::uint32_t>& flags, HiddenSampleMap& map);

    ~Impl()
    {
        for (const auto& byTargets : programs)
            for (GLuint program : byTargets)
                if (program)
                    gl.DeleteProgram(program);
        releaseTargets();
        gl.DeleteTextures(1, &tableTexture);
        gl.DeleteBuffers(1, &tableBuffer);
        gl.DeleteTextures(1, &regionTexture);
        for (GLuint* buffer : {&polygonBuffer, &sampleBuffer, &flagBuffer, &regionBuffer})
            gl.DeleteBuffers(1, buffer);
        gl.DeleteVertexArrays(1, &vertexArray);
    }

    GLuint program(int targets, MaskMode mode)
    {
        GLuint& slot = programs[mode == MaskMode::Table ? 1 : 0][targets];
        if (slot)
            return slot;
        return slot = gl::buildProgram(gl, {{GL_VERTEX_SHADER, glsl::bitmask_regions_vert}, {GL_FRAGMENT_SHADER, fragmentSource(targets, mode)}},
                                       "GL bitmask sampler");
    }

    /// Builds (on the CPU, HoughMaskTable) and uploads the table for this grid and resolution
    /// unless it is the one already uploaded. Returns the milliseconds spent (0 when cached).
    double ensureTable(int na, int nb, int tableWidth, int tableHeight)
    {
        const TableKey key{na, nb, tableWidth, tableHeight};
        if (tableTexture && key == tableKey)
            return 0.0;
        const auto start = Clock::now();
        const int targets = (na * nb + 127) / 128;
        GLint maxTexels = 0;
        gl.GetIntegerv(GL_MAX_TEXTURE_BUFFER_SIZE, &maxTexels);
        const double texels = double(tableWidth) * double(tableHeight) * double(targets);
        if (texels > double(maxTexels))
            throw Error("GL bitmask sampler: a " + std::to_string(tableWidth) + "x" + std::to_string(tableHeight) +
                        " Hough table for " + std::to_string(na * nb) + " source samples needs " +
                        std::to_string(std::uint64_t(texels)) + " texels, the context allows " + std::to_string(maxTexels));
        const std::vector<std::uint32_t> words = packTable(HoughMaskTable(na, nb, tableWidth, tableHeight), targets);
        if (!tableBuffer) {
            gl.CreateBuffers(1, &tableBuffer);
            gl.CreateTextures(GL_TEXTURE_BUFFER, 1, &tableTexture);
        }
        tableKey = {};   // until the upload succeeded
        gl.NamedBufferData(tableBuffer, GLsizeiptr(words.size() * sizeof(std::uint32_t)), words.data(), GL_STATIC_DRAW);
        gl.TextureBuffer(tableTexture, GL_RGBA32UI, tableBuffer);
        if (const GLenum error = gl.GetError(); error != GL_NO_ERROR)
            throw Error("GL bitmask sampler: uploading the " + std::to_string(tableWidth) + "x" +
                        std::to_string(tableHeight) + " Hough table failed (OpenGL error " + std::to_string(error) + ")");
        tableKey = key;
        return msSince(start);
    }

    void releaseTargets()
    {
        if (framebuffer)
            gl.DeleteFramebuffers(1, &framebuffer);
        if (targetCount)
            gl.DeleteTextures(targetCount, textures);
        framebuffer = 0;
        targetCount = 0;
    }

    void ensureTargets(int targets, int w, int h)
    {
        if (targets == targetCount && w == width && h == height)
            return;
        releaseTargets();
        gl.CreateFramebuffers(1, &framebuffer);
        gl.CreateTextures(GL_TEXTURE_2D, targets, textures);
        GLenum buffers[kMaxTargets];
        for (int k = 0; k < targets; ++k) {
            gl.TextureStorage2D(textures[k], 1, GL_RGBA32UI, w, h);
            gl.NamedFramebufferTexture(framebuffer, GLenum(GL_COLOR_ATTACHMENT0 + k), textures[k], 0);
            buffers[k] = GLenum(GL_COLOR_ATTACHMENT0 + k);
        }
        gl.NamedFramebufferDrawBuffers(framebuffer, targets, buffers);
        if (gl.CheckNamedFramebufferStatus(framebuffer, GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
            throw Error("GL bitmask sampler: incomplete framebuffer for " + std::to_string(targets) +
                        " RGBA32UI targets of " + std::to_string(w) + "x" + std::to_string(h));
        targetCount = targets;
        width = w;
        height = h;
    }
};

GlBitmaskSampler::GlBitmaskSampler(const gl::Functions& gl, const Scene& scene) : GlBitmaskSampler(gl, worldTriangles(scene))
{
    for (const Instance& instance : scene.instances)
        impl_->instances.push_back({scene.meshes[instance.mesh].watertight, scene.instanceBounds(instance)});
}

GlBitmaskSampler::GlBitmaskSampler(const gl::Functions& gl, const WorldTriangles& triangles)
    : impl_(std::make_unique<Impl>(gl))
{
    validateCoordinates(triangles, "scene");
    GLint drawBuffers = 0;
    gl.GetIntegerv(GL_MAX_DRAW_BUFFERS, &drawBuffers);
    if (drawBuffers < kMaxTargets)
        throw Error("GL bitmask sampler: needs 8 draw buffers, the context has " + std::to_string(drawBuffers));
    impl_->triangles = triangles;
    gl.CreateVertexArrays(1, &impl_->vertexArray);
    for (GLuint* buffer : {&impl_->polygonBuffer, &impl_->sampleBuffer, &impl_->flagBuffer, &impl_->regionBuffer})
        gl.CreateBuffers(1, buffer);
    gl.CreateTextures(GL_TEXTURE_BUFFER, 1, &impl_->regionTexture);
    impl_->program(1, MaskMode::Exact);   // compile now: shader errors surface at construction
}

GlBitmaskSampler::~GlBitmaskSampler() = default;

HiddenSampleMap GlBitmaskSampler::sample(const Patch& source, const Patch& receiver, GlBitmaskStats* stats)
{
    return sample(source, receiver, GlBitmaskOptions{}, stats);
}


/// The occluders, prepared on the CPU in double as the CPU sampler prepares them.
void GlBitmaskSampler::Impl::prepareOccluders(GlCall& call)
{
    using namespace bitmask;
    const ShaftHull hull(call.source, call.receiver);
    TriangleFilter filter;
    filter.triangles = &triangles;
    filter.hull = &hull;
    call.closedInstance.assign(instances.size(), 0);
    filter.instanceOutside.resize(instances.size());
    if (call.options.watertightCulling)
        filter.cullable.resize(instances.size());
    for (std::size_t i = 0; i < instances.size(); ++i) {
        const auto& instance = instances[i];
        filter.instanceOutside[i] = hull.excludesBox(instance.bounds.min, instance.bounds.max);
        call.closedInstance[i] = instance.watertight;
        if (call.options.watertightCulling)
            filter.cullable[i] = instance.watertight && receiverApartFrom(instance.bounds, call.receiver);
    }
    for (int k = 0; k < 4; ++k)
        filter.sourceCorners[std::size_t(k)] = call.source.cornerPoint(k);
    occluders.prepare(call.shaft, filter);
}

/// The GPU's share: every occluder in table mode; in exact mode the well-conditioned ones, factors
/// up to kMaxFloatFactor over their whole region. Also each receiver sample's coordinates.
void GlBitmaskSampler::Impl::takeGpuShare(GlCall& call)
{
    using namespace bitmask;
    const OccluderSet& set = occluders;
    const Shaft& shaft = call.shaft;
    call.onGpu.assign(set.occluders.size(), 0);
    for (std::size_t n = 0; n < set.occluders.size(); ++n) {
        const Occluder& o = *set.occluders[n];
        const double nearest = shaft.nearestSample(o.a0, o.a1, o.b0, o.b1);
        if (!call.tableMode && !(o.maxD <= nearest * (1.0 - 1.0 / detail::kMaxFloatFactor)))
            continue;
        call.onGpu[n] = 1;
        GpuPolygon p{};
        const bool closed = !call.closedInstance.empty() && call.closedInstance[triangles.instanceOf[set.triangleOf[n]]];
        p.info[0] = o.count, p.info[1] = closed, p.info[2] = shaft.parallel && o.path != Path::Clip;
        p.info[3] = o.path == Path::Clip;
        for (int i = 0; i < o.count; ++i) {
            const glm::dvec3& x = o.vertices[std::size_t(i)];
            split(x.x, p.hi[i][0], p.lo[i][0]);
            split(x.y, p.hi[i][1], p.lo[i][1]);
            split(x.z, p.hi[i][2], p.lo[i][2]);
            p.hi[i][3] = shaft.parallel ? float(o.factor[std::size_t(i)]) : 0.0f;
        }
        call.polygons.push_back(p);
        call.regions.insert(call.regions.end(), {o.a0, o.a1, o.b0, o.b1});
    }
    call.stats.gpuOccluders = call.polygons.size();
    call.stats.cpuOccluders = set.occluders.size() - call.polygons.size();
    call.samples.assign(std::size_t(call.receiver.sampleCount()) * 12, 0.0f);
    for (int j = 0; j < call.receiver.sampleCount(); ++j) {
        float* out = &call.samples[std::size_t(j) * 12];
        const glm::dvec3& r = shaft.receiverInSource[std::size_t(j)];
        split(r.x, out[0], out[4]);
        split(r.y, out[1], out[5]);
        split(r.z, out[2], out[6]);
        out[8] = float(shaft.jitterShift[std::size_t(j)].x);
        out[9] = float(shaft.jitterShift[std::size_t(j)].y);
    }
}

/// Uploads the call's buffers, binds them and sets the program's uniforms; clears the targets.
void GlBitmaskSampler::Impl::bind(GlCall& call, GLuint program)
{
    const std::vector<std::uint32_t> noFlags(std::size_t(call.receiver.sampleCount()), 0u);
    if (call.tableMode) {
        call.stats.tableMs = ensureTable(call.source.na, call.source.nb, call.options.tableWidth, call.options.tableHeight);
        gl.BindTextureUnit(1, tableTexture);
        gl.ProgramUniform1i(program, gl.GetUniformLocation(program, "uTable"), 1);
        gl.ProgramUniform2i(program, gl.GetUniformLocation(program, "uTableSize"), call.options.tableWidth, call.options.tableHeight);
    }
    // Never empty: a zero-sized buffer cannot back a binding.
    const auto upload = [&](GLuint buffer, const void* data, std::size_t bytes) {
        static const std::uint32_t zero[4] = {};
        gl.NamedBufferData(buffer, GLsizeiptr(std::max<std::size_t>(bytes, sizeof zero)), bytes ? data : zero, GL_STREAM_DRAW);
    };
    upload(polygonBuffer, call.polygons.data(), call.polygons.size() * sizeof(GpuPolygon));
    upload(sampleBuffer, call.samples.data(), call.samples.size() * sizeof(float));
    upload(flagBuffer, noFlags.data(), noFlags.size() * sizeof(std::uint32_t));
    upload(regionBuffer, call.regions.data(), call.regions.size() * sizeof(std::int32_t));
    gl.TextureBuffer(regionTexture, GL_RGBA32I, regionBuffer);
    gl.BindTextureUnit(0, regionTexture);
    gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, polygonBuffer);
    gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, sampleBuffer);
    gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, flagBuffer);
    gl.ProgramUniform1i(program, gl.GetUniformLocation(program, "uRegions"), 0);
    gl.ProgramUniform2i(program, gl.GetUniformLocation(program, "uSourceGrid"), call.source.na, call.source.nb);
    gl.ProgramUniform2i(program, gl.GetUniformLocation(program, "uReceiverGrid"), call.receiver.na, call.receiver.nb);
    if (!call.tableMode) {
        gl.ProgramUniform2f(program, gl.GetUniformLocation(program, "uMetres"), float(call.shaft.metresPerS),
                            float(call.shaft.metresPerT));
        gl.ProgramUniform1f(program, gl.GetUniformLocation(program, "uBudget"), float(bitmask::kFloatBandBudget));
    }
    const GLuint zero[4] = {0, 0, 0, 0};
    for (int k = 0; k < call.targets(); ++k)
        gl.ClearNamedFramebufferuiv(framebuffer, GL_COLOR, k, zero);
}

/// Draws every GPU polygon into the targets, OR-ed (section 5.1: the union over occluders, done
/// by the blending stage).
void GlBitmaskSampler::Impl::draw(const GlCall& call, GLuint program)
{
    gl.BindFramebuffer(GL_FRAMEBUFFER, framebuffer);
    gl.Viewport(0, 0, call.receiver.na, call.receiver.nb);
    gl.Enable(GL_COLOR_LOGIC_OP);
    gl.LogicOp(GL_OR);
    gl.UseProgram(program);
    gl.BindVertexArray(vertexArray);
    if (!call.polygons.empty())
        gl.DrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, GLsizei(call.polygons.size()));
    gl.MemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    gl.Finish();
    gl.Disable(GL_COLOR_LOGIC_OP);
    gl.BindFramebuffer(GL_FRAMEBUFFER, 0);
}

/// The targets into the map, and (exact mode) the samples the shader flagged as unproven.
std::vector<std::uint32_t> GlBitmaskSampler::Impl::readBack(const GlCall& call, HiddenSampleMap& map)
{
    std::vector<std::uint32_t> pixels(std::size_t(call.receiver.na) * std::size_t(call.receiver.nb) * 4);
    gl.PixelStorei(GL_PACK_ALIGNMENT, 4);
    const int rowBytes = (call.source.sampleCount() + 7) / 8;
    for (int k = 0; k < call.targets(); ++k) {
        gl.GetTextureImage(textures[k], 0, GL_RGBA_INTEGER, GL_UNSIGNED_INT, GLsizei(pixels.size() * sizeof(std::uint32_t)),
                           pixels.data());
        // Target k holds source bits [128k, 128k + 128) of every receiver sample, little-endian
        // 32-bit words: the same byte layout as the map's rows.
        const int bytes = std::min(16, rowBytes - 16 * k);
        for (int j = 0; j < map.receiverCount(); ++j)
            std::memcpy(reinterpret_cast<unsigned char*>(map.row(j).data()) + 16 * k, &pixels[std::size_t(j) * 4],
                        std::size_t(bytes));
    }
    std::vector<std::uint32_t> flags(std::size_t(call.receiver.sampleCount()), 0u);
    if (!call.tableMode)
        gl.GetNamedBufferSubData(flagBuffer, 0, GLsizeiptr(flags.size() * sizeof(std::uint32_t)), flags.data());
    if (const GLenum error = gl.GetError(); error != GL_NO_ERROR)
        throw Error("GL bitmask sampler: OpenGL error " + std::to_string(error));
    return flags;
}

/// The CPU's share (exact mode): the occluders the GPU did not take, on the CPU sampler's tile
/// pass (narrowed by what the GPU already blocked); then every flagged sample's tile again, with
/// the GPU's occluders in double.
void GlBitmaskSampler::Impl::cpuShare(GlCall& call, const std::vector<std::uint32_t>& flags, HiddenSampleMap& map)
{
    using namespace bitmask;
    bins.build(call.shaft, occluders, call.onGpu, call.closedInstance, triangles);
    bitmaskPass(call.shaft, bins, map, /*narrow=*/true);
    std::vector<std::uint32_t> flaggedTiles;
    const int na = call.receiver.na;
    const int tilesA = (na + kTile - 1) / kTile;
    for (int j = 0; j < call.receiver.sampleCount(); ++j)
        if (flags[std::size_t(j)]) {
            ++call.stats.flaggedSamples;
            flaggedTiles.push_back(std::uint32_t((j / na / kTile) * tilesA + (j % na) / kTile));
        }
    if (flaggedTiles.empty())
        return;
    std::sort(flaggedTiles.begin(), flaggedTiles.end());
    flaggedTiles.erase(std::unique(flaggedTiles.begin(), flaggedTiles.end()), flaggedTiles.end());
    std::vector<char> offGpu(call.onGpu.size());
    for (std::size_t n = 0; n < call.onGpu.size(); ++n)
        offGpu[n] = !call.onGpu[n];
    call.shaft.floatKernel = false;   // the shader could not prove them: double, not float again
    bins.build(call.shaft, occluders, offGpu, call.closedInstance, triangles);
    bitmaskPass(call.shaft, bins, map, /*narrow=*/true, &flaggedTiles);
}

HiddenSampleMap GlBitmaskSampler::sample(const Patch& source, const Patch& receiver, const GlBitmaskOptions& options,
                                         GlBitmaskStats* stats)
{
    validatePatchPair(source, receiver);
    if (options.mode == MaskMode::Table)
        HoughMaskTable::checkResolution(options.tableWidth, options.tableHeight);
    Impl& impl = *impl_;
    const auto setupStart = Clock::now();
    GlCall call(source, receiver, options);
    impl.prepareOccluders(call);
    impl.takeGpuShare(call);
    const GLuint program = impl.program(call.targets(), options.mode);
    impl.ensureTargets(call.targets(), receiver.na, receiver.nb);
    impl.bind(call, program);
    call.stats.setupMs = msSince(setupStart) - call.stats.tableMs;

    const auto drawStart = Clock::now();
    impl.draw(call, program);
    call.stats.drawMs = msSince(drawStart);

    const auto readStart = Clock::now();
    HiddenSampleMap map(source.sampleCount(), receiver.na, receiver.nb);
    const std::vector<std::uint32_t> flags = impl.readBack(call, map);
    call.stats.readbackMs = msSince(readStart);

    if (!call.tableMode) {
        const auto cpuStart = Clock::now();
        impl.cpuShare(call, flags, map);
        call.stats.cpuMs = msSince(cpuStart);
    }
    if (stats)
        *stats = call.stats;
    return map;
}

} // namespace sightline
