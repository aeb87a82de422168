#!/usr/bin/env python3
"""Refits Auto's ray-casting cost model (visibility/src/bitmask/Strategy.cpp, measuredCosts).

Inputs: the CSVs of one or more `bench` runs with --methods embree-tuned,cpu,cpu-bitmask,cpu-raycast
--threads 1 (docs/benchmarks.md, "Auto's cost model"), and the bench projects themselves, whose
pair and triangle estimates come from `sightline-cli shaft --json` on a copy of each project with
the bench's sample grids. Per configuration the median of the runs' thread_ms is taken, then

    ln(ray ns a ray, in the bitmask model's units) = b0 + b1 ln(1 + T) + b2 l + b3 l^2 + b4 ln(side) + b5 c

is fitted by least squares (T triangles in the shaft, l = ln(1 + pairs per ray) clamped to [0, 7],
c = pairs / (T x receiver samples)), and the clear-cut verdicts it would give are checked against
the measured costs. Prints the coefficients to paste into measuredCosts and what they predict.

    scripts/fit_auto_costs.py --cli build/app/sightline-cli --csv run-1.csv run-2.csv run-3.csv \\
        --projects build/demo/demo.json build/demo/bench/*.json ...
"""
import argparse
import collections
import csv
import json
import math
import os
import statistics
import subprocess
import tempfile

GRIDS = {32: [8, 4], 128: [16, 8], 1024: [32, 32]}   # bench's sourceGrid


def estimates(cli, projects, sides):
    """(project basename, sources, receiver side) -> what Auto estimated, from shaft --json."""
    out = {}
    with tempfile.TemporaryDirectory() as folder:
        for path in projects:
            project = json.load(open(path))
            base = os.path.dirname(os.path.abspath(path))
            for sources, grid in GRIDS.items():
                for side in sides:
                    variant = dict(project)
                    variant['source'] = dict(project['source'], samples=grid)
                    variant['receiver'] = dict(project['receiver'], samples=[side, side])
                    variant['scene'] = os.path.join(base, project['scene'])
                    name = os.path.join(folder, 'variant.json')
                    json.dump(variant, open(name, 'w'))
                    run = subprocess.run([cli, 'shaft', name, '--method', 'cpu', '--json', '--threads', '1'],
                                         capture_output=True, text=True, check=True)
                    out[(os.path.basename(path), sources, side)] = json.loads(run.stdout)
    return out


def solve(rows, targets):
    """Least squares by the normal equations (a handful of unknowns)."""
    n = len(rows[0])
    a = [[sum(r[i] * r[j] for r in rows) for j in range(n)] for i in range(n)]
    b = [sum(r[i] * y for r, y in zip(rows, targets)) for i in range(n)]
    for i in range(n):
        pivot = max(range(i, n), key=lambda r: abs(a[r][i]))
        a[i], a[pivot], b[i], b[pivot] = a[pivot], a[i], b[pivot], b[i]
        for r in range(n):
            if r != i:
                f = a[r][i] / a[i][i]
                a[r] = [x - f * y for x, y in zip(a[r], a[i])]
                b[r] -= f * b[i]
    return [b[i] / a[i][i] for i in range(n)]


def features(rays, triangles, pairs, side):
    l = min(7.0, math.log1p(pairs / rays))
    coverage = min(1.0, pairs / max(triangles, 1) / (side * side))
    return [1.0, math.log1p(triangles), l, l * l, math.log(side), coverage]


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument('--cli', required=True)
    parser.add_argument('--csv', nargs='+', required=True)
    parser.add_argument('--projects', nargs='+', required=True)
    args = parser.parse_args()

    times = collections.defaultdict(lambda: collections.defaultdict(list))
    sides = set()
    for path in args.csv:
        for row in csv.DictReader(open(path)):
            side = int(row['receiver'].split('x')[0])
            sides.add(side)
            key = (os.path.basename(row['project']), int(row['source_samples']), side)
            times[key][row['method']].append(float(row['thread_ms']))
    known = estimates(args.cli, args.projects, sorted(sides))
    data = []
    for key, methods in sorted(times.items()):
        if key in known and 'cpu-bitmask' in methods and 'cpu-raycast' in methods:
            data.append((key, known[key], statistics.median(methods['cpu-bitmask']),
                         statistics.median(methods['cpu-raycast'])))
    # The ray model is in the bitmask model's units: one-thread times scaled by the median ratio
    # of the bitmask's predictions to its measured times.
    scale = statistics.median(e['predicted_bitmask_ms'] / b for _, e, b, _ in data if e['predicted_bitmask_ms'] > 0)
    rows = [features(e['rays'], e['estimated_triangles'], e['estimated_pairs'], k[2]) for k, e, _, _ in data]
    targets = [math.log(1e6 * r * scale / e['rays']) for _, e, _, r in data]
    c = solve(rows, targets)
    names = ['rayLogBase', 'rayLogTriangles', 'rayLogPairs', 'rayLogPairs2', 'rayLogSide', 'rayCoverage']
    print(f'{len(data)} configurations; units: one-thread ms x {scale:.3f}')
    print(', '.join(f'.{n} = {v:.4f}' for n, v in zip(names, c)))
    ratios, wrong = [], []
    for (key, e, bitmask, rays), x in zip(data, rows):
        predicted = 1e-6 * e['rays'] * math.exp(sum(a * b for a, b in zip(c, x)))
        ratios.append(predicted / (rays * scale))
        predictedBitmask = max(e['predicted_bitmask_ms'], 1e-3)
        verdict = 'bitmask' if predictedBitmask <= 0.5 * predicted else 'rays' if predicted <= 0.5 * predictedBitmask else 'probe'
        if (verdict == 'bitmask' and bitmask > 1.1 * rays) or (verdict == 'rays' and rays > 1.1 * bitmask):
            wrong.append(f'  {key}: clear-cut {verdict}, measured bitmask {bitmask:.2f} ms, rays {rays:.2f} ms')
    print(f'predicted / measured: {min(ratios):.2f} - {max(ratios):.2f} (median {statistics.median(ratios):.2f})')
    print(f'clear-cut verdicts more than 10% wrong: {len(wrong)}')
    print('\n'.join(wrong))


if __name__ == '__main__':
    main()
