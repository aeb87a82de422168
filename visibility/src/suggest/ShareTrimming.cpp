#include "visibility/suggest/ShareTrimming.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <numeric>

namespace sightline::suggest {

namespace {

/// Sutherland-Hodgman against one half-plane {x : d . x <= h}.
std::vector<Point2> clipped(const std::vector<Point2>& polygon, Point2 d, double h)
{
    std::vector<Point2> out;
    out.reserve(polygon.size() + 1);
    for (std::size_t i = 0, n = polygon.size(); i < n; ++i) {
        const Point2 a = polygon[i], b = polygon[(i + 1) % n];
        const double fa = glm::dot(d, a) - h, fb = glm::dot(d, b) - h;
        if (fa <= 0.0)
            out.push_back(a);
        if ((fa < 0.0 && fb > 0.0) || (fa > 0.0 && fb < 0.0))
            out.push_back(a + (b - a) * (fa / (fa - fb)));
    }
    return out;
}

/// Everything the greedy step needs about one support line.
struct SupportLine {
    Point2 direction;
    std::vector<std::uint32_t> order;   ///< the points farthest along `direction`, farthest first
    std::size_t first = 0;              ///< first entry of `order` still kept
};

/// Steps the greedy takes at most: each costs a clip of the polygon per line, and where every band
/// costs more points than the budget holds (a tight cluster and far stragglers) the steps fall
/// back to single points. Stopping early keeps more points: a larger shape, still a valid one.
constexpr int kMaxSteps = 20000;

class Trimmer {
public:
    /// `weights` empty: each point weighs 1. `budget`: the weight that may be left out.
    Trimmer(std::span<const Point2> points, std::span<const double> weights, double budget, std::span<const Point2> directions)
        : points_(points), weights_(weights), kept_(points.size(), 1), budget_(budget)
    {
        Point2 lo{std::numeric_limits<double>::infinity()}, hi{-std::numeric_limits<double>::infinity()};
        for (const Point2& p : points) {
            lo = glm::min(lo, p);
            hi = glm::max(hi, p);
        }
        const double diagonal = glm::length(hi - lo);
        band_ = 1e-3 * diagonal;
        box_ = {lo - diagonal - 1.0, Point2{hi.x + diagonal + 1.0, lo.y - diagonal - 1.0}, hi + diagonal + 1.0,
                Point2{lo.x - diagonal - 1.0, hi.y + diagonal + 1.0}};
        // Only the budget + 1 farthest points along a line can ever be passed by it; a cap keeps
        // memory bounded when the budget is most of a million points (a line that runs out of
        // entries just stops moving: more points are kept, never fewer).
        const std::size_t memoryCap = std::max<std::size_t>(4096, 8'000'000 / std::max<std::size_t>(directions.size(), 1));
        const std::size_t cap = weights.empty() ? std::min({std::size_t(budget_) + 1, points.size(), memoryCap})
                                                : std::min(points.size(), memoryCap);
        std::vector<std::uint32_t> all(points.size());
        for (const Point2& d : directions) {
            std::iota(all.begin(), all.end(), 0u);
            const auto farther = [&](std::uint32_t a, std::uint32_t b) { return glm::dot(d, points[a]) > glm::dot(d, points[b]); };
            std::nth_element(all.begin(), all.begin() + std::ptrdiff_t(cap - 1), all.end(), farther);
            SupportLine line{d, std::vector<std::uint32_t>(all.begin(), all.begin() + std::ptrdiff_t(cap)), 0};
            std::sort(line.order.begin(), line.order.end(), farther);
            lines_.push_back(std::move(line));
        }
    }

    std::vector<char> run()
    {
        std::vector<Point2> polygon = supportPolygon();
        double area = polygonArea(polygon);
        for (int steps = 0; budget_ > 0 && steps < kMaxSteps; ++steps) {
            Step best;
            for (std::size_t k = 0; k < lines_.size(); ++k) {
                Step step = stepFor(k, band_);
                if (step.cost > budget_)
                    step = stepFor(k, 0.0);
                if (step.end == 0 || step.cost > budget_)
                    continue;
                step.gain = area - polygonArea(clipped(polygon, lines_[k].direction, step.newSupport));
                if (step.gain > 0.0 && (best.end == 0 || step.gain * best.cost > best.gain * step.cost)) {
                    best = step;
                    best.line = k;
                }
            }
            if (best.end == 0)
                break;
            SupportLine& line = lines_[best.line];
            for (std::size_t i = line.first; i < best.end; ++i)
                kept_[line.order[i]] = 0;
            budget_ -= best.cost;
            polygon = supportPolygon();
            area = polygonArea(polygon);
        }
        return std::move(kept_);
    }

private:
    struct Step {
        std::size_t line = 0;
        double cost = 0.0;      ///< the weight of the kept points it leaves out
        std::size_t end = 0;    ///< entries of the line's order it passes (0: no step)
        double newSupport = 0.0;
        double gain = 0.0;      ///< square metres saved
    };

    double weight(std::uint32_t point) const { return weights_.empty() ? 1.0 : weights_[point]; }

    double along(const SupportLine& line, std::size_t i) const { return glm::dot(line.direction, points_[line.order[i]]); }

    void skipLeftOut(SupportLine& line) const
    {
        while (line.first < line.order.size() && !kept_[line.order[line.first]])
            ++line.first;
    }

    /// Pulling line k past every kept point within `band` of its farthest one.
    Step stepFor(std::size_t k, double band)
    {
        SupportLine& line = lines_[k];
        skipLeftOut(line);
        Step step;
        if (line.first == line.order.size())
            return step;
        const double limit = along(line, line.first) - band;
        std::size_t i = line.first;
        double cost = 0.0;
        for (; i < line.order.size(); ++i) {
            const bool keptHere = kept_[line.order[i]] != 0;
            if (keptHere && along(line, i) < limit)
                break;
            if (keptHere)
                cost += weight(line.order[i]);
        }
        if (i == line.order.size())
            return step;   // where the line would stop is past the entries kept for it
        step.cost = cost;
        step.end = i;
        step.newSupport = along(line, i);
        return step;
    }

    /// The intersection of the support half-planes at their current places.
    std::vector<Point2> supportPolygon()
    {
        std::vector<Point2> polygon(box_.begin(), box_.end());
        for (SupportLine& line : lines_) {
            skipLeftOut(line);
            if (line.first < line.order.size())
                polygon = clipped(polygon, line.direction, along(line, line.first));
        }
        return polygon;
    }

    std::span<const Point2> points_;
    std::span<const double> weights_;
    std::vector<char> kept_;
    double budget_;
    double band_ = 0.0;
    std::array<Point2, 4> box_;
    std::vector<SupportLine> lines_;
};

} // namespace

std::vector<Point2> evenDirections(int count, double angle)
{
    std::vector<Point2> directions;
    for (int k = 0; k < count; ++k) {
        const double a = angle + 2.0 * std::numbers::pi * k / count;
        directions.push_back({std::cos(a), std::sin(a)});
    }
    return directions;
}

std::vector<char> trimToShare(std::span<const Point2> points, std::size_t keep, std::span<const Point2> directions)
{
    if (keep >= points.size() || directions.empty())
        return std::vector<char>(points.size(), 1);
    return Trimmer(points, {}, double(points.size() - keep), directions).run();
}

std::vector<char> trimToWeight(std::span<const Point2> points, std::span<const double> weights, double keepWeight,
                               std::span<const Point2> directions)
{
    double total = 0.0;
    for (const double w : weights)
        total += w;
    if (keepWeight >= total || directions.empty())
        return std::vector<char>(points.size(), 1);
    return Trimmer(points, weights, total - keepWeight, directions).run();
}

} // namespace sightline::suggest
