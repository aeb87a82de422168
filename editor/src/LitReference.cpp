#include "editor/LitReference.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include <glm/common.hpp>

#include "editor/LitPreview.h"

namespace sightline::ui {

namespace {

Light white(Light light)
{
    light.colour = glm::dvec3(1.0);
    return light;
}

double luminance(const glm::dvec3& e) { return 0.2126 * e.r + 0.7152 * e.g + 0.0722 * e.b; }

} // namespace

bool LitReference::isCurrent(std::size_t index, const Light& light) const
{
    return index < kept_.size() && kept_[index].valid && sameLight(kept_[index].light, white(light));
}

std::size_t LitReference::current(const std::vector<Light>& lights) const
{
    std::size_t n = 0;
    for (std::size_t l = 0; l < lights.size(); ++l)
        n += isCurrent(l, lights[l]) ? 1 : 0;
    return n;
}

bool LitReference::update(const LightingScene& scene, const std::vector<ShadingPoint>& points, const std::vector<Light>& lights,
                          double budgetMs)
{
    kept_.resize(lights.size());
    const auto start = std::chrono::steady_clock::now();
    bool first = true;
    for (std::size_t l = 0; l < lights.size(); ++l) {
        if (isCurrent(l, lights[l]))
            continue;
        const double spent = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
        if (!first && spent > budgetMs)
            return false;
        first = false;
        const Light light = white(lights[l]);
        const std::vector<glm::dvec3> field = directIrradiance(scene, {light}, points, {.path = LightingPath::Reference, .threads = 1});
        Kept& kept = kept_[l];
        kept.light = light;
        kept.field.resize(points.size());
        for (std::size_t j = 0; j < points.size(); ++j)
            kept.field[j] = float(field[j].x);
        kept.valid = true;
    }
    return true;
}

std::vector<glm::dvec3> LitReference::irradiance(const std::vector<Light>& lights, std::size_t points) const
{
    std::vector<glm::dvec3> sum(points, glm::dvec3(0.0));
    for (std::size_t l = 0; l < lights.size() && l < kept_.size(); ++l) {
        if (!kept_[l].valid)
            continue;
        for (std::size_t j = 0; j < points && j < kept_[l].field.size(); ++j)
            sum[j] += lights[l].colour * double(kept_[l].field[j]);
    }
    return sum;
}

std::vector<float> relativeError(const std::vector<glm::dvec3>& shown, const std::vector<glm::dvec3>& reference)
{
    double brightest = 0.0;
    for (const glm::dvec3& e : reference)
        brightest = std::max(brightest, luminance(e));
    const double floor = std::max(1e-3 * brightest, 1e-300);
    std::vector<float> error(shown.size(), 0.0f);
    for (std::size_t j = 0; j < shown.size() && j < reference.size(); ++j)
        error[j] = float(std::abs(luminance(shown[j]) - luminance(reference[j])) / std::max(luminance(reference[j]), floor));
    return error;
}

glm::vec3 errorColour(float relative)
{
    if (std::isnan(relative))
        return glm::vec3(1.0f, 0.1f, 0.1f);
    if (relative < kErrorAgrees)
        return glm::vec3(0.1f, 0.3f, 0.15f);
    // log10 from kErrorAgrees (1e-4) to 1: 0 to 1.
    const float t = std::clamp(std::log10(relative / kErrorAgrees) / 4.0f, 0.0f, 1.0f);
    if (t < 0.5f)
        return glm::mix(glm::vec3(0.2f, 0.35f, 1.0f), glm::vec3(1.0f, 0.9f, 0.2f), t * 2.0f);
    return glm::mix(glm::vec3(1.0f, 0.9f, 0.2f), glm::vec3(1.0f, 0.1f, 0.1f), (t - 0.5f) * 2.0f);
}

} // namespace sightline::ui
