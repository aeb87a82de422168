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
    : points_(points), k_(k)
{
    if (matrix.points() != points.size() || matrix.capacity() < k)
        throw std::invalid_argument("AoRelighter: the matrix does not match the points or k");
    const AoDirectionSet& set = aoDirections(k);
    const int words = (k + 63) / 64;
    auto rowBits = [&](std::size_t i, int w) {
        std::uint64_t bits = matrix.row(i)[w];
        if (w == words - 1 && (k & 63))
            bits &= (std::uint64_t(1) << (k & 63)) - 1;
        return bits;
    };
    start_.assign(points.size() + 1, 0);
    for (std::size_t i = 0; i < points.size(); ++i) {
        std::uint32_t n = 0;
        if (points.status[i] == AoPointStatus::Ok)
            for (int w = 0; w < words; ++w)
                n += unsigned(std::popcount(rowBits(i, w)));
        start_[i + 1] = start_[i] + n;
    }
    direction_.resize(start_.back());
    weight_.resize(start_.back());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size(), 512), [&](const tbb::blocked_range<std::size_t>& r) {
        std::vector<float> w(static_cast<std::size_t>(k));
        for (std::size_t i = r.begin(); i < r.end(); ++i) {
            if (points.status[i] != AoPointStatus::Ok)
                continue;
            double sum = 0.0;
            for (int j = 0; j < k; ++j)
                sum += w[std::size_t(j)] = aoWeight(set, j, points.normals[i], weighting);
            const float inverse = sum > 0.0 ? float(1.0 / sum) : 0.0f;
            std::uint32_t e = start_[i];
            for (int word = 0; word < words; ++word)
                for (std::uint64_t bits = rowBits(i, word); bits; bits &= bits - 1) {
                    const int j = word * 64 + std::countr_zero(bits);
                    direction_[e] = std::uint16_t(j);
                    weight_[e++] = w[std::size_t(j)] * inverse;
                }
        }
    });
}

std::vector<glm::vec3> AoRelighter::shade(const std::vector<glm::vec3>& radiance, int threads) const
{
    if (int(radiance.size()) < k_)
        throw std::invalid_argument("AoRelighter::shade: fewer radiance values than directions");
    std::vector<glm::vec3> out(points_.size());
    auto work = [&] {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points_.size(), 2048), [&](const tbb::blocked_range<std::size_t>& r) {
            for (std::size_t i = r.begin(); i < r.end(); ++i) {
                if (points_.status[i] != AoPointStatus::Ok) {
                    out[i] = glm::vec3(kNaN);
                    continue;
                }
                float cr = 0.0f, cg = 0.0f, cb = 0.0f;
                for (std::uint32_t e = start_[i]; e < start_[i + 1]; ++e) {
                    const glm::vec3& l = radiance[direction_[e]];
                    const float w = weight_[e];
                    cr += w * l.r;
                    cg += w * l.g;
                    cb += w * l.b;
                }
                out[i] = glm::vec3(cr, cg, cb);
            }
        });
    };
    if (threads > 0) {
        tbb::task_arena arena(threads);
        arena.execute(work);
    } else {
        work();
    }
    return out;
}

std::vector<float> ambientOcclusion(const VisibilityMatrix& matrix, const AoPoints& points, int k, AoWeighting weighting)
{
    if (matrix.points() != points.size() || matrix.capacity() < k)
        throw std::invalid_argument("ambientOcclusion: the matrix does not match the points or k");
    // Directly, without AoRelighter's per-bit storage (a level's texels at k = 1026 would take
    // hundreds of MB): the weights are recomputed per point.
    const AoDirectionSet& set = aoDirections(k);
    std::vector<float> ao(points.size(), kNaN);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size(), 512), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t i = r.begin(); i < r.end(); ++i) {
            if (points.status[i] != AoPointStatus::Ok)
                continue;
            double all = 0.0, seen = 0.0;
            for (int j = 0; j < k; ++j) {
                const float w = aoWeight(set, j, points.normals[i], weighting);
                all += w;
                if (matrix.visible(i, j))
                    seen += w;
            }
            ao[i] = all > 0.0 ? float(std::min(1.0, seen / all)) : kNaN;
        }
    });
    return ao;
}

} // namespace sightline
