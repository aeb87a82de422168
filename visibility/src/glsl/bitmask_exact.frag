// GlBitmaskSampler.cpp, exact mode: the CPU float kernel's filtered predicate (BitmaskRows.h), one
// receiver sample per fragment. Differences of float pairs; per vertex and axis the bound
//     8 |x - r| + (|r| + 6 |p|) / k
// in float epsilons, a little wider than the CPU's (6, 4) for the GPU's 2.5-ulp division, and
// the unit 1.25 times the float epsilon. A fragment over the budget flags its sample for the
// CPU's double path and writes nothing. The placeholder at the end of main() becomes the writes
// of the mask to the render targets.
layout(std430, binding = 2) buffer Flags { uint flags[]; };
uniform vec2 uMetres;       // |u|, |v| of the source
uniform float uBudget;      // metres between ray and occluder boundary
const float kUnit = 1.25 / 16777216.0;

void main()
{
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    int j = pixel.y * uReceiverGrid.x + pixel.x;
    int n = polygons[vPolygon].info.x;
    bool closed = polygons[vPolygon].info.y != 0;
    bool sharedFactor = polygons[vPolygon].info.z != 0;
    precise vec3 r = samples[3 * j].xyz;
    precise vec3 rLo = samples[3 * j + 1].xyz;
    vec2 shift = samples[3 * j + 2].xy;
    float ps[8], pt[8], magnitude[8], factor[8], rayS[8], rayT[8];
    float tMin = 1e38, tMax = -1e38, rayMaxS = 0.0, rayMaxT = 0.0;
    for (int i = 0; i < n; ++i) {
        precise vec4 hi = polygons[vPolygon].hi[i];
        precise vec3 lo = polygons[vPolygon].lo[i].xyz;
        precise float k = sharedFactor ? hi.w : r.z / ((r.z - hi.z) + (rLo.z - lo.z));
        precise float dS = (hi.x - r.x) + (lo.x - rLo.x);
        precise float dT = (hi.y - r.y) + (lo.y - rLo.y);
        ps[i] = fma(dS, k, r.x) - shift.x;
        pt[i] = fma(dT, k, r.y) - shift.y;
        tMin = min(tMin, pt[i]);
        tMax = max(tMax, pt[i]);
        magnitude[i] = abs(ps[i]) + abs(pt[i]);
        factor[i] = k;
        rayS[i] = 8.0 * abs(dS) + (abs(r.x) + 6.0 * abs(ps[i])) / k;
        rayT[i] = 8.0 * abs(dT) + (abs(r.y) + 6.0 * abs(pt[i])) / k;
        rayMaxS = max(rayMaxS, rayS[i]);
        rayMaxT = max(rayMaxT, rayT[i]);
    }
    float eS = 0.0, eT = 0.0, kMin = 1e38, sMin = 1e38, sMax = -1e38;
    for (int i = 0; i < n; ++i) {
        eS = max(eS, rayS[i] * factor[i]);
        eT = max(eT, rayT[i] * factor[i]);
        kMin = min(kMin, factor[i]);
        sMin = min(sMin, ps[i]);
        sMax = max(sMax, ps[i]);
    }
    float errorS = kUnit * (eS + 2.0), errorT = kUnit * (eT + 2.0);
    float band = kUnit * ((rayMaxS + 2.0) * uMetres.x + (rayMaxT + 2.0) * uMetres.y);
    float slackS = 0.0, slackT = 0.0;
    if (closed) {   // widened, so that no crack opens against a neighbour the CPU answers
        band += (errorS * uMetres.x + errorT * uMetres.y) / kMin;
        slackS = errorS;
        slackT = errorT;
    }
    if (band > uBudget) {
        // Nothing to prove when even the widened bounds hold no sample.
        ivec2 columns = sampleRange(sMin - errorS, sMax + errorS, uSourceGrid.x);
        ivec2 rows = sampleRange(tMin - errorT, tMax + errorT, uSourceGrid.y);
        if (columns.x <= columns.y && rows.x <= rows.y)
            flags[j] = 1u;
        discard;
    }
    ivec2 rows = sampleRange(tMin - slackT, tMax + slackT, uSourceGrid.y);
    if (rows.x > rows.y) discard;
    for (int w = 0; w < 4 * TARGETS; ++w) mask[w] = 0u;
    for (int b = rows.x; b <= rows.y; ++b) {
        float tb = (float(b) + 0.5) / float(uSourceGrid.y);
        float lo = 1e38, hi = -1e38;
        // Crossings from each edge's end of smaller magnitude, kept within the edge's span of s;
        // an edge along the row is left out (the edges at its ends bring them): BitmaskRows.h.
        for (int i = 0, k = n - 1; i < n; k = i++) {
            if (pt[k] == pt[i]) continue;
            if (tb < min(pt[k], pt[i]) - slackT || tb > max(pt[k], pt[i]) + slackT) continue;
            bool fromI = magnitude[i] < magnitude[k];
            float s0 = fromI ? ps[i] : ps[k], t0 = fromI ? pt[i] : pt[k];
            float slope = (ps[i] - ps[k]) / (pt[i] - pt[k]);
            float dt = tb - t0;
            float x = dt == 0.0 ? s0 : fma(dt, slope, s0);
            x = clamp(x, min(ps[k], ps[i]), max(ps[k], ps[i]));
            lo = min(lo, x);
            hi = max(hi, x);
        }
        ivec2 columns = sampleRange(lo - slackS, hi + slackS, uSourceGrid.x);
        if (columns.x <= columns.y)
            setRange(b * uSourceGrid.x + columns.x, b * uSourceGrid.x + columns.y);
    }
    OUTPUTS
}
