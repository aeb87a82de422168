#include "bench/Bench.h"

#include <algorithm>
#include <bit>
#include <chrono>
#include <ctime>
#include <cmath>
#include <map>
#include <memory>
#include <span>
#include <tuple>
#include <sstream>
#include <utility>

#include "bench/TunedEmbree.h"
#include "lighting/SoftShadow.h"
#include "project/CoarseOccluders.h"
#include "project/Project.h"
#include "visibility/CpuBitmaskSampler.h"
#include "base/Error.h"
#include "visibility/ExactJudge.h"
#include "visibility/GlBitmaskSampler.h"
#include "visibility/HeckbertHerfSampler.h"
#include "visibility/RayCastSampler.h"
#include "visibility/gl/HeadlessContext.h"

namespace sightline::bench {

namespace {

double threadMs()
{
    timespec now{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
    return double(now.tv_sec) * 1e3 + double(now.tv_nsec) * 1e-6;
}

/// The lower median (an even count never reports the slower middle run).
double lowerMedian(std::vector<double> values)
{
    std::sort(values.begin(), values.end());
    return values[(values.size() - 1) / 2];
}

/// One way of answering a configuration (a method; the tuned tracer has one per traversal), its
/// answer and the wall and processor times of its timed runs. All of a configuration's
/// candidates are timed in interleaved rounds, not one after another: a shared machine has slow
/// and fast spells longer than a method's runs (the same call a quarter dearer in one than in the
/// next, processor time too), and rounds let them fall on every method alike instead of deciding
/// a ratio.
struct Candidate {
    std::string variant;
    std::function<void()> run;   ///< fills map (or counts) and, for the CPU sampler, variant
    HiddenSampleMap map;
    std::vector<std::uint32_t> counts;   ///< hh: blocked source samples per receiver sample
    std::vector<double> wall, thread;

    void timeOnce()
    {
        const auto start = std::chrono::steady_clock::now();
        const double threadStart = threadMs();
        run();
        thread.push_back(threadMs() - threadStart);
        wall.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
    }
    double medianMs() const { return lowerMedian(wall); }
    double medianThreadMs() const { return lowerMedian(thread); }
};

/// A method's candidates (each heap-held: its run captures it by reference).
struct MethodRuns {
    std::string method;
    bool jittered = false;
    std::vector<std::unique_ptr<Candidate>> candidates;

    Candidate& add(std::string variant = {})
    {
        candidates.push_back(std::make_unique<Candidate>());
        candidates.back()->variant = std::move(variant);
        return *candidates.back();
    }
};

/// The CPU sampler's `variant`: the strategy its last run took ("bitmask", "raycast", "hybrid",
/// "mixed" over swapped tiles), with " swapped" where the patches swapped roles, so that Auto's
/// rows say what it chose.
std::string strategyVariant(const BitmaskStats& stats)
{
    std::string out = stats.strategy;
    if (stats.swappedRoles)
        out += " swapped";
    return out;
}

/// "<prefix>WxH" with a table resolution HoughMaskTable accepts.
bool parseTable(const std::string& name, const std::string& prefix, int& w, int& h)
{
    if (name.rfind(prefix, 0) != 0)
        return false;
    const std::string size = name.substr(prefix.size());
    const auto x = size.find('x');
    if (x == std::string::npos)
        return false;
    try {
        w = std::stoi(size.substr(0, x));
        h = std::stoi(size.substr(x + 1));
    } catch (const std::exception&) {
        return false;
    }
    return w >= 4 && h >= 2 && w <= 8192 && h <= 8192;
}

} // namespace

std::vector<std::string> parseMethods(const std::string& commaSeparated)
{
    std::vector<std::string> out;
    std::stringstream in(commaSeparated);
    for (std::string name; std::getline(in, name, ',');) {
        int w, h;
        const bool jittered = name == "raycast-jitter" || name == "cpu-jitter" || name == "gl-jitter";
        const bool plain = name == "raycast" || name == "embree-tuned" || name == "cpu" || name == "cpu-bitmask" ||
                           name == "cpu-hybrid" || name == "cpu-raycast" || name == "cpu-scalar" || name == "gl" || name == "hh";
        if (!jittered && !plain && !parseTable(name, "cpu-table-", w, h) && !parseTable(name, "gl-table-", w, h))
            throw Error("unknown bench method '" + name +
                        "' (raycast, embree-tuned, cpu, cpu-bitmask, cpu-hybrid, cpu-raycast, cpu-scalar, cpu-table-WxH, gl, "
                        "gl-table-WxH, hh, raycast-jitter, cpu-jitter, gl-jitter)");
        out.push_back(name);
    }
    if (out.empty())
        throw Error("no bench methods given");
    return out;
}

std::pair<int, int> sourceGrid(int count)
{
    int nb = int(std::sqrt(double(count)));
    while (nb > 1 && count % nb != 0)
        --nb;
    return {count / nb, nb};
}

namespace {

/// The judges of one configuration, made when first needed (regular and jittered rays).
struct Judges {
    const WorldTriangles& triangles;
    const Patch& source;
    const Patch& receiver;
    std::unique_ptr<ExactJudge> regular = nullptr, jittered = nullptr;

    const ExactJudge& forJitter(const SourceJitter& jitter)
    {
        std::unique_ptr<ExactJudge>& judge = jitter.enabled() ? jittered : regular;
        if (!judge)
            judge = std::make_unique<ExactJudge>(triangles, source, receiver, jitter);
        return *judge;
    }
};

} // namespace

void judgeDifferences(Row& row, const HiddenSampleMap& map, const HiddenSampleMap& truth,
                      const std::function<const ExactJudge&()>& judge)
{
    std::vector<std::pair<int, int>> differ;
    std::uint64_t blockedMore = 0, freeMore = 0;
    for (int j = 0; j < map.receiverCount(); ++j) {
        const std::span<const std::uint64_t> mine = map.row(j), theirs = truth.row(j);
        for (std::size_t k = 0; k < mine.size(); ++k) {
            blockedMore += std::uint64_t(std::popcount(mine[k] & ~theirs[k]));
            freeMore += std::uint64_t(std::popcount(~mine[k] & theirs[k]));
            if (blockedMore + freeMore <= kMaxJudgedRays)
                for (std::uint64_t bits = mine[k] ^ theirs[k]; bits; bits &= bits - 1)
                    differ.emplace_back(j, int(64 * k) + std::countr_zero(bits));
        }
    }
    row.judged = blockedMore + freeMore <= kMaxJudgedRays;
    row.wronglyBlocked = row.wronglyFree = row.ties = row.referenceErrors = 0;
    if (!row.judged) {
        row.wronglyBlocked = blockedMore, row.wronglyFree = freeMore;
        return;
    }
    if (differ.empty())
        return;
    const std::vector<RayKind> kinds = judge().kinds(differ);
    for (std::size_t k = 0; k < differ.size(); ++k) {
        const bool blocked = map.blocked(differ[k].first, differ[k].second);
        switch (kinds[k]) {
        case RayKind::Free: row.wronglyBlocked += blocked, row.referenceErrors += !blocked; break;
        case RayKind::Blocked: row.wronglyFree += !blocked, row.referenceErrors += blocked; break;
        case RayKind::EdgeTie:
        case RayKind::EndTie: ++row.ties; break;
        }
    }
}

namespace {

/// What one project's methods sample with: the reference and the CPU sampler at once, the others
/// on first use (the GL context is shared by every project of a run).
struct ProjectSamplers {
    const Settings& settings;
    std::unique_ptr<gl::HeadlessContext>& context;
    Scene scene;
    RayCastScene reference;
    CpuBitmaskSampler cpu;
    WorldTriangles triangles;
    std::unique_ptr<TunedEmbree> tuned;
    std::unique_ptr<GlBitmaskSampler> gpu;
    std::unique_ptr<HeckbertHerfSampler> heckbertHerf;

    ProjectSamplers(const Settings& runSettings, std::unique_ptr<gl::HeadlessContext>& sharedContext, Scene projectScene)
        : settings(runSettings), context(sharedContext), scene(std::move(projectScene)), reference(scene), cpu(scene),
          triangles(worldTriangles(scene))
    {
    }

    gl::HeadlessContext& gl()
    {
        if (!context)
            context = gl::HeadlessContext::create(settings.glBackend);
        return *context;
    }
};

/// One configuration (a source count and a receiver side) of a project.
struct Configuration {
    Patch source, receiver;
    SourceJitter jitter{.seed = 1};
};

/// The candidates that answer `m.method` on the configuration: one, or the tuned tracer's
/// traversals (every one a user tuning it could pick; the fastest is kept).
void addCandidates(MethodRuns& m, ProjectSamplers& s, const Configuration& c)
{
    const std::string& method = m.method;
    const Settings& settings = s.settings;
    int w = 0, h = 0;
    if (method == "embree-tuned") {
        if (!s.tuned)
            s.tuned = std::make_unique<TunedEmbree>(s.triangles);
        for (const TunedTraversal& traversal : tunedTraversals()) {
            Candidate& k = m.add(traversal.name());
            k.run = [&, traversal] { k.map = s.tuned->sample(c.source, c.receiver, settings.threads, traversal); };
        }
    } else if (method == "raycast" || method == "raycast-jitter") {
        const RayCastOptions options{.packets = true, .threads = settings.threads, .jitter = m.jittered ? c.jitter : SourceJitter{}};
        Candidate& k = m.add();
        k.run = [&, options] { k.map = s.reference.sample(c.source, c.receiver, options); };
    } else if (method == "gl" || method == "gl-jitter" || parseTable(method, "gl-table-", w, h)) {
        if (!s.gpu)
            s.gpu = std::make_unique<GlBitmaskSampler>(s.gl().functions(), s.scene);
        GlBitmaskOptions options;
        if (m.jittered)
            options.jitter = c.jitter;
        else if (method != "gl")
            options.mode = MaskMode::Table, options.tableWidth = w, options.tableHeight = h;
        Candidate& k = m.add();
        k.run = [&, options] { k.map = s.gpu->sample(c.source, c.receiver, options); };
    } else if (method == "hh") {
        if (!s.heckbertHerf)
            s.heckbertHerf = std::make_unique<HeckbertHerfSampler>(s.gl().functions(), s.triangles);
        Candidate& k = m.add();
        k.run = [&] { k.counts = s.heckbertHerf->blockedCounts(c.source, c.receiver); };
    } else {
        BitmaskOptions options;
        options.threads = settings.threads;
        if (m.jittered)
            options.jitter = c.jitter;
        else if (method == "cpu-bitmask")
            options.strategy = CpuStrategy::Bitmask;
        else if (method == "cpu-hybrid")
            options.strategy = CpuStrategy::Hybrid;
        else if (method == "cpu-raycast")
            options.strategy = CpuStrategy::RayCast;
        else if (method == "cpu-scalar")
            options.simd = false;
        else if (parseTable(method, "cpu-table-", w, h))
            options.mode = MaskMode::Table, options.tableWidth = w, options.tableHeight = h;
        Candidate& k = m.add();
        k.run = [&, options] {
            BitmaskStats stats;
            k.map = s.cpu.sample(c.source, c.receiver, options, &stats);
            k.variant = strategyVariant(stats);
        };
    }
}

/// In each round every candidate runs once untimed, then timed until its batch has taken
/// minBatchMs. The untimed run warms what the previous candidate evicted (a sub-millisecond call
/// right after another method's runs slower than right after itself), so each is timed warm, as
/// in the editor's repeated calls; the first round's pays the page faults, thread pools and shader
/// compilation. A batch of at least minBatchMs gives a sub-millisecond call dozens of runs, where a
/// median of three is mostly timing noise.
void timeInRounds(const std::vector<MethodRuns>& methods, const Settings& settings)
{
    for (int k = 0; k < std::max(1, settings.repeat); ++k)
        for (const MethodRuns& m : methods)
            for (const auto& c : m.candidates) {
                c->run();
                const auto batchStart = std::chrono::steady_clock::now();
                for (int n = 0; n < kMaxRunsPerRound; ++n) {
                    c->timeOnce();
                    if (std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - batchStart).count() >=
                        settings.minBatchMs)
                        break;
                }
            }
}

/// hh answers counts only: per receiver sample, the excess or shortfall of blocked rays (a lower
/// bound on the rays in error).
void judgeCounts(Row& row, const std::vector<std::uint32_t>& counts, const HiddenSampleMap& truth)
{
    for (int j = 0; j < truth.receiverCount(); ++j) {
        std::int64_t expected = 0;
        for (std::uint64_t word : truth.row(j))
            expected += std::popcount(word);
        const std::int64_t got = counts[std::size_t(j)];
        row.blocked += std::uint64_t(got);
        row.wronglyBlocked += std::uint64_t(std::max<std::int64_t>(0, got - expected));
        row.wronglyFree += std::uint64_t(std::max<std::int64_t>(0, expected - got));
    }
}

/// The row of a method's fastest candidate (by processor time on one thread, else by wall time),
/// judged against the truth, with its light fractions' errors (§8) against the truth's and the
/// dense reference's (when there is one).
Row judgedRow(const MethodRuns& m, const Settings& settings, const Configuration& c, const HiddenSampleMap& truth,
              Judges& judges, const ImportanceMap& dense)
{
    const auto cost = [&](const Candidate& k) { return settings.threads == 1 ? k.medianThreadMs() : k.medianMs(); };
    const Candidate* best = m.candidates.front().get();
    for (const auto& k : m.candidates)
        if (cost(*k) < cost(*best))
            best = k.get();
    Row row;
    row.method = m.method;
    row.sourceSamples = c.source.sampleCount();
    row.receiverSide = c.receiver.na;
    row.ms = best->medianMs();
    row.threadMs = best->medianThreadMs();
    row.variant = best->variant;
    row.runs = int(best->wall.size());
    row.rays = truth.rayCount();
    const bool counts = m.method == "hh";
    if (counts) {
        judgeCounts(row, best->counts, truth);
    } else {
        row.blocked = best->map.blockedCount();
        judgeDifferences(row, best->map, truth, [&]() -> const ExactJudge& { return judges.forJitter(m.jittered ? c.jitter : SourceJitter{}); });
    }
    ImportanceMap light(c.receiver.na, c.receiver.nb);
    for (int j = 0; j < truth.receiverCount(); ++j) {
        const int blocked = counts ? int(best->counts[std::size_t(j)]) : best->map.blockedCount(j);
        light.values[std::size_t(j)] = 1.0f - float(blocked) / float(row.sourceSamples);
    }
    row.lightMae = meanAbsoluteError(light, receiverImportance(truth));
    if (!dense.values.empty())
        row.denseMae = meanAbsoluteError(light, dense);
    return row;
}

} // namespace

std::vector<Row> run(const Settings& settings, const std::function<void(const Row&)>& progress)
{
    std::vector<Row> rows;
    std::unique_ptr<gl::HeadlessContext> context;   // made on first use of "gl" or "hh"
    for (const std::string& file : settings.projects) {
        const Project project = loadProject(file, {.allowOutsidePaths = settings.allowOutsidePaths});
        ProjectSamplers samplers(settings, context, buildRayScene(project));
        std::map<int, ImportanceMap> denseBySide;   // receiver side -> dense light fraction
        for (int count : settings.sourceCounts) {
            if (count < 1 || count > kMaxSourceSamples)
                throw Error("bench: source sample count " + std::to_string(count) + " is outside [1, 1024]");
            for (int side : settings.receiverSides) {
                Configuration c{project.source, project.receiver};
                std::tie(c.source.na, c.source.nb) = sourceGrid(count);
                c.receiver.na = c.receiver.nb = side;
                validatePatchPair(c.source, c.receiver);
                const RayCastOptions exact{.packets = true, .threads = settings.threads};
                const HiddenSampleMap regularTruth = samplers.reference.sample(c.source, c.receiver, exact);
                Judges judges{samplers.triangles, c.source, c.receiver};
                std::unique_ptr<HiddenSampleMap> jitteredTruth;   // made for the first "-jitter" method
                // The dense light does not depend on the source grid: once per receiver grid.
                ImportanceMap& dense = denseBySide[side];
                if (settings.denseSide > 0 && dense.values.empty())
                    dense = denseLightFraction(samplers.reference, project.source, c.receiver, settings.denseSide, exact);
                // Every method's runs are prepared first and timed in interleaved rounds (the
                // Candidate comment says why); each is then judged and reported in method order.
                std::vector<MethodRuns> methods;
                methods.reserve(settings.methods.size());
                for (const std::string& method : settings.methods) {
                    MethodRuns& m = methods.emplace_back();
                    m.method = method;
                    m.jittered = method.ends_with("-jitter");
                    if (m.jittered && !jitteredTruth) {
                        RayCastOptions jittered = exact;
                        jittered.jitter = c.jitter;
                        jitteredTruth = std::make_unique<HiddenSampleMap>(samplers.reference.sample(c.source, c.receiver, jittered));
                    }
                    addCandidates(m, samplers, c);
                }
                timeInRounds(methods, settings);
                for (const MethodRuns& m : methods) {
                    Row row = judgedRow(m, settings, c, m.jittered ? *jitteredTruth : regularTruth, judges, dense);
                    row.project = file;
                    rows.push_back(row);
                    if (progress)
                        progress(row);
                }
            }
        }
    }
    return rows;
}

std::string toCsv(const std::vector<Row>& rows)
{
    std::ostringstream out;
    out << "project,method,source_samples,receiver,rays,ms,blocked,wrongly_blocked,wrongly_free,error_fraction,"
           "light_mae,dense_light_mae,thread_ms,ties,variant,runs\n";
    for (const Row& r : rows) {
        out << '"' << r.project << "\"," << r.method << ',' << r.sourceSamples << ',' << r.receiverSide << 'x'
            << r.receiverSide << ',' << r.rays << ',' << r.ms << ',' << r.blocked << ',' << r.wronglyBlocked << ','
            << r.wronglyFree << ',' << r.errorFraction() << ',' << r.lightMae << ',';
        if (r.denseMae >= 0.0)
            out << r.denseMae;
        out << ',' << r.threadMs << ',';
        if (r.judged)
            out << r.ties;
        out << ',' << r.variant << ',' << r.runs << '\n';
    }
    return out.str();
}

} // namespace sightline::bench
