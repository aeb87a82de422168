#pragma once
// A coarse-occluder sweep (project/CoarseSweep.h) as the chart's data (report/CoarseChart.h): the
// one place both meet, for the editor's dialog and the CLI's PNG.

#include "project/CoarseSweep.h"
#include "report/CoarseChart.h"

namespace sightline::ui {

inline CoarseChartData coarseChartData(const CoarseSweep& sweep)
{
    CoarseChartData data;
    data.full = {sweep.triangles, sweep.ms, 0.0};
    const double rays = double(sweep.rays > 0 ? sweep.rays : 1);
    for (const CoarseSweepPoint& p : sweep.points)
        data.coarse.push_back({p.triangles, p.ms, 100.0 * double(p.disagreeing()) / rays});
    return data;
}

} // namespace sightline::ui
