#!/usr/bin/env python3
"""How far one bounce of virtual point lights is from the gathering reference as the photon count
grows (docs/lights.md, "Indirect light"): for each photon count N, `sightline-cli lights PROJECT
--indirect N --indirect-reference M --json` (VPLs and reference in the same run) and one row: photons,
VPLs, trace and bounce times, the bounce's mean, its relative RMSE against the reference and the
clamp's loss. With --chart PNG it draws the relative RMSE against the VPL count (log-log), beside
the 1/sqrt(N) line through the first point (`sightline-cli chart`).

    scripts/vpl_sweep.py PROJECT.json 64,256,1024,4096,16384 [--reference 2048] [--side 16] [--chart OUT.png]

--side S lights an S x S grid of the receiver patch (default 16, the table in docs/lights.md)."""
import json
import os
import subprocess
import sys
import tempfile


def option(name, default):
    return sys.argv[sys.argv.index(name) + 1] if name in sys.argv else default


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    project_file, counts = sys.argv[1], [int(n) for n in sys.argv[2].split(",")]
    reference, side, chart = int(option("--reference", 2048)), int(option("--side", 16)), option("--chart", None)
    cli = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "build", "app", "sightline-cli")
    with open(project_file) as f:
        project = json.load(f)
    project["receiver"] = dict(project["receiver"], samples=[side, side])
    errors = []
    with tempfile.TemporaryDirectory() as folder:
        path = os.path.join(os.path.dirname(os.path.abspath(project_file)), "vpl_sweep_%d.json" % side)
        with open(path, "w") as f:
            json.dump(project, f)
        print("photons   vpls  trace_ms  bounce_ms  mean_w_m2  relative_rmse  clamp_loss  (reference mean)")
        for n in counts:
            run = subprocess.run([cli, "lights", path, "--indirect", str(n), "--indirect-reference", str(reference), "--json"],
                                 capture_output=True, text=True, check=True)
            r = json.loads(run.stdout)["indirect"]
            mean = sum(r["mean"]) / 3.0
            print("%7d  %5d  %8.1f  %9.1f  %9.3f  %13.3f  %10.3g  (%.3f)" % (
                n, r["vpls"], r["trace_ms"], r["ms"], mean, r["reference"]["relative_rmse"], r["clamp_loss"],
                r["reference"]["mean"]))
            if r["vpls"] > 0:
                errors.append([r["vpls"], r["reference"]["relative_rmse"]])
        if chart and errors:
            first_n, first_e = errors[0]
            guide = [[n, first_e * (first_n / n) ** 0.5] for n, _ in errors]
            spec = {"title": "One bounce of VPLs against the gathering reference (%d directions)" % reference,
                    "x": {"title": "VPLs", "log": True}, "y": {"title": "relative RMSE", "log": True},
                    "series": [{"name": "VPLs' relative RMSE", "points": errors},
                               {"name": "1/sqrt(N) through the first point", "points": guide}]}
            spec_file = os.path.join(folder, "chart.json")
            with open(spec_file, "w") as f:
                json.dump(spec, f)
            subprocess.run([cli, "chart", spec_file, "--out", chart], check=True)


if __name__ == "__main__":
    main()
