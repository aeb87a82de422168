#!/usr/bin/env python3
"""A Quake 1 level (a compiled BSP, version 29) as a Sightline scene, for local measurements on a
real architectural interior (docs/benchmarks.md, "A real interior"). No level data is in this
repository: the original levels' sources were released under the GNU GPL v2 by John Romero in
2006, and compiled copies are at github.com/fzwoch/quake_map_source (bsp/*.bsp).

    quake_bsp_to_obj.py LEVEL.bsp LEVEL.obj|LEVEL.ply LEVEL-origins.jsonl

Writes the static world (model 0) as OBJ (or, named .ply, binary PLY with welded positions) in metres with Y up (1 Quake unit = 1 inch), each face
fan-triangulated and wound counter-clockwise seen from the front (Quake winds clockwise); liquid faces (textures named '*...') are left out, as a player sees through
them. Also writes the entities' origins (lights, monsters, items: points in open space), one JSON
object a line, from which interior_layouts.py places patches."""
import json
import struct
import sys

SCALE = 0.0254


def yup(v):
    return (v[0] * SCALE, v[2] * SCALE, -v[1] * SCALE)


def read_bsp(src, versions=(29,)):
    """The file's lumps: lump(k) gives lump k's bytes, records(k, fmt) its records unpacked."""
    data = open(src, 'rb').read()
    version, = struct.unpack_from('<i', data, 0)
    if version not in versions:
        raise SystemExit(f'{src}: not a Quake 1 BSP (version {version}, expected {" or ".join(map(str, versions))})')
    lumps = [struct.unpack_from('<ii', data, 4 + 8 * k) for k in range(15)]

    def lump(k):
        offset, length = lumps[k]
        return data[offset:offset + length]

    def records(k, fmt):
        size = struct.calcsize(fmt)
        raw = lump(k)
        return [struct.unpack_from(fmt, raw, size * i) for i in range(len(raw) // size)]
    return lump, records


def main(src, dst, origins_out):
    lump, records = read_bsp(src)

    vertices = records(3, '<3f')
    edges = records(12, '<2H')
    surfedges = [s[0] for s in records(13, '<i')]
    texinfo = records(6, '<8f2i')
    faces = records(7, '<hhihh4bi')
    textures = lump(2)
    count, = struct.unpack_from('<i', textures, 0)
    names = []
    for k in range(count):
        offset, = struct.unpack_from('<i', textures, 4 + 4 * k)
        names.append(textures[offset:offset + 16].split(b'\0')[0].decode('latin-1') if offset >= 0 else '')
    first, numfaces = struct.unpack_from('<ii', lump(14), 56)   # model 0, the world

    lines, triangles, next_vertex = [], 0, 1
    welded, corners = {}, []   # for .ply: each position once, triangles by index
    for f in range(first, first + numfaces):
        _, _, firstedge, numedges, tex = faces[f][:5]
        miptex = texinfo[tex][8]
        if 0 <= miptex < len(names) and names[miptex].startswith('*'):
            continue
        polygon = []
        for e in range(firstedge, firstedge + numedges):
            s = surfedges[e]
            polygon.append(vertices[edges[s][0]] if s >= 0 else vertices[edges[-s][1]])
        lines += ['v %.6f %.6f %.6f' % yup(p) for p in polygon]
        ids = [welded.setdefault(yup(p), len(welded)) for p in polygon]
        corners += [(ids[0], ids[k + 1], ids[k]) for k in range(1, len(polygon) - 1)]
        # Quake winds a face clockwise seen from its front; OBJ counter-clockwise.
        lines += [f'f {next_vertex} {next_vertex + k + 1} {next_vertex + k}' for k in range(1, len(polygon) - 1)]
        triangles += max(0, len(polygon) - 2)
        next_vertex += len(polygon)
    if dst.endswith('.ply'):
        # Binary PLY, positions welded: a third of the OBJ's size, for levels kept as test data.
        header = ('ply\nformat binary_little_endian 1.0\ncomment ' + src.split('/')[-1] + ' (Quake 1 BSP, world model), '
                  'metres, Y up\nelement vertex %d\nproperty float x\nproperty float y\nproperty float z\n'
                  'element face %d\nproperty list uchar int vertex_indices\nend_header\n') % (len(welded), len(corners))
        with open(dst, 'wb') as out:
            out.write(header.encode('ascii'))
            for p in sorted(welded, key=welded.get):
                out.write(struct.pack('<3f', *p))
            for c in corners:
                out.write(struct.pack('<B3i', 3, *c))
    else:
        open(dst, 'w').write('\n'.join(lines) + '\n')

    with open(origins_out, 'w') as out:
        for block in lump(0).decode('latin-1').split('}'):
            keys = {}
            for line in block.splitlines():
                parts = line.strip().split('"')
                if len(parts) >= 5:
                    keys[parts[1]] = parts[3]
            if 'origin' in keys and 'classname' in keys:
                origin = tuple(map(float, keys['origin'].split()))
                out.write(json.dumps({'classname': keys['classname'], 'origin': yup(origin)}) + '\n')
    print(f'{dst}: {triangles} triangles')


if __name__ == '__main__':
    if len(sys.argv) != 4:
        raise SystemExit(__doc__)
    main(*sys.argv[1:4])
