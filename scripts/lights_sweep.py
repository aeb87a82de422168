#!/usr/bin/env python3
"""The lighting benchmark's light-count sweep (docs/lights.md): the demo level lit by N light
samples over its floor, the fast path against the brute-force reference in the same run, and
against the brute force a user would write with Embree's float rays alone (not exact).

For each N it writes a project beside the demo's demo_lights.json whose lights are the demo's
first N light samples' worth (panels, lamps, spots and the sun in their order; past the demo's
300, more lamps with seeded positions in the level's rooms), runs
`sightline-cli lights PROJECT --compare --json` and prints one row: N, both times, the ratio,
the points that differ (ties only) and how the fast path settled its (tile, light) pairs.

With --cut E1,E2,... it adds, for each N, a row per light-cut error E (`--light-cut E`: the point
lights through a light tree's cut, an approximation): its time against the same run's reference
and its error (mean, 99th percentile and largest relative difference per point, and the share of
points beyond 1% and 5%).

With --chart PREFIX it also draws the sweep (`sightline-cli chart`): PREFIX-time.png, each path's
time against the light samples; PREFIX-speedup.png, the fast path's speed-up over the brute force
and over the float Embree brute force; and with --cut, PREFIX-cut.png, time against mean error for
each light count (the exact fast path at error 0 as the last point of each line).

    scripts/lights_sweep.py build/demo/demo_lights.json 10,30,100,300,1000,3000 [--side 256] [--cut 0.1,0.03,0.01]
        [--chart PREFIX]
"""
import json
import os
import random
import subprocess
import sys
import tempfile


def lights_for(base, count, rng):
    out, samples = [], 0
    for light in base:
        n = light["samples"][0] * light["samples"][1] if light["type"] == "area" else 1
        if samples + n > count:
            continue
        out.append(light)
        samples += n
    rooms = [((0.4, 0.4), (9.6, 9.6)), ((10.4, 0.4), (21.6, 9.6)), ((22.4, 0.4), (29.6, 9.6)),
             ((0.4, 10.4), (13.6, 19.6)), ((14.4, 10.4), (29.6, 19.6))]
    while samples < count:
        lo, hi = rooms[rng.randrange(len(rooms))]
        out.append({"type": "point", "name": "extra lamp %d" % samples,
                    "position": [rng.uniform(lo[0], hi[0]), rng.uniform(1.6, 2.8), rng.uniform(lo[1], hi[1])],
                    "intensity": rng.uniform(1.0, 4.0), "range": 8.0, "colour": [1.0, 0.85, 0.6]})
        samples += 1
    return out


def draw(cli, prefix, name, title, x, y, series):
    spec = {"title": title, "x": x, "y": y, "series": [{"name": k, "points": v} for k, v in series.items() if v]}
    with tempfile.TemporaryDirectory() as folder:
        path = os.path.join(folder, "chart.json")
        with open(path, "w") as f:
            json.dump(spec, f)
        subprocess.run([cli, "chart", path, "--out", "%s-%s.png" % (prefix, name)], check=True)


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    project_file, counts = sys.argv[1], [int(n) for n in sys.argv[2].split(",")]
    side = int(sys.argv[sys.argv.index("--side") + 1]) if "--side" in sys.argv else 256
    cuts = [float(e) for e in sys.argv[sys.argv.index("--cut") + 1].split(",")] if "--cut" in sys.argv else []
    chart = sys.argv[sys.argv.index("--chart") + 1] if "--chart" in sys.argv else None
    times = {"exact fast path": [], "exact brute force (reference)": [], "Embree float brute force (not exact)": []}
    speedups = {"over the exact brute force": [], "over the Embree float brute force": []}
    cut_lines = {}
    cli = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "build", "app", "sightline-cli")
    with open(project_file) as f:
        project = json.load(f)
    base = project["lights"]
    folder = os.path.dirname(os.path.abspath(project_file))
    print("samples  lights  fast_ms  reference_ms  speedup  differing  embree_float_ms  fast_vs_float  float_differing  unreached  shadowed  cast")
    for count in counts:
        document = dict(project)
        document["lights"] = lights_for(base, count, random.Random(count))
        document["receiver"] = dict(project["receiver"], samples=[side, side])
        path = os.path.join(folder, "lights_sweep_%d.json" % count)
        with open(path, "w") as f:
            json.dump(document, f)
        run = subprocess.run([cli, "lights", path, "--compare", "--json"], capture_output=True, text=True, check=True)
        r = json.loads(run.stdout)
        c = r["compare"]
        print("%7d  %6d  %7.0f  %12.0f  %6.2fx  %9d  %15.0f  %12.2fx  %15d  %9d  %8d  %5d" % (
            r["light_samples"], r["lights"], c["fast_ms"], c["reference_ms"], c["speedup"], c["points_differing"],
            c["embree_float_ms"], c["speedup_over_embree_float"], c["embree_float_points_differing"],
            r["tiles_unreached"], r["tiles_proven_shadowed"], r["tiles_cast"]))
        n = r["light_samples"]
        times["exact fast path"].append([n, c["fast_ms"]])
        times["exact brute force (reference)"].append([n, c["reference_ms"]])
        times["Embree float brute force (not exact)"].append([n, c["embree_float_ms"]])
        speedups["over the exact brute force"].append([n, c["speedup"]])
        speedups["over the Embree float brute force"].append([n, c["speedup_over_embree_float"]])
        exact_ms = c["fast_ms"]
        for error in cuts:
            run = subprocess.run([cli, "lights", path, "--compare", "--json", "--light-cut", str(error)],
                                 capture_output=True, text=True, check=True)
            r = json.loads(run.stdout)
            c, e = r["compare"], r["compare"]["light_cut"]
            print("%7d  cut %-6g  %7.0f ms (%.1f Hz)  reference %6.0f ms  %6.2fx  error mean %.4f  p99 %.3f  max %.3g  "
                  "beyond 1%% %.3f  beyond 5%% %.3f  clusters %d" % (
                      r["light_samples"], error, c["fast_ms"], 1000.0 / c["fast_ms"], c["reference_ms"], c["speedup"],
                      e["mean_relative"], e["p99_relative"], e["max_relative"], e["points_beyond_1pct"],
                      e["points_beyond_5pct"], r["cut_clusters"]))
            cut_lines.setdefault("%d light samples" % r["light_samples"], []).append([100.0 * e["mean_relative"], c["fast_ms"]])
        if cuts:
            cut_lines["%d light samples" % n].append([0.0, exact_ms])
    if chart:
        samples = {"title": "light samples", "log": True}
        draw(cli, chart, "time", "Many lights over %dx%d floor points: time" % (side, side), samples,
             {"title": "ms", "log": True}, times)
        draw(cli, chart, "speedup", "The exact fast path's speed-up", samples, {"title": "speed-up (x)"}, speedups)
        if cuts:
            draw(cli, chart, "cut", "The light cut: time against error", {"title": "mean error (%)"},
                 {"title": "ms", "log": True}, {k: sorted(v) for k, v in cut_lines.items()})


if __name__ == "__main__":
    main()
