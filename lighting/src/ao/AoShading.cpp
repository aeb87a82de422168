#include "lighting/ao/AoShading.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

namespace sightline {

namespace {
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
}

AoRelighter::AoRelighter(const VisibilityMatrix& matrix, const AoPoints& points, int k, AoWeighting weighting)
    : matrix_(matrix), points_(points), set_(aoDirections(k)), k_(k), weighting_(weighting)
{
    if (matrix.points() != points.size() || matrix.capacity() < k)
        throw std::invalid_argument("AoRelighter: the matrix does not match the points or k");
    inverseWeightSum_.assign(points.size(), 0.0f);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size(), 1024), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t i = r.begin(); i < r.end(); ++i) {
            if (points.status[i] != AoPointStatus::Ok)
                continue;
            double sum = 0.0;
            for (int j = 0; j < k; ++j)
                sum += aoWeight(set_, j, points.normals[i], weighting);
            inverseWeightSum_[i] = sum > 0.0 ? float(1.0 / sum) : 0.0f;
        }
    });
}

std::vector<glm::vec3> AoRelighter::shade(const std::vector<glm::vec3>& radiance, int threads) const
{
    if (int(radiance.size()) < k_)
        throw std::invalid_argument("AoRelighter::shade: fewer radiance values than directions");
    std::vector<glm::vec3> out(points_.size());
    const int words = (k_ + 63) / 64;
    // The weight of a set bit: the cell moment (or direction) dotted with the normal.
    const std::vector<glm::vec3>& axes = weighting_ == AoWeighting::SolidAngle ? set_.moment : set_.directions;
    const bool plain = weighting_ == AoWeighting::PlainCount;
    tbb::task_arena arena(threads > 0 ? threads : tbb::task_arena::automatic);
    arena.execute([&] {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points_.size(), 512), [&](const tbb::blocked_range<std::size_t>& r) {
            for (std::size_t i = r.begin(); i < r.end(); ++i) {
                if (points_.status[i] != AoPointStatus::Ok) {
                    out[i] = glm::vec3(kNaN);
                    continue;
                }
                const glm::vec3 n = points_.normals[i];
                const std::uint64_t* row = matrix_.row(i);
                float cr = 0.0f, cg = 0.0f, cb = 0.0f;
                for (int w = 0; w < words; ++w) {
                    std::uint64_t bits = row[w];
                    if (w == words - 1 && (k_ & 63))
                        bits &= (std::uint64_t(1) << (k_ & 63)) - 1;
                    while (bits) {
                        const int j = w * 64 + std::countr_zero(bits);
                        bits &= bits - 1;
                        // Set bits face the point (only those are tested); cells the horizon cuts
                        // take the general weight (aoWeight), the rest the cheap dot product.
                        const glm::vec3& a = axes[std::size_t(j)];
                        float weight = n.x * a.x + n.y * a.y + n.z * a.z;
                        const glm::vec3& dj = set_.directions[std::size_t(j)];
                        const float c = n.x * dj.x + n.y * dj.y + n.z * dj.z;
                        if (plain)
                            weight = c;
                        else if (c * c < (1.0f - c * c) * set_.cellRadius[std::size_t(j)] * set_.cellRadius[std::size_t(j)])
                            weight = aoWeight(set_, j, n, weighting_);
                        weight = weight > 0.0f ? weight : 0.0f;
                        const glm::vec3& l = radiance[std::size_t(j)];
                        cr += weight * l.r;
                        cg += weight * l.g;
                        cb += weight * l.b;
                    }
                }
                const float s = inverseWeightSum_[i];
                out[i] = glm::vec3(cr * s, cg * s, cb * s);
            }
        });
    });
    return out;
}

std::vector<float> ambientOcclusion(const VisibilityMatrix& matrix, const AoPoints& points, int k, AoWeighting weighting)
{
    const AoRelighter relighter(matrix, points, k, weighting);
    const std::vector<glm::vec3> white(std::size_t(k), glm::vec3(1.0f));
    const std::vector<glm::vec3> c = relighter.shade(white);
    std::vector<float> ao(c.size());
    for (std::size_t i = 0; i < c.size(); ++i)
        ao[i] = std::isnan(c[i].r) ? kNaN : std::min(1.0f, c[i].r);
    return ao;
}

} // namespace sightline
