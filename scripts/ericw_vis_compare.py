#!/usr/bin/env python3
"""Sightline's `pvs vis` against ericw-tools' `vis` on a compiled Quake 1 level, side by side: time,
row sizes, and the witness search run on every set of rows (docs/pvs.md, "Quake levels"). A
measurement, not a test: it needs a `vis` binary built from ericw-tools' public source
(scripts/build_ericw.sh) and a compiled level (the original levels are GPL-2.0, e.g.
github.com/fzwoch/quake_map_source, bsp/*.bsp).

    ericw_vis_compare.py VIS_BINARY LEVEL.bsp WORKDIR [--threads N] [--check SEGMENTS] [--runs R]

Both tools work from the same portals: Sightline rebuilds them from the BSP's tree and writes them
as LEVEL.prt, which ericw's vis reads beside a copy of the level. Sightline's rows, ericw's and the
level's own (written by the tools it was compiled with) are each searched for witnesses: segments
through open space from one leaf into another that the rows cull. Times are whole processes, the
best of R runs each, N threads for both. Prints one JSON object.
"""
import argparse
import json
import os
import shutil
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
CLI = os.path.join(HERE, '..', 'build', 'app', 'sightline-cli')


def timed(command, runs):
    best = None
    for _ in range(runs):
        start = time.perf_counter()
        done = subprocess.run(command, capture_output=True, text=True)
        elapsed = time.perf_counter() - start
        if done.returncode != 0:
            raise SystemExit(f'{command[0]} failed: {done.stderr.strip() or done.stdout[-500:]}')
        best = elapsed if best is None else min(best, elapsed)
    return best, done.stdout


def sightline_report(level, extra, runs):
    elapsed, out = timed([CLI, 'pvs', 'vis', level, '--print-json'] + extra, runs)
    return elapsed, json.loads(out)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('vis')
    parser.add_argument('level')
    parser.add_argument('workdir')
    parser.add_argument('--threads', type=int, default=2)
    parser.add_argument('--check', type=int, default=32)
    parser.add_argument('--runs', type=int, default=3)
    args = parser.parse_args()

    os.makedirs(args.workdir, exist_ok=True)
    name = os.path.splitext(os.path.basename(args.level))[0]
    original = os.path.join(args.workdir, name + '.bsp')
    if os.path.abspath(original) != os.path.abspath(args.level):
        shutil.copyfile(args.level, original)
    ours = os.path.join(args.workdir, name + '-sightline.bsp')
    ericw_dir = os.path.join(args.workdir, 'ericw')
    os.makedirs(ericw_dir, exist_ok=True)
    ericw = os.path.join(ericw_dir, name + '.bsp')
    prt = os.path.join(ericw_dir, name + '.prt')

    threads = ['--threads', str(args.threads)]
    sightline_s, report = sightline_report(original, threads + ['--out', ours, '--prt', prt], args.runs)
    shutil.copyfile(original, ericw)
    ericw_s, _ = timed([args.vis, '-threads', str(args.threads), '-nocolor', ericw], args.runs)

    _, checked = sightline_report(original, threads + ['--check', str(args.check)], 1)
    _, ericw_checked = sightline_report(ericw, threads + ['--check', str(args.check)], 1)
    result = {
        'level': args.level,
        'visleafs': report['visleafs'],
        'portals': report['portals'],
        'threads': args.threads,
        'sightline_s': round(sightline_s, 3),
        'sightline_vis_ms': report['vis_ms'],
        'ericw_s': round(ericw_s, 3),
        'visible_mean': {'sightline': report['visible_mean'], 'ericw': ericw_checked['level']['visible_mean'],
                         'level': report['level']['visible_mean']},
        'lump_bytes': {'sightline': report['lump_bytes'], 'ericw': ericw_checked['level']['lump_bytes'],
                       'level': report['level']['lump_bytes']},
        'witnessed_culls': {'sightline': checked['check']['culled']['witnessed'],
                            'ericw': ericw_checked['check']['level_culled']['witnessed'],
                            'level': checked['check']['level_culled']['witnessed']},
        'culled_pairs_searched': checked['check']['culled']['pairs'],
        'segments_per_pair': args.check,
        'level_pairs_culled_here': report['level']['pairs_it_keeps_culled_here'],
    }
    print(json.dumps(result))


if __name__ == '__main__':
    sys.exit(main())
