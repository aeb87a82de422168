#include "project/Approximation.h"

#include <chrono>
#include <charconv>
#include <optional>
#include <string_view>

#include "project/CoarseOccluders.h"
#include "visibility/CpuBitmaskSampler.h"
#include "base/Error.h"
#include "visibility/ExactJudge.h"
#include "visibility/GlBitmaskSampler.h"
#include "visibility/RayDisagreement.h"

namespace sightline {

namespace {

constexpr const char* kSpellings = "table[-WxH], gl, gl-table[-WxH], samples-K, coarse[-N] or inner[-R]";

/// A whole decimal number within [lo, hi], or nothing.
std::optional<long long> number(std::string_view text, long long lo, long long hi)
{
    long long value = 0;
    const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (text.empty() || error != std::errc() || end != text.data() + text.size() || value < lo || value > hi)
        return std::nullopt;
    return value;
}

/// "WxH" within the Hough table's range (HoughMaskTable.h).
bool parseTableSize(std::string_view text, Approximation& out)
{
    const std::size_t x = text.find('x');
    if (x == std::string_view::npos)
        return false;
    const auto w = number(text.substr(0, x), 4, 8192), h = number(text.substr(x + 1), 2, 8192);
    if (!w || !h)
        return false;
    out.tableWidth = int(*w), out.tableHeight = int(*h);
    return true;
}

/// `name` is `stem` alone or `stem-<rest>`: rest (empty when alone), or nothing.
std::optional<std::string_view> suffixAfter(std::string_view name, std::string_view stem)
{
    if (name == stem)
        return std::string_view{};
    if (name.size() > stem.size() + 1 && name.substr(0, stem.size()) == stem && name[stem.size()] == '-')
        return name.substr(stem.size() + 1);
    return std::nullopt;
}

bool parseInto(std::string_view name, Approximation& a)
{
    using K = ApproximationKind;
    if (name == "gl") {
        a.kind = K::Gl;
        return true;
    }
    if (const auto rest = suffixAfter(name, "gl-table")) {
        a.kind = K::GlTable;
        return rest->empty() || parseTableSize(*rest, a);
    }
    if (const auto rest = suffixAfter(name, "table")) {
        a.kind = K::Table;
        return rest->empty() || parseTableSize(*rest, a);
    }
    std::optional<long long> value;
    if (const auto rest = suffixAfter(name, "samples"); rest && !rest->empty()) {
        a.kind = K::FewerSamples;
        if ((value = number(*rest, 2, 64)))
            a.sampleFactor = int(*value);
    } else if (const auto coarse = suffixAfter(name, "coarse")) {
        a.kind = K::Coarse;
        if ((value = coarse->empty() ? 5000 : number(*coarse, 4, 100'000'000)))
            a.triangles = std::size_t(*value);
    } else if (const auto inner = suffixAfter(name, "inner")) {
        a.kind = K::Inner;
        if ((value = inner->empty() ? 32 : number(*inner, 4, 256)))
            a.resolution = int(*value);
    }
    return value.has_value();
}

} // namespace

Approximation parseApproximation(const std::string& name)
{
    Approximation a;
    if (!parseInto(name, a))
        throw Error("approximation \"" + name + "\" is not one of " + kSpellings +
                    " (tables 4..8192 x 2..8192, K 2..64, N 4..100000000, R 4..256)");
    return a;
}

std::string approximationName(const Approximation& a)
{
    const std::string size = std::to_string(a.tableWidth) + "x" + std::to_string(a.tableHeight);
    switch (a.kind) {
    case ApproximationKind::Table: return "table-" + size;
    case ApproximationKind::GlTable: return "gl-table-" + size;
    case ApproximationKind::Gl: return "gl";
    case ApproximationKind::FewerSamples: return "samples-" + std::to_string(a.sampleFactor);
    case ApproximationKind::Coarse: return "coarse-" + std::to_string(a.triangles);
    case ApproximationKind::Inner: return "inner-" + std::to_string(a.resolution);
    }
    return "?";
}

std::string describeApproximation(const Approximation& a)
{
    const std::string size = std::to_string(a.tableWidth) + "x" + std::to_string(a.tableHeight);
    switch (a.kind) {
    case ApproximationKind::Table: return "Hough table " + size + " (CPU)";
    case ApproximationKind::GlTable: return "Hough table " + size + " (GL)";
    case ApproximationKind::Gl: return "GL bitmask, exact masks";
    case ApproximationKind::FewerSamples:
        return "1/" + std::to_string(a.sampleFactor * a.sampleFactor) + " of the samples on each patch (1/" +
               std::to_string(a.sampleFactor) + " each side)";
    case ApproximationKind::Coarse: return "coarse occluders (meshes cut to " + std::to_string(a.triangles) + " triangles)";
    case ApproximationKind::Inner: return "inner occluders (conservative, " + std::to_string(a.resolution) + " voxels)";
    }
    return "?";
}

ApproximateSampler::ApproximateSampler(const Approximation& approximation, const Scene& level)
    : approximation_(approximation), scene_(level)
{
    if (approximation.replacesMeshes()) {
        CoarseOccluder spec;
        spec.kind = approximation.kind == ApproximationKind::Inner ? CoarseKind::Inner : CoarseKind::Closest;
        spec.triangles = approximation.triangles;
        spec.resolution = approximation.resolution;
        replaced_ = replaceDenseMeshes(scene_, spec).replaced;
        if (replaced_ == 0)
            throw Error(approximation.kind == ApproximationKind::Inner
                            ? "no closed mesh of more than 12 triangles to stand an inner occluder in"
                            : "no mesh has more than " + std::to_string(approximation.triangles) +
                                  " triangles to simplify (coarse-N with a smaller N)");
    }
    if (!approximation.needsGl())
        cpu_ = std::make_unique<CpuBitmaskSampler>(scene_);
}

ApproximateSampler::~ApproximateSampler() = default;

HiddenSampleMap ApproximateSampler::sample(const Patch& source, const Patch& receiver, const ReceiverHeights* heights,
                                           int threads, const gl::Functions* gl)
{
    const bool bumpy = heights && !heights->empty();
    const std::string name = approximationName(approximation_);
    if (bumpy && (approximation_.needsGl() || approximation_.kind == ApproximationKind::FewerSamples))
        throw Error(name + " cannot sample a bumpy receiver (its heights are given for the full grid, on the CPU); "
                           "clear the project's receiver_heights or pick table, coarse or inner");
    if (approximation_.needsGl()) {
        if (!gl)
            throw Error(name + " needs an OpenGL 4.5 core context");
        if (!gl_ || glFunctions_ != gl) {
            gl_ = std::make_unique<GlBitmaskSampler>(*gl, scene_);
            glFunctions_ = gl;
        }
        GlBitmaskOptions options;
        options.mode = approximation_.kind == ApproximationKind::GlTable ? MaskMode::Table : MaskMode::Exact;
        options.tableWidth = approximation_.tableWidth, options.tableHeight = approximation_.tableHeight;
        return gl_->sample(source, receiver, options);
    }
    BitmaskOptions options;
    options.threads = threads;
    if (approximation_.kind == ApproximationKind::Table) {
        options.mode = MaskMode::Table;
        options.tableWidth = approximation_.tableWidth, options.tableHeight = approximation_.tableHeight;
    }
    if (approximation_.kind != ApproximationKind::FewerSamples) {
        options.heights = bumpy ? heights : nullptr;
        return cpu_->sample(source, receiver, options);
    }
    validatePatchPair(source, receiver);
    const Patch coarseSource = withFewerSamples(source, approximation_.sampleFactor);
    const Patch coarseReceiver = withFewerSamples(receiver, approximation_.sampleFactor);
    return spreadToFullGrids(cpu_->sample(coarseSource, coarseReceiver, options), coarseSource, coarseReceiver, source,
                             receiver);
}

JudgedDisagreement judgedDisagreement(ApproximateSampler& sampler, const Scene& level, const Patch& source,
                                      const Patch& receiver, const ReceiverHeights* heights, const HiddenSampleMap& exact,
                                      int threads, const gl::Functions* gl)
{
    using Clock = std::chrono::steady_clock;
    const auto msSince = [](Clock::time_point start) {
        return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
    };
    JudgedDisagreement out;
    auto start = Clock::now();
    const HiddenSampleMap approximate = sampler.sample(source, receiver, heights, threads, gl);
    out.approximateMs = msSince(start);
    out.approximateBlocked = approximate.blockedCount();
    start = Clock::now();
    std::vector<glm::dvec3> displaced;
    for (int j = 0; heights && !heights->empty() && j < receiver.sampleCount(); ++j)
        displaced.push_back(displacedReceiverSample(source, receiver, *heights, j));
    const ExactJudge judge(worldTriangles(level), source, receiver, {}, displaced.empty() ? nullptr : &displaced);
    out.disagreement = rayDisagreement(exact, approximate, &judge);
    out.judgeMs = msSince(start);
    return out;
}

} // namespace sightline
