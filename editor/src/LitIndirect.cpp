#include "editor/LitIndirect.h"

#include <algorithm>

#include "editor/LitPreview.h"

namespace sightline::ui {

IndirectOptions litIndirectOptions()
{
    IndirectOptions options;
    options.vpls = 512;
    options.threads = 1;   // the lit view's worker runs on one thread, below the editor's priority
    return options;
}

LitIndirect::LitIndirect(std::vector<ShadingPoint> points, IndirectOptions options)
    : points_(std::move(points)), tiling_(std::make_unique<PointTiling>(points_)), options_(options),
      shown_(points_.size(), glm::dvec3(0.0))
{
    validateIndirectOptions(options_);
}

namespace {

/// The VPLs of `from` that `than` lacks (sameLight: bit for bit), each matched once.
std::vector<Light> missing(const std::vector<Light>& from, const std::vector<Light>& than)
{
    std::vector<bool> used(than.size(), false);
    std::vector<Light> out;
    for (const Light& vpl : from) {
        bool found = false;
        for (std::size_t k = 0; k < than.size() && !found; ++k)
            if (!used[k] && sameLight(vpl, than[k]))
                found = used[k] = true;
        if (!found)
            out.push_back(vpl);
    }
    return out;
}

} // namespace

void LitIndirect::setLights(const LightingScene& scene, const std::vector<Light>& lights)
{
    VplSet set = traceVpls(scene, lights, options_);
    vplLights_ = std::move(set.vpls);
    work_.clear();
    next_ = 0;
    const std::vector<Light> gone = anyShown_ ? missing(shownVpls_, vplLights_) : std::vector<Light>{};
    const std::vector<Light> added = anyShown_ ? missing(vplLights_, shownVpls_) : vplLights_;
    if (anyShown_ && gone.size() + added.size() < vplLights_.size()) {
        // From the bounce shown: its VPLs that are gone taken away, the new ones added.
        sum_ = shown_;
        for (const Light& vpl : gone)
            work_.push_back({vpl, -1.0});
        for (const Light& vpl : added)
            work_.push_back({vpl, 1.0});
    } else {
        sum_.assign(points_.size(), glm::dvec3(0.0));
        for (const Light& vpl : vplLights_)
            work_.push_back({vpl, 1.0});
    }
    exact_ = false;
    finishIfDone();
}

void LitIndirect::finishIfDone()
{
    if (next_ < work_.size())
        return;
    shown_ = sum_;
    shownVpls_ = vplLights_;
    anyShown_ = true;
    exact_ = true;
}

void LitIndirect::update(const LightingScene& scene, std::uint64_t budget)
{
    if (exact_)
        return;
    const std::uint64_t perVpl = std::max<std::uint64_t>(points_.size(), 1);
    const std::size_t count = std::min(work_.size() - next_, std::size_t(std::max<std::uint64_t>(budget / perVpl, 1)));
    // Added and taken-away VPLs lit apart (each sum in the VPLs' order), then applied.
    for (const double sign : {-1.0, 1.0}) {
        std::vector<Light> chunk;
        for (std::size_t k = next_; k < next_ + count; ++k)
            if (work_[k].sign == sign)
                chunk.push_back(work_[k].vpl);
        if (chunk.empty())
            continue;
        const std::vector<glm::dvec3> part =
            directIrradiance(scene, chunk, points_, DirectLightOptions{.threads = options_.threads, .tiling = tiling_.get()});
        for (std::size_t j = 0; j < sum_.size(); ++j)
            sum_[j] += sign * part[j];
    }
    next_ += count;
    finishIfDone();
}

} // namespace sightline::ui
