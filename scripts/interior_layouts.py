#!/usr/bin/env python3
"""Patch layouts in a level converted by quake_bsp_to_obj.py (docs/benchmarks.md, "A real
interior"): pairs of entity origins (points in open space) 8-25 m apart, a 1.5 m square patch at
each facing the other, kept when the reference finds between 15% and 85% of their rays free.
Deterministic for a seed.

    interior_layouts.py SIGHTLINE_CLI LEVEL COUNT SEED

reads LEVEL-origins.jsonl and writes LEVEL-layout1.json ... (scene LEVEL.obj, 32x32 samples on
both patches) in the current folder."""
import json
import math
import random
import subprocess
import sys


def sub(a, b): return [a[k] - b[k] for k in range(3)]
def add(a, b): return [a[k] + b[k] for k in range(3)]
def mul(a, s): return [x * s for x in a]
def cross(a, b): return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def norm(a):
    length = math.sqrt(sum(x * x for x in a))
    return [x / length for x in a]


def facing(centre, towards, size):
    n = norm(sub(towards, centre))
    up = [0, 1, 0] if abs(n[1]) < 0.9 else [1, 0, 0]
    u = norm(cross(up, n))
    v = cross(n, u)
    return {'corner': add(centre, add(mul(u, -size / 2), mul(v, -size / 2))), 'u': mul(u, size), 'v': mul(v, size)}


def main(cli, level, count, seed):
    origins = [json.loads(line)['origin'] for line in open(f'{level}-origins.jsonl')]
    rng = random.Random(seed)
    kept = tries = 0
    while kept < count and tries < 400:
        tries += 1
        a, b = rng.sample(origins, 2)
        distance = math.dist(a, b)
        if not 8 <= distance <= 25:
            continue
        source, receiver = facing(a, b, 1.5), facing(b, a, 1.5)
        source['samples'], receiver['samples'] = [8, 8], [16, 16]
        project = {'version': 1, 'scene': f'{level}.obj', 'occluders': [], 'source': source, 'receiver': receiver,
                   'description': f'{level} (Quake, id Software 1996; map sources under the GNU GPL v2, John Romero 2006), '
                                  f'layout {kept + 1}'}
        name = f'{level}-layout{kept + 1}.json'
        json.dump(project, open(name, 'w'), indent=1)
        run = subprocess.run([cli, 'shaft', name, '--method', 'raycast', '--json'], capture_output=True, text=True)
        if run.returncode != 0:
            continue
        visible = json.loads(run.stdout)['visible_fraction']
        if 0.15 <= visible <= 0.85:
            source['samples'] = receiver['samples'] = [32, 32]
            json.dump(project, open(name, 'w'), indent=1)
            print(f'{name}: patches {distance:.1f} m apart, {visible:.0%} of the rays free')
            kept += 1


if __name__ == '__main__':
    if len(sys.argv) != 5:
        raise SystemExit(__doc__)
    main(sys.argv[1], sys.argv[2], int(sys.argv[3]), int(sys.argv[4]))
