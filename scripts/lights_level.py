#!/usr/bin/env python3
"""A generated many-light level for the light-map targets (docs/lights.md, "Figures"): a grid of
8 m rooms, 3 m high, whose floors, ceilings and walls are tessellated into small quads (as a
modelling tool's subdivided planes, or a level made for vertex lighting), so that the level holds
80-100k triangles while its coplanar faces still share one chart each (the demo's dense props give
every triangle a chart of its own, and no density brings its light map near 100k texels). Each
room is closed by its own faces (walls 0.2 m thick, each face spanning the room's inside, so that no
face reaches behind another); about 60% of the inner walls have a doorway of about 1 m x 2 m with
its sides and lintel. Every room has a few box props, two lamps and a spot; every third room a
ceiling panel. Deterministic (seeded).

    lights_level.py OUTDIR [--rooms N] [--cells C] [--seed S]

writes OUTDIR/lights_level.glb and OUTDIR/lights_level.json (N x N rooms, default 6; C quads a
side on each floor and ceiling, default 20): 300 light samples at the defaults (12 panels of 4 x 4
samples, 72 lamps with an 8 m range, 36 spots)."""
import json
import os
import random
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from quake_pvs_project import glb  # noqa: E402

ROOM, HEIGHT, HALF_WALL = 8.0, 3.0, 0.1
INNER = ROOM - 2 * HALF_WALL   # a room's inside, wall face to wall face
WALL_COLUMNS, WALL_ROWS = 16, 6
DOOR_CELLS = (7, 9, 4)         # doorway: columns 7-8 of 16, rows 0-3 of 6 (0.98 m x 2 m)


def grid_mesh(name, origin, du, dv, nu, nv, skip=lambda i, j: False):
    """nu x nv quads from origin along du, dv (each a step), two triangles a quad, wound so that
    du x dv is the front; quads where skip(i, j) is true are left out."""
    positions = [tuple(origin[k] + i * du[k] + j * dv[k] for k in range(3)) for j in range(nv + 1) for i in range(nu + 1)]
    indices = []
    for j in range(nv):
        for i in range(nu):
            if skip(i, j):
                continue
            a = j * (nu + 1) + i
            b, c, d = a + 1, a + nu + 1, a + nu + 2
            indices += [a, b, d, a, d, c]
    return (name, positions, indices)


def box_mesh(name, lo, hi):
    x0, y0, z0 = lo
    x1, y1, z1 = hi
    p = [(x0, y0, z0), (x1, y0, z0), (x1, y1, z0), (x0, y1, z0), (x0, y0, z1), (x1, y0, z1), (x1, y1, z1), (x0, y1, z1)]
    faces = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 4, 7, 3), (1, 2, 6, 5), (0, 1, 5, 4), (3, 7, 6, 2)]
    indices = []
    for a, b, c, d in faces:
        indices += [a, b, c, a, c, d]
    return (name, p, indices)


def wall_face(name, x, z, along_x, facing, door):
    """A room's wall face on the boundary at x (running along z) or at z (running along x),
    HALF_WALL inside the room (`facing` +1: the room lies on the + side), spanning the room's
    inside so that no face reaches behind another; its front faces the room."""
    du, up = INNER / WALL_COLUMNS, (0.0, HEIGHT / WALL_ROWS, 0.0)
    skip = (lambda i, j: DOOR_CELLS[0] <= i < DOOR_CELLS[1] and j < DOOR_CELLS[2]) if door else (lambda i, j: False)
    lo, hi = HALF_WALL, ROOM - HALF_WALL
    if along_x:   # the front is facing * +z
        zz = z + facing * HALF_WALL
        if facing > 0:
            return grid_mesh(name, (x + lo, 0.0, zz), (du, 0.0, 0.0), up, WALL_COLUMNS, WALL_ROWS, skip)
        return grid_mesh(name, (x + hi, 0.0, zz), (-du, 0.0, 0.0), up, WALL_COLUMNS, WALL_ROWS,
                         lambda i, j: skip(WALL_COLUMNS - 1 - i, j))
    xx = x + facing * HALF_WALL
    if facing > 0:
        return grid_mesh(name, (xx, 0.0, z + hi), (0.0, 0.0, -du), up, WALL_COLUMNS, WALL_ROWS,
                         lambda i, j: skip(WALL_COLUMNS - 1 - i, j))
    return grid_mesh(name, (xx, 0.0, z + lo), (0.0, 0.0, du), up, WALL_COLUMNS, WALL_ROWS, skip)


def doorway_reveals(name, x, z, along_x):
    """The doorway's sides and lintel through the wall's thickness (the wall on the boundary at x
    running along z, or at z running along x), so that no light passes into the wall."""
    du, height = INNER / WALL_COLUMNS, HEIGHT / WALL_ROWS * DOOR_CELLS[2]
    a, b = HALF_WALL + DOOR_CELLS[0] * du, HALF_WALL + DOOR_CELLS[1] * du   # along the wall
    t = 2 * HALF_WALL
    if along_x:   # across the wall is z
        return [grid_mesh(f'{name} side', (x + a, 0.0, z + HALF_WALL), (0.0, 0.0, -t), (0.0, height, 0.0), 1, 1),
                grid_mesh(f'{name} side 2', (x + b, 0.0, z - HALF_WALL), (0.0, 0.0, t), (0.0, height, 0.0), 1, 1),
                grid_mesh(f'{name} lintel', (x + a, height, z - HALF_WALL), (b - a, 0.0, 0.0), (0.0, 0.0, t), 1, 1)]
    return [grid_mesh(f'{name} side', (x - HALF_WALL, 0.0, z + a), (t, 0.0, 0.0), (0.0, height, 0.0), 1, 1),
            grid_mesh(f'{name} side 2', (x + HALF_WALL, 0.0, z + b), (-t, 0.0, 0.0), (0.0, height, 0.0), 1, 1),
            grid_mesh(f'{name} lintel', (x - HALF_WALL, height, z + a), (t, 0.0, 0.0), (0.0, 0.0, b - a), 1, 1)]


def level(rooms, cells, rng):
    meshes, lights = [], []
    step = INNER / cells
    doors_x = {(i, j): rng.random() < 0.6 for i in range(1, rooms) for j in range(rooms)}   # wall at x = i * ROOM
    doors_z = {(i, j): rng.random() < 0.6 for i in range(rooms) for j in range(1, rooms)}   # wall at z = j * ROOM
    for i in range(rooms):
        for j in range(rooms):
            x, z, tag = i * ROOM, j * ROOM, f'{i}-{j}'
            lo, hi = HALF_WALL, ROOM - HALF_WALL
            meshes.append(grid_mesh(f'floor {tag}', (x + lo, 0.0, z + hi), (step, 0.0, 0.0), (0.0, 0.0, -step), cells, cells))
            meshes.append(grid_mesh(f'ceiling {tag}', (x + lo, HEIGHT, z + lo), (step, 0.0, 0.0), (0.0, 0.0, step), cells, cells))
            if i > 0 and doors_x[(i, j)]:
                meshes += doorway_reveals(f'doorway {tag} west', x, z, False)
            if j > 0 and doors_z[(i, j)]:
                meshes += doorway_reveals(f'doorway {tag} south', x, z, True)
            meshes.append(wall_face(f'wall {tag} west', x, z, False, +1, i > 0 and doors_x[(i, j)]))
            meshes.append(wall_face(f'wall {tag} east', x + ROOM, z, False, -1, i + 1 < rooms and doors_x[(i + 1, j)]))
            meshes.append(wall_face(f'wall {tag} south', x, z, True, +1, j > 0 and doors_z[(i, j)]))
            meshes.append(wall_face(f'wall {tag} north', x, z + ROOM, True, -1, j + 1 < rooms and doors_z[(i, j + 1)]))
            for k in range(4):
                sx, sy, sz = rng.uniform(0.4, 1.2), rng.uniform(0.4, 1.6), rng.uniform(0.4, 1.2)
                px, pz = x + rng.uniform(0.5, ROOM - 0.5 - sx), z + rng.uniform(0.5, ROOM - 0.5 - sz)
                if abs(px + sx / 2 - x - ROOM / 2) < 1.2 or abs(pz + sz / 2 - z - ROOM / 2) < 1.2:
                    continue   # keep the doorways' lanes clear
                meshes.append(box_mesh(f'crate {tag} {k}', (px, 0.0, pz), (px + sx, sy, pz + sz)))
            if (i * rooms + j) % 3 == 0:
                lights.append({'type': 'area', 'name': f'panel {tag}', 'corner': [x + 3.5, HEIGHT - 0.01, z + 3.5],
                               'u': [1.0, 0.0, 0.0], 'v': [0.0, 0.0, 1.0], 'samples': [4, 4], 'radiance': 30.0,
                               'colour': [1.0, 0.93, 0.82]})
            for k in range(2):
                lights.append({'type': 'point', 'name': f'lamp {tag} {k}', 'intensity': rng.uniform(3.0, 8.0), 'range': 8.0,
                               'position': [x + rng.uniform(1.0, 7.0), rng.uniform(1.8, 2.6), z + rng.uniform(1.0, 7.0)],
                               'colour': [1.0, rng.uniform(0.8, 1.0), rng.uniform(0.5, 0.9)]})
            lights.append({'type': 'spot', 'name': f'spot {tag}', 'intensity': 10.0, 'range': 10.0,
                           'position': [x + 0.4, 2.6, z + 4.0], 'direction': [0.64, -0.76, 0.1],
                           'inner_angle': 0.3, 'outer_angle': 0.7, 'colour': [1.0, 1.0, 1.0]})
    return meshes, lights


def main():
    if len(sys.argv) < 2 or sys.argv[1].startswith('-'):
        raise SystemExit(__doc__)
    out = sys.argv[1]
    def option(name, default):
        if name not in sys.argv:
            return default
        try:
            return int(sys.argv[sys.argv.index(name) + 1])
        except (IndexError, ValueError):
            raise SystemExit(f'lights_level.py: {name} needs a whole number')
    rooms, cells, seed = option('--rooms', 6), option('--cells', 20), option('--seed', 1)
    if not 1 <= rooms <= 64 or not 1 <= cells <= 200:
        raise SystemExit('lights_level.py: --rooms must be in [1, 64] and --cells in [1, 200]')
    meshes, lights = level(rooms, cells, random.Random(seed))
    os.makedirs(out, exist_ok=True)
    with open(os.path.join(out, 'lights_level.glb'), 'wb') as f:
        f.write(glb(meshes))
    # The patches look across the first room, wall to wall (a project needs a pair).
    project = {'version': 1, 'description': f'generated many-light level: {rooms} x {rooms} rooms, seed {seed}',
               'scene': 'lights_level.glb', 'occluders': [],
               'source': {'corner': [0.5, 0.3, 4.5], 'u': [0.0, 0.0, -1.0], 'v': [0.0, 1.6, 0.0], 'samples': [32, 32]},
               'receiver': {'corner': [7.5, 0.3, 3.5], 'u': [0.0, 0.0, 1.0], 'v': [0.0, 1.6, 0.0], 'samples': [32, 32]},
               'lights': lights}
    with open(os.path.join(out, 'lights_level.json'), 'w') as f:
        json.dump(project, f, indent=1)
    triangles = sum(len(m[2]) // 3 for m in meshes)
    samples = sum(16 if l['type'] == 'area' else 1 for l in lights)
    print(f'{out}/lights_level.json: {rooms} x {rooms} rooms, {triangles} triangles, {len(lights)} lights, {samples} light samples')


if __name__ == '__main__':
    main()
