#!/usr/bin/env python3
"""Sightline's lights against ericw-tools' `light` on a real Quake map, side by side: time and
difference (docs/lights.md, "Against ericw-tools"). A measurement, not a test: it needs a `light`
binary built from ericw-tools' public source (scripts/build_ericw.sh) and a compiled Quake 1 map
(BSP version 29; the original levels are GPL-2.0, e.g. github.com/fzwoch/quake_map_source, bsp/*.bsp).

    ericw_light_compare.py LIGHT_BINARY LEVEL.bsp WORKDIR [--scale S] [--threads N]

The same lighting is set up for both: every light entity becomes an inverse-square point light
(ericw's "delay" "2": value L * 128^2 / dist^2 times the cosine at the surface with "_anglescale"
"1", times the worldspawn range scale 0.5), white, unstyled, no minlight, sun or bounce; its value
times S (default 1). ericw lights the map (`-threads N -visapprox none`, no approximation by the
map's vis); Sightline lights the same luxels: each lightmapped face's sample points as ericw
places them (the texture-space grid at multiples of 16 units from the face's lightmap origin,
one unit in front of the face), in metres with Y up (1 unit = 1 inch), from the same lights as
point lights of intensity 0.5 * 128^2 * 0.0254^2 * L * S, so that its irradiance is ericw's 8-bit
luxel value before rounding and clamping. Both light every luxel; compared are those strictly inside
their face (by half a unit; ericw moves the others onto it) whose ericw value is below 250 (not
clamped).

Prints one JSON object: both tools' wall times (whole processes, and Sightline's lighting alone),
the luxels compared, and their difference in 8-bit units (mean and 95th percentile of |diff|,
shares within 1 and 3 units, luxels one tool lights (>= 4) and the other leaves dark (< 1)).
"""
import json
import math
import os
import re
import struct
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import quake_bsp_to_obj  # noqa: E402  (the same world geometry and conversion)

INCH = 0.0254
LUMPS = 15


def read_lumps(data):
    version, = struct.unpack_from('<i', data, 0)
    if version != 29:
        raise SystemExit('not a Quake 1 BSP (version %d, expected 29)' % version)
    return [list(struct.unpack_from('<ii', data, 4 + 8 * k)) for k in range(LUMPS)]


def entities_of(text):
    return [dict(re.findall(r'"([^"]*)"\s+"([^"]*)"', block)) for block in re.findall(r'\{([^}]*)\}', text)]


def rewrite_entities(entities, scale):
    """Every light an unstyled white inverse-square point light; no minlight or sun."""
    out, lights = [], []
    for e in entities:
        name = e.get('classname', '')
        if name == 'worldspawn':
            e = {k: v for k, v in e.items() if k not in ('light', '_minlight', '_sunlight', '_sun_mangle', '_sunlight2',
                                                           '_sunlight3', '_dirt', '_bounce', '_range', '_dist', '_anglescale')}
        elif name.startswith('light'):
            value = float(e.get('light', '300')) * scale
            if value <= 0.0 or 'origin' not in e:
                continue   # antilights have no counterpart in the contract
            origin = [float(x) for x in e['origin'].split()]
            e = {'classname': 'light', 'origin': e['origin'], 'light': '%g' % value, 'delay': '2', '_anglescale': '1'}
            lights.append((origin, value))
        out.append(e)
    text = ''.join('{\n' + ''.join('"%s" "%s"\n' % kv for kv in e.items()) + '}\n' for e in out) + '\0'
    return text.encode('latin-1'), lights


def write_with_entities(data, lumps, entity_bytes, path):
    """The BSP with its entity lump replaced: appended at the end, the directory pointing there."""
    body = bytearray(data)
    while len(body) % 4:
        body.append(0)
    lumps = [list(l) for l in lumps]
    lumps[0] = [len(body), len(entity_bytes)]
    body += entity_bytes
    for k, (offset, length) in enumerate(lumps):
        struct.pack_into('<ii', body, 4 + 8 * k, offset, length)
    with open(path, 'wb') as f:
        f.write(body)


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def solve3(rows, rhs):
    """x with rows[i] . x = rhs[i] (Cramer's rule; the rows are two texture axes and a normal)."""
    def det(m):
        return (m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]))
    d = det(rows)
    out = []
    for c in range(3):
        m = [list(r) for r in rows]
        for r in range(3):
            m[r][c] = rhs[r]
        out.append(det(m) / d)
    return out


def luxels(data, lumps):
    """Every luxel of the lightmapped world faces: position (units), the face normal, ericw's value and
    whether it lies inside its face (ericw moves the others onto the face)."""
    def records(k, fmt):
        size = struct.calcsize(fmt)
        offset, length = lumps[k]
        return [struct.unpack_from(fmt, data, offset + size * i) for i in range(length // size)]

    planes = records(1, '<4fi')
    vertices = records(3, '<3f')
    texinfo = records(6, '<8f2i')
    faces = records(7, '<hhihh4Bi')
    edges = records(12, '<2H')
    surfedges = [s[0] for s in records(13, '<i')]
    light_offset, light_length = lumps[8]
    lighting = data[light_offset:light_offset + light_length]
    first, count = struct.unpack_from('<ii', data, lumps[14][0] + 56)
    points, normals, values, inner = [], [], [], []
    for f in range(first, first + count):
        planenum, side, firstedge, numedges, tex = faces[f][:5]
        styles, lightofs = faces[f][5:9], faces[f][9]
        if lightofs < 0 or styles[0] != 0:
            continue   # unlit (sky, liquids) or no unstyled map
        polygon = []
        for e in range(firstedge, firstedge + numedges):
            s = surfedges[e]
            polygon.append(vertices[edges[s][0]] if s >= 0 else vertices[edges[-s][1]])
        vecs = texinfo[tex][:8]
        axes = (vecs[0:3], vecs[4:7])
        uv = [(dot(p, axes[0]) + vecs[3], dot(p, axes[1]) + vecs[7]) for p in polygon]
        lo = [math.floor(min(c[i] for c in uv) / 16.0) for i in range(2)]
        hi = [math.ceil(max(c[i] for c in uv) / 16.0) for i in range(2)]
        width, height = hi[0] - lo[0] + 1, hi[1] - lo[1] + 1
        flip = -1.0 if side else 1.0
        normal = [flip * c for c in planes[planenum][:3]]
        dist = flip * planes[planenum][3]
        inside = edge_test(uv)
        for t in range(height):
            for s in range(width):
                u, v = (lo[0] + s) * 16.0, (lo[1] + t) * 16.0
                world = solve3([axes[0], axes[1], normal], [u - vecs[3], v - vecs[7], dist])
                points.append([world[i] + normal[i] for i in range(3)])   # one unit in front, as ericw samples
                normals.append(normal)
                values.append(float(lighting[lightofs + t * width + s]))
                inner.append(inside(u, v))
    return points, normals, values, inner


def write_npy(path, rows):
    """float32 .npy of shape (len(rows), len(rows[0]))."""
    header = "{'descr': '<f4', 'fortran_order': False, 'shape': (%d, %d), }" % (len(rows), len(rows[0]))
    header += ' ' * (63 - (10 + len(header)) % 64) + '\n'
    with open(path, 'wb') as f:
        f.write(b'\x93NUMPY\x01\x00' + struct.pack('<H', len(header)) + header.encode('latin-1'))
        for row in rows:
            f.write(struct.pack('<%df' % len(row), *row))


def read_npy_first_column(path):
    """Column 0 of a float32 (N, 3) .npy."""
    data = open(path, 'rb').read()
    length, = struct.unpack_from('<H', data, 8)
    body = data[10 + length:]
    values = struct.unpack('<%df' % (len(body) // 4), body)
    return list(values[0::3])


def edge_test(uv):
    """Whether (u, v) lies inside the convex polygon by half a unit (either winding)."""
    n = len(uv)
    area = sum(uv[i][0] * uv[(i + 1) % n][1] - uv[(i + 1) % n][0] * uv[i][1] for i in range(n))
    sign = 1.0 if area > 0 else -1.0

    def inside(u, v):
        for i in range(n):
            a, b = uv[i], uv[(i + 1) % n]
            edge = (b[0] - a[0], b[1] - a[1])
            length = math.hypot(edge[0], edge[1])
            if length == 0.0:
                continue
            cross = sign * (edge[0] * (v - a[1]) - edge[1] * (u - a[0])) / length
            if cross < 0.5:
                return False
        return True
    return inside


def yup(p):
    return [p[0] * INCH, p[2] * INCH, -p[1] * INCH]


def main():
    args = [a for a in sys.argv[1:] if not a.startswith('--')]
    if len(args) != 3:
        sys.exit(__doc__)
    light_binary, bsp_path, work = args
    scale = float(sys.argv[sys.argv.index('--scale') + 1]) if '--scale' in sys.argv else 1.0
    threads = sys.argv[sys.argv.index('--threads') + 1] if '--threads' in sys.argv else '2'
    cli = os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', 'build', 'app', 'sightline-cli')
    os.makedirs(work, exist_ok=True)
    data = open(bsp_path, 'rb').read()
    lumps = read_lumps(data)
    entity_text = data[lumps[0][0]:lumps[0][0] + lumps[0][1]].decode('latin-1')
    entity_bytes, lights = rewrite_entities(entities_of(entity_text), scale)
    lit_bsp = os.path.join(work, 'level.bsp')
    write_with_entities(data, lumps, entity_bytes, lit_bsp)

    start = time.monotonic()
    subprocess.run([light_binary, '-threads', threads, '-visapprox', 'none', lit_bsp], check=True, capture_output=True)
    ericw_s = time.monotonic() - start
    lit = open(lit_bsp, 'rb').read()
    positions, normals, ericw, inner = luxels(lit, read_lumps(lit))

    scene = os.path.join(work, 'level.ply')
    quake_bsp_to_obj.main(bsp_path, scene, os.path.join(work, 'origins.jsonl'))
    k = 0.5 * 128.0 * 128.0 * INCH * INCH
    project = {'version': 1, 'scene': 'level.ply',
               'source': {'corner': [0, 0, 0], 'u': [1, 0, 0], 'v': [0, 1, 0], 'samples': [4, 4]},
               'receiver': {'corner': [0, 0, 2], 'u': [1, 0, 0], 'v': [0, 1, 0], 'samples': [4, 4]},
               'lights': [{'type': 'point', 'position': yup(o), 'intensity': k * value} for o, value in lights]}
    with open(os.path.join(work, 'level.json'), 'w') as f:
        json.dump(project, f)
    write_npy(os.path.join(work, 'luxels.npy'), [yup(p) + yup(n) for p, n in zip(positions, normals)])
    start = time.monotonic()
    run = subprocess.run([cli, 'lights', os.path.join(work, 'level.json'), '--points', os.path.join(work, 'luxels.npy'),
                          '--npy', os.path.join(work, 'sightline.npy'), '--json', '--threads', threads],
                         check=True, capture_output=True, text=True)
    sightline_s = time.monotonic() - start
    report = json.loads(run.stdout)
    ours = read_npy_first_column(os.path.join(work, 'sightline.npy'))

    pairs = [(o, e) for o, e, i in zip(ours, ericw, inner) if i and e < 250.0]
    diff = sorted(abs(o - e) for o, e in pairs)
    lit_dark = sum(1 for o, e in pairs if o >= 4.0 and e < 1.0)
    dark_lit = sum(1 for o, e in pairs if o < 1.0 and e >= 4.0)
    mean = lambda xs: sum(xs) / max(1, len(xs))
    print(json.dumps({
        'level': os.path.basename(bsp_path), 'lights': len(lights), 'light_scale': scale, 'threads': int(threads),
        'luxels': len(ericw), 'luxels_inside': sum(inner), 'luxels_compared': len(pairs),
        'ericw_light_s': round(ericw_s, 3), 'sightline_process_s': round(sightline_s, 3),
        'sightline_lighting_ms': round(report['ms'], 1), 'sightline_setup_ms': round(report['setup_ms'], 1),
        'mean_abs_diff': round(mean(diff), 3), 'p95_abs_diff': round(diff[int(0.95 * (len(diff) - 1))], 3),
        'within_1': round(mean([d <= 1.0 for d in diff]), 4), 'within_3': round(mean([d <= 3.0 for d in diff]), 4),
        'sightline_lit_ericw_dark': lit_dark, 'sightline_dark_ericw_lit': dark_lit,
        'mean_ericw': round(mean([e for _, e in pairs]), 2), 'mean_sightline': round(mean([o for o, _ in pairs]), 2)}, indent=1))


if __name__ == '__main__':
    main()
