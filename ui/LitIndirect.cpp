#include "LitIndirect.h"

namespace sightline::ui {

IndirectOptions litIndirectOptions()
{
    IndirectOptions options;
    options.vpls = 512;
    options.threads = 1;   // the lit view's worker runs on one thread, below the editor's priority
    return options;
}

LitIndirect::LitIndirect(std::vector<ShadingPoint> points, IndirectOptions options)
    : points_(std::move(points)), options_(options), shown_(points_.size(), glm::dvec3(0.0))
{
    validateIndirectOptions(options_);
}

void LitIndirect::setLights(const LightingScene& scene, const std::vector<Light>& lights)
{
    VplSet set = traceVpls(scene, lights, options_);
    vpls_ = set.vpls.size();
    cache_ = std::make_unique<LightingCache>(points_, std::move(set.vpls));
    exact_ = false;
}

void LitIndirect::update(const LightingScene& scene, std::uint64_t budget)
{
    if (!cache_ || exact_)
        return;
    if (cache_->update(scene, budget, options_.threads).exact) {
        shown_ = cache_->irradiance();
        exact_ = true;
    }
}

} // namespace sightline::ui
