#!/usr/bin/env python3
"""Summarises `bench` CSVs of the methods embree-tuned,cpu,cpu-bitmask,cpu-raycast (run with
--threads 1; docs/benchmarks.md, "Ray casting where it is the right strategy"), one CSV per run:

- errors outside ties and tie differences per method, summed over the runs;
- Auto (`cpu`) against the better of `cpu-bitmask` and `cpu-raycast`, by the medians of the runs'
  thread_ms: how many configurations are within 10%, and every one that is not, with the strategy
  Auto ran (`variant`, where the bench recorded it) and whether it is the better one's;
- where ray casting is the right strategy (`cpu-raycast` faster than `cpu-bitmask`), the tuned
  tracer's time over `cpu-raycast`'s and over `cpu`'s, by scene kind and sample counts;
- the tuned tracer over `cpu` (Auto) on every scene kind and sample count, worst scene first, and
  which of its traversals (`variant`) won how often.

    scripts/bench_summary.py run-1.csv run-2.csv run-3.csv
"""
import collections
import csv
import os
import re
import statistics
import sys


def main(paths):
    times = collections.defaultdict(lambda: collections.defaultdict(list))
    ran = collections.defaultdict(lambda: collections.defaultdict(collections.Counter))   # strategies run
    errors, ties, variants = collections.Counter(), collections.Counter(), collections.Counter()
    for path in paths:
        for row in csv.DictReader(open(path)):
            key = (os.path.basename(row['project']).removesuffix('.json'), int(row['source_samples']),
                   int(row['receiver'].split('x')[0]))
            times[key][row['method']].append(float(row['thread_ms']))
            if row['method'].startswith('cpu') and row.get('variant'):
                ran[key][row['method']][row['variant']] += 1
            if row['method'] == 'embree-tuned':
                variants[row.get('variant') or '(not recorded)'] += 1
            else:
                errors[row['method']] += int(row['wrongly_blocked']) + int(row['wrongly_free'])
                ties[row['method']] += int(row.get('ties') or 0)
    print(f'{len(paths)} runs; errors outside ties: {dict(errors)}; tie differences: {dict(ties)}')
    median = {k: {m: statistics.median(v) for m, v in methods.items()} for k, methods in times.items()}

    misses, chose = [], collections.Counter()
    for key, m in sorted(median.items()):
        better = 'cpu-bitmask' if m['cpu-bitmask'] <= m['cpu-raycast'] else 'cpu-raycast'
        auto, best = ran[key]['cpu'], ran[key][better]
        same = None   # unknown: CSVs from before the strategy was recorded
        if auto and best:
            # The strategy, swapped or not: the forced ray caster never swaps (Auto's swapped rays
            # are its own, faster, way of casting them).
            strategy = lambda runs: runs.most_common(1)[0][0].removesuffix(' swapped')
            same = strategy(auto) == strategy(best)
            chose[same] += 1
        ratio = m['cpu'] / m[better]
        if ratio > 1.1:
            misses.append((ratio, key, m, same, '/'.join(sorted(auto))))
    print(f'Auto within 10% of the better strategy: {len(median) - len(misses)} of {len(median)}')
    if chose:
        print(f'Auto ran the better strategy on {chose[True]} of {sum(chose.values())} '
              '(the strategy most runs took, swapped or not)')
        spread = sorted(m['cpu'] / m[b] for key, m in median.items() for b in ('cpu-bitmask', 'cpu-raycast')
                        if ran[key]['cpu'] and ran[key]['cpu'] == ran[key][b])
        if spread:
            print(f'  where Auto ran exactly what a forced strategy ran ({len(spread)}), its time over that one\'s: '
                  f'median {statistics.median(spread):.3f}, quartiles {spread[len(spread) // 4]:.3f}-'
                  f'{spread[3 * len(spread) // 4]:.3f}, range {spread[0]:.2f}-{spread[-1]:.2f}')
    for ratio, key, m, same, auto in sorted(misses, reverse=True):
        verdict = '' if same is None else (f' [ran {auto}, the better one]' if same else f' [ran {auto}, not the better one]')
        print(f'  {ratio:.2f} {key[0]} {key[1]} x {key[2]}²: ' + ', '.join(f'{n} {t:.2f}' for n, t in sorted(m.items())) + verdict)

    groups = collections.defaultdict(list)
    for key, m in median.items():
        if m['cpu-raycast'] < m['cpu-bitmask']:
            kind = re.sub(r'-\d+$', '', key[0])
            groups[(kind, key[1], key[2])].append((m['embree-tuned'] / m['cpu-raycast'], m['embree-tuned'] / m['cpu'], key[0]))
    rays = [r for group in groups.values() for r, _, _ in group]
    if rays:
        print(f'ray casting the right strategy on {len(rays)}: tuned / cpu-raycast {min(rays):.2f}-{max(rays):.2f}, '
              f'1.0 or more on {sum(r >= 1.0 for r in rays)}')
    for (kind, sources, side), group in sorted(groups.items()):
        worst = min(group)
        print(f'  {kind} ({len(group)}), {sources} x {side}²: tuned / cpu-raycast {min(r for r, _, _ in group):.2f}-'
              f'{max(r for r, _, _ in group):.2f} (worst {worst[2]}), tuned / cpu {min(a for _, a, _ in group):.2f}-'
              f'{max(a for _, a, _ in group):.2f}')

    print(f'tuned tracer traversals kept: {dict(variants)}')
    kinds = collections.defaultdict(list)
    for key, m in median.items():
        kinds[(re.sub(r'-\d+$', '', key[0]), key[1], key[2])].append((m['embree-tuned'] / m['cpu'], key[0]))
    print('tuned / cpu (Auto) by kind, worst (scene) and best:')
    for (kind, sources, side), group in sorted(kinds.items()):
        worst, best = min(group), max(group)
        print(f'  {kind:24} {sources:5} x {side}²: {worst[0]:6.2f} ({worst[1]})  {best[0]:6.2f}')


if __name__ == '__main__':
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    main(sys.argv[1:])
