#!/usr/bin/env python3
"""A PVS project on a real Quake level (docs/pvs.md, "Accuracy"): the world's faces as one glTF
node per BSP leaf (the faces its marksurfaces list, each face in the first leaf that lists it;
liquids left out), so the PVS objects are the level's own leaves, and small box cells at the
entities' origins (monsters, items, lights: places in open space), 0.3 m on a side. Metres with Y
up, as quake_bsp_to_obj.py converts.

    quake_pvs_project.py LEVEL.bsp OUTDIR [--cells N]

writes OUTDIR/LEVEL-leaves.glb and OUTDIR/LEVEL-pvs.json (at most N cells, default 200, every k-th
origin so they spread over the level)."""
import json
import os
import struct
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from quake_bsp_to_obj import read_bsp, yup  # noqa: E402


def glb(meshes):
    """meshes: list of (name, positions [(x,y,z)], indices [i]) -> GLB bytes, one node per mesh."""
    binary, views, accessors, gltf_meshes, nodes = b'', [], [], [], []
    for name, positions, indices in meshes:
        lo = [min(p[a] for p in positions) for a in range(3)]
        hi = [max(p[a] for p in positions) for a in range(3)]
        offset = len(binary)
        binary += b''.join(struct.pack('<3f', *p) for p in positions)
        views.append({'buffer': 0, 'byteOffset': offset, 'byteLength': 12 * len(positions), 'target': 34962})
        accessors.append({'bufferView': len(views) - 1, 'componentType': 5126, 'count': len(positions), 'type': 'VEC3',
                          'min': lo, 'max': hi})
        offset = len(binary)
        binary += struct.pack('<%dI' % len(indices), *indices)
        views.append({'buffer': 0, 'byteOffset': offset, 'byteLength': 4 * len(indices), 'target': 34963})
        accessors.append({'bufferView': len(views) - 1, 'componentType': 5125, 'count': len(indices), 'type': 'SCALAR'})
        gltf_meshes.append({'name': name, 'primitives': [{'attributes': {'POSITION': len(accessors) - 2},
                                                          'indices': len(accessors) - 1}]})
        nodes.append({'name': name, 'mesh': len(gltf_meshes) - 1})
    doc = {'asset': {'version': '2.0', 'generator': 'sightline quake_pvs_project.py'}, 'scene': 0,
           'scenes': [{'nodes': list(range(len(nodes)))}], 'nodes': nodes, 'meshes': gltf_meshes,
           'accessors': accessors, 'bufferViews': views, 'buffers': [{'byteLength': len(binary)}]}
    text = json.dumps(doc).encode()
    text += b' ' * (-len(text) % 4)
    binary += b'\0' * (-len(binary) % 4)
    return (struct.pack('<3I', 0x46546C67, 2, 12 + 8 + len(text) + 8 + len(binary)) + struct.pack('<2I', len(text), 0x4E4F534A)
            + text + struct.pack('<2I', len(binary), 0x004E4942) + binary)


def main():
    if len(sys.argv) < 3:
        raise SystemExit(__doc__)
    src, out = sys.argv[1], sys.argv[2]
    cells_wanted = int(sys.argv[sys.argv.index('--cells') + 1]) if '--cells' in sys.argv else 200
    lump, records = read_bsp(src, versions=(29, 30))
    vertices = records(3, '<3f')
    edges = records(12, '<2H')
    surfedges = [s[0] for s in records(13, '<i')]
    texinfo = records(6, '<8f2i')
    faces = records(7, '<hhihh4bi')
    leaves = records(10, '<ii6hHH4B')
    marks = [m[0] for m in records(11, '<H')]
    textures = lump(2)
    count, = struct.unpack_from('<i', textures, 0)
    names = []
    for k in range(count):
        offset, = struct.unpack_from('<i', textures, 4 + 4 * k)
        names.append(textures[offset:offset + 16].split(b'\0')[0].decode('latin-1') if offset >= 0 else '')
    visleafs, = struct.unpack_from('<i', lump(14), 52)

    taken, meshes = set(), []
    for leaf in range(1, visleafs + 1):
        first, count = leaves[leaf][8], leaves[leaf][9]
        positions, indices, welded = [], [], {}
        for f in marks[first:first + count]:
            if f in taken:
                continue
            taken.add(f)
            _, _, firstedge, numedges, tex = faces[f][:5]
            miptex = texinfo[tex][8]
            if 0 <= miptex < len(names) and names[miptex][:1] in ('*', '!'):
                continue
            polygon = []
            for e in range(firstedge, firstedge + numedges):
                s = surfedges[e]
                polygon.append(yup(vertices[edges[s][0]] if s >= 0 else vertices[edges[-s][1]]))
            ids = [welded.setdefault(p, len(welded)) for p in polygon]
            for k in range(1, len(polygon) - 1):
                indices += [ids[0], ids[k + 1], ids[k]]   # Quake winds clockwise seen from the front
        if indices:
            positions = sorted(welded, key=welded.get)
            meshes.append(('leaf %d' % leaf, positions, indices))

    origins = []
    for block in lump(0).decode('latin-1').split('}'):
        keys = {}
        for line in block.splitlines():
            parts = line.strip().split('"')
            if len(parts) >= 5:
                keys[parts[1]] = parts[3]
        if 'origin' in keys and keys.get('classname', '').split('_')[0] in ('monster', 'item', 'weapon', 'light', 'info'):
            origins.append(yup(tuple(map(float, keys['origin'].split()))))
    step = max(1, len(origins) // cells_wanted)
    half = 0.15
    cells = [{'min': [c[0] - half, c[1] - half, c[2] - half], 'max': [c[0] + half, c[1] + half, c[2] + half]}
             for c in origins[::step][:cells_wanted]]

    os.makedirs(out, exist_ok=True)
    name = os.path.splitext(os.path.basename(src))[0]
    scene = os.path.join(out, name + '-leaves.glb')
    open(scene, 'wb').write(glb(meshes))
    # The project's patches (the file needs a pair): two small facing squares at the first origin.
    o = origins[0] if origins else (0.0, 0.0, 0.0)
    project = {'version': 1, 'scene': os.path.abspath(scene), 'pvs': {'cells': cells},
               'source': {'corner': list(o), 'u': [0.1, 0, 0], 'v': [0, 0.1, 0], 'samples': [8, 8]},
               'receiver': {'corner': [o[0], o[1], o[2] + 1.0], 'u': [0, 0.1, 0], 'v': [0.1, 0, 0], 'samples': [8, 8]}}
    with open(os.path.join(out, name + '-pvs.json'), 'w') as f:
        json.dump(project, f)
    print(f'{scene}: {len(meshes)} leaves with faces, {len(cells)} cells')


if __name__ == '__main__':
    main()
