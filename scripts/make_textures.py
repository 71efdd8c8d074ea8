#!/usr/bin/env python3
"""Writes the example textures (24-bit bottom-up BMP, like the framework's) to examples/textures/.

Deterministic and dependency-free. Run from the repository root.
"""
import math
import struct


def write_bmp(path, w, h, pixel):
    """pixel(x, y) -> (r, g, b) bytes, y counted from the BOTTOM (BMP row order)."""
    row = (w * 3 + 3) & ~3
    data = bytearray()
    for y in range(h):
        line = bytearray()
        for x in range(w):
            r, g, b = pixel(x, y)
            line += bytes((b, g, r))
        line += b"\0" * (row - len(line))
        data += line
    header = struct.pack("<2sIHHI", b"BM", 54 + len(data), 0, 0, 54)
    info = struct.pack("<IiiHHIIiiII", 40, w, h, 1, 24, 0, len(data), 2835, 2835, 0, 0)
    with open(path, "wb") as f:
        f.write(header + info + data)


def checker(x, y):
    on = ((x // 16) + (y // 16)) % 2 == 0
    return (240, 240, 240) if on else (20, 20, 20)


def tiles(x, y):
    # Warm stone tiles with darker grout and a little deterministic variation.
    gx, gy = x % 64, y % 64
    if gx < 3 or gy < 3:
        return (70, 60, 55)
    k = ((x // 64) * 7 + (y // 64) * 13) % 5
    s = 0.06 * math.sin(x * 0.21) * math.sin(y * 0.17)
    base = 0.62 + 0.05 * k + s
    return (int(255 * min(1, base)), int(235 * min(1, base * 0.95)), int(205 * min(1, base * 0.9)))


def stripes(x, y):
    t = 0.5 + 0.5 * math.sin(2 * math.pi * (x / 32 + 0.25 * math.sin(2 * math.pi * y / 128)))
    return (int(40 + 200 * t), int(90 + 120 * t), int(200 - 120 * t))


write_bmp("examples/textures/checker.bmp", 128, 128, checker)
write_bmp("examples/textures/tiles.bmp", 256, 256, tiles)
write_bmp("examples/textures/stripes.bmp", 128, 128, stripes)
