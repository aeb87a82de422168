#include "editor/DisagreementWorker.h"

#include <chrono>
#include <cstdio>
#include <exception>
#include <new>

#include "base/Error.h"
#include "visibility/gl/HeadlessContext.h"

namespace sightline::ui {

namespace {

double msSince(std::chrono::steady_clock::time_point start)
{
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

std::string withCommas(std::uint64_t n)
{
    std::string digits = std::to_string(n), out;
    for (std::size_t k = 0; k < digits.size(); ++k) {
        if (k > 0 && (digits.size() - k) % 3 == 0)
            out += ',';
        out += digits[k];
    }
    return out;
}

} // namespace

std::string disagreementStatus(const DisagreementAnswer& a)
{
    const std::string name = describeApproximation(a.approximation);
    if (!a.error.empty())
        return "Disagreement with exact (" + name + "): " + a.error;
    const RayDisagreement& d = *a.disagreement;
    char share[32];
    std::snprintf(share, sizeof share, "%.3g%%", 100.0 * d.errorFraction());
    std::string line = name + " vs exact: " + withCommas(d.falseBlockedCount) + " false-blocked (red), " +
                       withCommas(d.falseFreeCount) + " false-free (blue)";
    line += d.judged ? ", " + withCommas(d.tieCount) + " ties (amber)" : " (too many to judge ties)";
    line += " of " + withCommas(d.rays) + " rays: " + share + " wrong";
    if (a.trianglesApproximate != a.trianglesExact)
        line += "; " + withCommas(a.trianglesApproximate) + " of " + withCommas(a.trianglesExact) + " triangles";
    char ms[48];
    std::snprintf(ms, sizeof ms, "; %.0f ms", a.approximateMs);
    return line + ms;
}

class DisagreementWorker::State {
public:
    DisagreementAnswer answer(const DisagreementRequest& r)
    {
        DisagreementAnswer a;
        a.approximation = r.approximation;
        a.source = r.source, a.receiver = r.receiver;
        try {
            if (!r.scene || !r.exact)
                throw Error("no exact answer to compare with");
            auto start = std::chrono::steady_clock::now();
            const std::string name = approximationName(r.approximation);
            if (!sampler_ || scene_ != r.scene || samplerName_ != name) {
                sampler_.reset();
                sampler_ = std::make_unique<ApproximateSampler>(r.approximation, *r.scene);
                scene_ = r.scene, samplerName_ = name;
                a.prepareMs = msSince(start);
            }
            if (r.approximation.needsGl() && !context_)
                context_ = gl::HeadlessContext::create(gl::Backend::OSMesa);   // current on this thread from now on
            JudgedDisagreement judged = judgedDisagreement(*sampler_, *r.scene, r.source, r.receiver, r.heights.get(),
                                                           *r.exact, 0, context_ ? &context_->functions() : nullptr);
            a.disagreement = std::make_shared<const RayDisagreement>(std::move(judged.disagreement));
            a.approximateMs = judged.approximateMs;
            a.judgeMs = judged.judgeMs;
            a.trianglesExact = r.scene->triangleCount();
            a.trianglesApproximate = sampler_->scene().triangleCount();
        } catch (const std::bad_alloc&) {
            a.error = "out of memory";
            a.disagreement.reset();
        } catch (const std::exception& e) {
            a.error = e.what();
            a.disagreement.reset();
        }
        return a;
    }

private:
    std::unique_ptr<gl::HeadlessContext> context_;   // first: outlives the GL sampler that uses it
    std::unique_ptr<ApproximateSampler> sampler_;
    std::shared_ptr<const Scene> scene_;   // the level sampler_ was built from
    std::string samplerName_;
};

DisagreementWorker::DisagreementWorker(Deliver deliver)
    : state_(std::make_shared<State>()),
      worker_([state = state_](const DisagreementRequest& r) { return state->answer(r); }, std::move(deliver))
{
}

DisagreementWorker::~DisagreementWorker() = default;

void DisagreementWorker::request(DisagreementRequest request)
{
    const std::uint64_t generation = request.generation;
    worker_.request(generation, std::move(request));
}

} // namespace sightline::ui
