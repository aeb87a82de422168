#!/usr/bin/env python3
"""A Quake 1 BSP with its textures' pixels zeroed, everything else byte for byte.

    quake_bsp_blank_textures.py IN.bsp OUT.bsp

The original levels' map sources and compiled BSPs were released under the GNU GPL v2, but the
textures embedded in a BSP are id Software's art, which is not. Zeroing each miptex's pixels (names,
sizes and offsets kept) leaves a file every engine and tool still reads, free of the art: this is how
tests/data/levels/quake-*.bsp were made (tests/data/SOURCES.md)."""
import struct
import sys


def main(src, dst):
    data = bytearray(open(src, 'rb').read())
    version, = struct.unpack_from('<I', data, 0)
    if version not in (29, 0x32505342):
        raise SystemExit(f'{src}: not a Quake 1 BSP (version {version})')
    offset, length = struct.unpack_from('<ii', data, 4 + 8 * 2)
    if length < 4:
        open(dst, 'wb').write(data)
        return
    count, = struct.unpack_from('<i', data, offset)
    for k in range(count):
        at, = struct.unpack_from('<i', data, offset + 4 + 4 * k)
        if at < 0:
            continue
        base = offset + at
        width, height = struct.unpack_from('<II', data, base + 16)
        pixels = sum((width >> m) * (height >> m) for m in range(4))
        first, = struct.unpack_from('<I', data, base + 24)
        start = base + first
        if start + pixels > offset + length:
            raise SystemExit(f'{src}: texture {k} runs past the texture lump')
        data[start:start + pixels] = bytes(pixels)
    open(dst, 'wb').write(data)


if __name__ == '__main__':
    if len(sys.argv) != 3:
        raise SystemExit(__doc__)
    main(sys.argv[1], sys.argv[2])
