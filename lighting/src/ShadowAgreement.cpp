#include "lighting/ShadowAgreement.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "TaskArena.h"
#include "lighting/LightEmission.h"
#include "base/Error.h"

namespace sightline {

EmitterBits::EmitterBits(std::size_t pointCount, std::size_t emitterCount)
    : points(pointCount), emitters(emitterCount), words((emitterCount + 31) / 32), bits(pointCount * words, 0u)
{
}

EmitterBits exactEmitterBits(const LightingScene& scene, const std::vector<Light>& lights,
                             std::span<const ShadingPoint> points, int threads)
{
    const std::vector<Emitter> emitters = lightEmitters(lights);
    EmitterBits exact(points.size(), emitters.size());
    inArena(threads, [&] {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size(), 16), [&](const auto& range) {
            std::vector<glm::dvec3> ends;
            std::vector<std::uint32_t> which;
            std::vector<std::uint8_t> blocked;
            for (std::size_t j = range.begin(); j != range.end(); ++j) {
                const ShadingPoint& p = points[j];
                ends.clear();
                which.clear();
                for (std::size_t e = 0; e < emitters.size(); ++e) {
                    const Light& light = lights[emitters[e].light];
                    if (emitterTerm(light, emitters[e].position, p.position, p.normal) <= 0.0)
                        continue;
                    ends.push_back(light.type == LightType::Directional ? scene.reach().end(light, p.position)
                                                                       : emitters[e].position);
                    which.push_back(std::uint32_t(e));
                }
                blocked.assign(ends.size(), 0);
                scene.rays().segmentsBlocked(p.position, ends, blocked.data());
                for (std::size_t k = 0; k < which.size(); ++k)
                    if (!blocked[k])
                        exact.setLit(j, which[k]);
            }
        });
    });
    return exact;
}

ShadowAgreement compareEmitterBits(const std::vector<Light>& lights, std::span<const ShadingPoint> points,
                                   const EmitterBits& answer, const EmitterBits& exact)
{
    const std::vector<Emitter> emitters = lightEmitters(lights);
    if (answer.points != points.size() || exact.points != points.size() || answer.emitters != emitters.size() ||
        exact.emitters != emitters.size())
        throw Error("shadow agreement: the bits do not cover these points and lights");
    ShadowAgreement agreement;
    for (std::size_t j = 0; j < points.size(); ++j)
        for (std::size_t e = 0; e < emitters.size(); ++e) {
            if (emitterTerm(lights[emitters[e].light], emitters[e].position, points[j].position, points[j].normal) <= 0.0)
                continue;
            ++agreement.pairs;
            const bool a = answer.lit(j, e), x = exact.lit(j, e);
            agreement.falseLit += a && !x;
            agreement.falseShadowed += !a && x;
        }
    return agreement;
}

} // namespace sightline
