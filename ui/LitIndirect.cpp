#include "LitIndirect.h"

#include <algorithm>

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

void LitIndirect::setLights(const LightingScene& scene, const std::vector<Light>& lights)
{
    VplSet set = traceVpls(scene, lights, options_);
    vplLights_ = std::move(set.vpls);
    next_ = 0;
    sum_.assign(points_.size(), glm::dvec3(0.0));
    exact_ = vplLights_.empty();
    if (exact_)
        shown_ = sum_;
}

void LitIndirect::update(const LightingScene& scene, std::uint64_t budget)
{
    if (exact_)
        return;
    const std::uint64_t perVpl = std::max<std::uint64_t>(points_.size(), 1);
    const std::size_t count = std::min(vplLights_.size() - next_, std::size_t(std::max<std::uint64_t>(budget / perVpl, 1)));
    const std::vector<Light> chunk(vplLights_.begin() + std::ptrdiff_t(next_), vplLights_.begin() + std::ptrdiff_t(next_ + count));
    const std::vector<glm::dvec3> part = directIrradiance(scene, chunk, points_, DirectLightOptions{.threads = options_.threads, .tiling = tiling_.get()});
    for (std::size_t j = 0; j < sum_.size(); ++j)
        sum_[j] += part[j];
    next_ += count;
    if (next_ == vplLights_.size()) {
        shown_ = sum_;
        exact_ = true;
    }
}

} // namespace sightline::ui
