#!/usr/bin/env python3
"""A PVS baked over a Quake level's leaves (quake_pvs_project.py) against the level's own vis
(docs/pvs.md, "Accuracy"): for each view cell, the BSP leaf its centre lies in, the leaves that
leaf's own vis row keeps, and the leaves the cell's row keeps (objects are leaves with faces, so
both are counted over those). The level's row answers for the whole leaf, the cell's for a 0.3 m box
in it, so a row as tight as a portal vis is at most the leaf's and usually smaller.

    quake_pvs_vs_vis.py LEVEL.bsp PVS.json [--json]

PVS.json is `pvs bake PROJECT.json --out X.pvs --json PVS.json [--safe]`'s. Prints, over the cells
in a leaf with a vis row: the mean and median of (cell's row / leaf's row), how many cells keep more
than their leaf's row, and the pairs each side keeps that the other does not."""
import json
import os
import statistics
import struct
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from quake_bsp_to_obj import SCALE, read_bsp  # noqa: E402


def leaf_at(point, planes, nodes):
    """The leaf (index into the leaves lump) that a point in Quake units lies in: the world's tree."""
    node = 0
    while node >= 0:
        plane_index, front, back = nodes[node][0], nodes[node][1], nodes[node][2]
        nx, ny, nz, dist = planes[plane_index][:4]
        node = front if nx * point[0] + ny * point[1] + nz * point[2] - dist >= 0 else back
    return -node - 1


def vis_row(visdata, offset, visleafs):
    """The leaves (1-based) a compressed Quake 1 row keeps: runs of zero bytes as (0, count)."""
    seen, leaf, k = set(), 1, offset
    while leaf <= visleafs and k < len(visdata):
        byte = visdata[k]
        k += 1
        if byte == 0:
            leaf += 8 * (visdata[k] if k < len(visdata) else 0)
            k += 1
            continue
        for bit in range(8):
            if byte & (1 << bit) and leaf + bit <= visleafs:
                seen.add(leaf + bit)
        leaf += 8
    return seen


def main():
    if len(sys.argv) < 3:
        raise SystemExit(__doc__)
    bsp, pvs_file = sys.argv[1:3]
    lump, records = read_bsp(bsp, versions=(29, 30))
    planes = records(1, '<4fi')
    nodes = records(5, '<ihh6hHH')
    leaves = records(10, '<ii6hHH4B')
    visdata = lump(4)
    visleafs, = struct.unpack_from('<i', lump(14), 52)
    pvs = json.load(open(pvs_file))
    object_leaf = [int(o['name'].split()[-1]) for o in pvs['objects']]   # "leaf N"
    objects = set(object_leaf)

    ratios, larger, ours_only, theirs_only, ours_total, theirs_total = [], 0, 0, 0, 0, 0
    for cell, visible in zip(pvs['cells'], pvs['visible']):
        c = [(a + b) / 2 for a, b in zip(cell['min'], cell['max'])]
        quake = (c[0] / SCALE, -c[2] / SCALE, c[1] / SCALE)   # quake_bsp_to_obj.yup, inverted
        leaf = leaf_at(quake, planes, nodes)
        if leaf < 1 or leaves[leaf][1] < 0:
            continue   # solid, or a leaf without a row
        theirs = (vis_row(visdata, leaves[leaf][1], visleafs) | {leaf}) & objects
        ours = {object_leaf[o] for o in visible}
        if not theirs:
            continue
        ratios.append(len(ours) / len(theirs))
        larger += len(ours) > len(theirs)
        ours_only += len(ours - theirs)
        theirs_only += len(theirs - ours)
        ours_total += len(ours)
        theirs_total += len(theirs)
    if not ratios:
        raise SystemExit(f'{pvs_file}: no cell lies in a leaf of {bsp} with a vis row')
    summary = {'cells': len(ratios), 'mean_ratio': statistics.mean(ratios), 'median_ratio': statistics.median(ratios),
               'max_ratio': max(ratios), 'cells_larger_than_their_leaf': larger, 'pairs': ours_total,
               'leaf_pairs': theirs_total, 'pairs_only_in_cells': ours_only, 'pairs_only_in_leaves': theirs_only}
    if '--json' in sys.argv:
        print(json.dumps(summary))
    else:
        print(f"{summary['cells']} cells: rows {summary['mean_ratio']:.2f}x their leaf's on average "
              f"(median {summary['median_ratio']:.2f}x, largest {summary['max_ratio']:.2f}x); "
              f"{larger} cells keep more than their leaf; {ours_total} pairs against {theirs_total}, "
              f"{ours_only} only in the cells' rows, {theirs_only} only in the leaves'")


if __name__ == '__main__':
    main()
