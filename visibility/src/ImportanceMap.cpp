#include "visibility/ImportanceMap.h"

#include <algorithm>
#include <bit>
#include <numeric>
#include <stdexcept>
#include <string>

#include "base/Error.h"

namespace sightline {

double ImportanceMap::mean() const
{
    if (values.empty())
        return 0.0;
    return std::accumulate(values.begin(), values.end(), 0.0) / double(values.size());
}

ImportanceMap receiverImportance(const HiddenSampleMap& map)
{
    ImportanceMap result(map.receiverNa(), map.receiverNb());
    const double inverseS = 1.0 / double(map.sourceCount());
    for (int j = 0; j < map.receiverCount(); ++j)
        result.values[std::size_t(j)] = float(1.0 - double(map.blockedCount(j)) * inverseS);
    return result;
}

ImportanceMap sourceImportance(const HiddenSampleMap& map, int sourceNa, int sourceNb)
{
    if (sourceNa < 1 || sourceNb < 1 || sourceNa * sourceNb != map.sourceCount())
        throw std::invalid_argument("sourceImportance: the source grid does not match the map's source count");
    // Count blocked rays per source bit by walking only the set bits: most maps are sparse in one
    // of blocked/visible, and 70% blocked still costs one countr_zero per blocked ray.
    std::vector<std::uint32_t> blocked(std::size_t(map.sourceCount()), 0);
    for (int j = 0; j < map.receiverCount(); ++j) {
        const auto row = map.row(j);
        for (std::size_t w = 0; w < row.size(); ++w) {
            for (std::uint64_t bits = row[w]; bits != 0; bits &= bits - 1)
                ++blocked[w * 64 + std::size_t(std::countr_zero(bits))];
        }
    }
    ImportanceMap result(sourceNa, sourceNb);
    const double inverseR = 1.0 / double(map.receiverCount());
    for (std::size_t i = 0; i < blocked.size(); ++i)
        result.values[i] = float(1.0 - double(blocked[i]) * inverseR);
    return result;
}

ImportanceStatistic parseImportanceStatistic(std::string_view name)
{
    if (name == "mean")
        return ImportanceStatistic::Mean;
    if (name == "max")
        return ImportanceStatistic::Maximum;
    if (name == "ever")
        return ImportanceStatistic::EverVisible;
    throw Error("unknown statistic '" + std::string(name) + "' (use mean, max or ever)");
}

const char* toString(ImportanceStatistic statistic)
{
    switch (statistic) {
    case ImportanceStatistic::Mean: return "mean";
    case ImportanceStatistic::Maximum: return "max";
    case ImportanceStatistic::EverVisible: return "ever";
    }
    return "?";
}

void ImportanceAccumulator::add(const ImportanceMap& frame)
{
    if (frames_ == 0) {
        na_ = frame.na;
        nb_ = frame.nb;
        sum_.assign(frame.values.size(), 0.0);
        maximum_.assign(frame.values.size(), 0.0f);
        ever_.assign(frame.values.size(), 0);
    } else if (frame.na != na_ || frame.nb != nb_) {
        throw std::invalid_argument("ImportanceAccumulator: the sample grid changed; reset first");
    }
    for (std::size_t k = 0; k < frame.values.size(); ++k) {
        const float value = frame.values[k];
        sum_[k] += double(value);
        maximum_[k] = std::max(maximum_[k], value);
        ever_[k] |= std::uint8_t(value > 0.0f);
    }
    ++frames_;
}

void ImportanceAccumulator::reset()
{
    frames_ = 0;
    na_ = nb_ = 0;
    sum_.clear();
    maximum_.clear();
    ever_.clear();
}

ImportanceMap ImportanceAccumulator::result(ImportanceStatistic statistic) const
{
    if (frames_ == 0)
        return {};
    ImportanceMap map(na_, nb_);
    for (std::size_t k = 0; k < map.values.size(); ++k) {
        switch (statistic) {
        case ImportanceStatistic::Mean: map.values[k] = float(sum_[k] / double(frames_)); break;
        case ImportanceStatistic::Maximum: map.values[k] = maximum_[k]; break;
        case ImportanceStatistic::EverVisible: map.values[k] = ever_[k] ? 1.0f : 0.0f; break;
        }
    }
    return map;
}

} // namespace sightline
