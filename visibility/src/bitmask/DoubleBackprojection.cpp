#include "DoubleBackprojection.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "SampleRange.h"
#include "TableMode.h"
#include "visibility/Patch.h"

namespace sightline::bitmask {

namespace {

/// The widening of an interval end: relative to the end itself (an occluder reaching near a
/// receiver sample projects to 1e9 and more, and a slack relative to that would move its near
/// edges by millimetres).
double lower(double x) { return x - 1e-12 * (1.0 + std::abs(x)); }
double upper(double x) { return x + 1e-12 * (1.0 + std::abs(x)); }

/// Where row t = tb crosses the edge (sa, ta) - (sb, tbEnd) (ta < tbEnd), kept within the edge's s.
double edgeCrossing(double tb, double sa, double ta, double sb, double tbEnd)
{
    const double x = sa + (tb - ta) * ((sb - sa) / (tbEnd - ta));
    return std::clamp(x, std::min(sa, sb), std::max(sa, sb));
}

/// The common case, a backprojected triangle with some height: a scanline walk. Sorted by t, rows
/// below the middle vertex lie between the long edge (0-2) and edge 0-1, the others between the
/// long edge and edge 1-2; no per-row arrays, no per-edge row ranges.
void triangleRows(const Shaft& shaft, const double* ps, const double* pt, int b0, int b1, std::uint64_t* mask)
{
    int i0 = 0, i1 = 1, i2 = 2;
    if (pt[i0] > pt[i1])
        std::swap(i0, i1);
    if (pt[i1] > pt[i2])
        std::swap(i1, i2);
    if (pt[i0] > pt[i1])
        std::swap(i0, i1);
    const double s0 = ps[i0], t0 = pt[i0], s1 = ps[i1], t1 = pt[i1], s2 = ps[i2], t2 = pt[i2];
    for (int b = b0; b <= b1; ++b) {
        const double tb = (b + 0.5) / shaft.nb;
        const double xLong = edgeCrossing(tb, s0, t0, s2, t2);
        double xShortLo, xShortHi;
        if (tb < t1 && t1 > t0) {
            xShortLo = xShortHi = edgeCrossing(tb, s0, t0, s1, t1);
        } else if (t2 > t1) {
            xShortLo = xShortHi = edgeCrossing(tb, s1, t1, s2, t2);
        } else {   // top edge along the row: both of its ends count
            xShortLo = std::min(s1, s2);
            xShortHi = std::max(s1, s2);
        }
        int a0, a1;
        sampleRange(lower(std::min(xLong, xShortLo)), upper(std::max(xLong, xShortHi)), shaft.na, a0, a1);
        if (a0 <= a1)
            setBitRange(mask, b * shaft.na + a0, b * shaft.na + a1);
    }
}

} // namespace

void backproject(const Shaft& shaft, const Occluder& occluder, Path path, int j, std::uint64_t* row)
{
    const glm::dvec3& r = shaft.receiverInSource[std::size_t(j)];
    const glm::dvec2& shift = shaft.jitterShift[std::size_t(j)];
    if (path != Path::Clip) {
        backprojectPolygon(shaft, occluder.vertices.data(), occluder.count, r, shift, row,
                           shaft.parallel ? occluder.factor.data() : nullptr);
        return;
    }
    if (occluder.maxD < Shaft::clipDistance(r.z)) {   // nothing to clip for this sample
        backprojectPolygon(shaft, occluder.vertices.data(), occluder.count, r, shift, row, nullptr);
        return;
    }
    const ClippedPolygon local = clippedFor(occluder, r.z);
    if (local.count >= 3)
        backprojectPolygon(shaft, local.vertices.data(), local.count, r, shift, row, nullptr);
}

ClippedPolygon clippedFor(const Occluder& occluder, double d)
{
    ClippedPolygon local;
    local.count = occluder.count;
    std::copy_n(occluder.vertices.begin(), occluder.count, local.vertices.begin());
    clipPolygon(local, glm::dvec3(0, 0, -1), -Shaft::clipDistance(d));
    return local;
}

void backprojectPolygon(const Shaft& shaft, const glm::dvec3* vertices, int count, const glm::dvec3& r,
                        const glm::dvec2& shift, std::uint64_t* mask, const double* factors)
{
    // Backprojection onto the source plane, in source (s, t).
    std::array<double, ClippedPolygon::kMaxVertices> ps, pt;
    double tMin = 1e300, tMax = -1e300;
    for (int i = 0; i < count; ++i) {
        const glm::dvec3& x = vertices[i];
        const double k = factors ? factors[i] : r.z / (r.z - x.z);
        ps[std::size_t(i)] = r.x + (x.x - r.x) * k - shift.x;
        pt[std::size_t(i)] = r.y + (x.y - r.y) * k - shift.y;
        tMin = std::min(tMin, pt[std::size_t(i)]);
        tMax = std::max(tMax, pt[std::size_t(i)]);
    }
    if (shaft.table) {
        tableMask(*shaft.table, ps.data(), pt.data(), count, mask);
        return;
    }
    const int na = shaft.na, nb = shaft.nb;
    int b0, b1;
    sampleRange(lower(tMin), upper(tMax), nb, b0, b1);
    if (b0 > b1)
        return;
    if (count == 3 && tMax > tMin) {
        triangleRows(shaft, ps.data(), pt.data(), b0, b1, mask);
        return;
    }
    // Each row's line t = tb meets the convex polygon in one interval [lo, hi]. Walk every edge
    // over just the rows it spans (O(rows + edges), not O(rows x edges)).
    double lo[kMaxSourceSamples], hi[kMaxSourceSamples];
    std::fill(lo + b0, lo + b1 + 1, 1e300);
    std::fill(hi + b0, hi + b1 + 1, -1e300);
    for (int i = 0, k = count - 1; i < count; k = i++) {
        const double t0 = pt[std::size_t(k)], t1 = pt[std::size_t(i)];
        const double s0 = ps[std::size_t(k)], s1 = ps[std::size_t(i)];
        int r0, r1;
        sampleRange(lower(std::min(t0, t1)), upper(std::max(t0, t1)), nb, r0, r1);
        r0 = std::max(r0, b0);
        r1 = std::min(r1, b1);
        if (r0 > r1)
            continue;
        if (t0 == t1) {   // along a row: both ends count
            lo[r0] = std::min({lo[r0], s0, s1});
            hi[r0] = std::max({hi[r0], s0, s1});
            continue;
        }
        // From the lower end, whichever way the polygon walks the edge.
        const bool up = t0 < t1;
        const double sa = up ? s0 : s1, ta = up ? t0 : t1, sb = up ? s1 : s0, tbEnd = up ? t1 : t0;
        for (int row = r0; row <= r1; ++row) {
            const double x = edgeCrossing((row + 0.5) / nb, sa, ta, sb, tbEnd);
            lo[row] = std::min(lo[row], x);
            hi[row] = std::max(hi[row], x);
        }
    }
    for (int b = b0; b <= b1; ++b) {
        int a0, a1;
        sampleRange(lower(lo[b]), upper(hi[b]), na, a0, a1);
        if (a0 <= a1)
            setBitRange(mask, b * na + a0, b * na + a1);
    }
}

} // namespace sightline::bitmask
