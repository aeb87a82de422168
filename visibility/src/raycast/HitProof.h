#pragma once
// Internal to the proven ray caster (ProvenRayCaster.h): when a hit that Embree's float triangle
// test reports proves, from the reported numbers alone, that the exact segment crosses the exact
// triangle as docs/design.md §2's test (ExactSegment.h) decides it.
//
// Embree (3.13, Triangle4 leaves, kernels/geometry/triangle_intersector_moeller.h) stores v0,
// e1 = fl(v0 - v1), e2 = fl(v2 - v0) and computes, for a float ray O + t D,
//     C = fl(v0 - O), R = fl(C x D), Ng = fl(e2 x e1), den = fl(Ng . D),
//     U = fl(R . e2), V = fl(R . e1), T = fl(Ng . C)      (U, V, T sign-flipped by den's sign)
// and reports u = U / |den|, v = V / |den|, t = T / |den| (an approximate reciprocal) and Ng. In
// exact arithmetic on the exact segment P -> Q and the exact triangle (a, b, c) the same four
// numbers decide the contract's question: the segment crosses the triangle strictly inside and
// strictly between its ends iff U > 0, V > 0, |den| - U - V > 0 and 0 < T < |den|.
//
// Each computed number differs from its exact counterpart by at most (first order in the float
// unit roundoff u = 2^-24, with |C| <= Cb, |O|, |D|, edges <= L, and dv the largest rounding of a
// vertex into the caster's local frame; triangle inequality on each rounding of the sums and
// products above, O and D rounded from the exact ends in double):
//     eps_U = eps_V = |D| (L (9u Cb + u |O| + dv) + 2 dv Cb)
//     eps_N = 5u L^2 + 4 dv L                                   (Ng's rounding and the edges')
//     eps_den = |D| (4u |Ng| + eps_N)
//     eps_T = Cb (4u |Ng| + eps_N) + |Ng| (dv + u |O|)
// (R: 3u|C||D| for its rounding, (u|C| + u|O| + dv)|D| from C's and O's, u|C||D| from D's; U:
// 3u|R|L for the dot product, |dR| L, and |C||D| (2dv + uL) from e2's rounding. den and T:
// 3u|Ng| for the dot product plus Ng's and the ray's.) Cb = |D| + 2L: t <= 1, and a point inside
// the triangle lies within L of v0. The reported values carry Embree's reciprocal (relative error
// below rho = 2^-20), and |den| is recomputed here from the reported Ng (within 6u|Ng||D| of
// Embree's). A hit whose every margin exceeds its bound (plus 2^-10 for the float arithmetic of
// the bound itself) is a crossing in exact arithmetic with margins far above double rounding, so
// the contract's double test says the same: the caster answers bit for bit as the reference.
// Everything else goes to that test. NaN and infinities fail every comparison: not proven.

#include <algorithm>
#include <cmath>

namespace sightline::raycast {

/// What the proof reads of one reported hit: the float ray (local frame; the segment is
/// t in [0, 1]) and Embree's Ng, u, v, t.
struct ReportedHit {
    float ox, oy, oz;
    float dx, dy, dz;
    float nx, ny, nz;
    float u, v, t;
};

/// Whether the hit is a crossing by the contract. `edge` bounds the triangle's edges (its size
/// class); `vertexError` is the largest rounding of a vertex into the local frame.
inline bool provenCrossing(const ReportedHit& h, float edge, float vertexError)
{
    constexpr float u = 0x1p-24f, rho = 0x1p-20f, slack = 1.0f + 0x1p-10f;
    constexpr float endMargin = 2e-8f;   // twice kEndMarginMetres: the test's own distance from the ends
    const float L = edge, dv = vertexError;
    const float D = std::sqrt(h.dx * h.dx + h.dy * h.dy + h.dz * h.dz) * (1.0f + 0x1p-20f);
    const float N = std::sqrt(h.nx * h.nx + h.ny * h.ny + h.nz * h.nz) * (1.0f + 0x1p-20f);
    const float O = std::sqrt(h.ox * h.ox + h.oy * h.oy + h.oz * h.oz) * (1.0f + 0x1p-20f);
    const float Cb = D + 2.0f * L;
    const float epsU = slack * D * (L * (9.0f * u * Cb + u * O + dv) + 2.0f * dv * Cb);
    const float epsN = 5.0f * u * L * L + 4.0f * dv * L;
    const float epsDen = slack * D * (4.0f * u * N + epsN);
    const float epsT = slack * (Cb * (4.0f * u * N + epsN) + N * (dv + u * O));
    const float den = std::abs(h.nx * h.dx + h.ny * h.dy + h.nz * h.dz);
    const float low = den - 6.0f * u * N * D, high = (den + 6.0f * u * N * D + epsDen) * slack;
    const float inside = std::min(h.u, h.v);
    const float third = 1.0f - (h.u + h.v) * (1.0f + rho);
    // Lower bounds on the exact T and |den| - T, over an upper bound on |den|, times |D|: the
    // crossing's distances from both ends, which must exceed the test's end margin.
    const float fromStart = (h.t * low * (1.0f - rho) - epsT) / high * (D * (1.0f - 0x1p-18f));
    const float fromEnd = (low * (1.0f - h.t * (1.0f + rho)) - epsT - epsDen) / high * (D * (1.0f - 0x1p-18f));
    // Without short-circuits, so that a loop over a packet's lanes vectorises.
    return (low > 0.0f) & (inside * low * (1.0f - rho) > epsU) & (third * low > epsDen + 2.0f * epsU) &
           (fromStart > endMargin) & (fromEnd > endMargin);
}

} // namespace sightline::raycast
