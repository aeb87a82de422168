#pragma once
// How the command-line tools time their work: wall-clock milliseconds, and the median of repeated
// runs after a warm-up (as `bench` times).

#include <algorithm>
#include <chrono>
#include <vector>

namespace sightline::cli {

inline double millisecondsSince(std::chrono::steady_clock::time_point start)
{
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

/// Without --repeat (`repeat` 0), runs `sample` once and returns its time in milliseconds: what
/// one call costs cold, as a script calling the CLI once sees it. With --repeat N, runs it once to
/// warm up (thread pools, page faults, shader compilation), then N timed times, and returns their
/// lower median.
template <typename Sample>
double timeSampling(int repeat, Sample&& sample)
{
    if (repeat > 0)
        sample();
    std::vector<double> times;
    for (int k = 0; k < std::max(repeat, 1); ++k) {
        const auto start = std::chrono::steady_clock::now();
        sample();
        times.push_back(millisecondsSince(start));
    }
    std::sort(times.begin(), times.end());
    return times[(times.size() - 1) / 2];
}

} // namespace sightline::cli
