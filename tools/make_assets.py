#!/usr/bin/env python3
"""Writes texr's demo assets into models/: textures (PNG) and OBJ meshes with UVs.

Run from the repository root: python3 tools/make_assets.py
The output is committed; this script documents how it was made and remakes it exactly.
"""
import math
import struct
import zlib


def write_png(path, width, height, pixel):
    """pixel(i, j) -> (r, g, b) bytes, or (r, g, b, a) for an image with alpha (every pixel
    alike); j = 0 is the top row of the file."""
    rows = bytearray()
    for j in range(height):
        rows.append(0)  # filter type: none
        for i in range(width):
            rows.extend(pixel(i, j))

    def chunk(kind, data):
        body = kind + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body) & 0xFFFFFFFF)

    colour_type = 6 if len(pixel(0, 0)) == 4 else 2  # RGBA or RGB
    header = struct.pack(">IIBBBBB", width, height, 8, colour_type, 0, 0, 0)
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) +
                chunk(b"IDAT", zlib.compress(bytes(rows), 9)) + chunk(b"IEND", b""))


def checker(i, j, size=256, cells=8):
    cell = size // cells
    light = ((i // cell) + (j // cell)) % 2 == 0
    return (235, 235, 235) if light else (40, 40, 48)


def uvgrid(i, j, size=256, cells=8):
    """Cell colour tells (u, v): red grows with u (to the right), green with v (upwards,
    v = 0 is the bottom row of the file). Dark grid lines every cell."""
    cell = size // cells
    cu, cv = i // cell, (size - 1 - j) // cell
    if i % cell in (0, cell - 1) or j % cell in (0, cell - 1):
        return (20, 20, 20)
    r = 40 + 215 * cu // (cells - 1)
    g = 40 + 215 * cv // (cells - 1)
    b = 200 if (cu + cv) % 2 == 0 else 90
    return (r, g, b)


def detail(i, j, size=1024):
    """Benchmark texture: 32-texel cells whose colours vary over the image, split into a
    4x4 fine checker inside each cell, with 1-texel dark grid lines: detail at several
    frequencies, so every filter's blur and aliasing show in the error."""
    if i % 32 == 0 or j % 32 == 0:
        return (25, 25, 30)
    cu, cv = i // 32, j // 32
    fine = ((i // 8) + (j // 8)) % 2
    base = (60 + (cu * 37) % 180, 60 + (cv * 53) % 180, 60 + ((cu + cv) * 29) % 180)
    return tuple(min(255, c + 50) if fine else c for c in base)


def tree(i, j, size=64):
    """A billboard's tree (RGBA, straight alpha): a round crown on a trunk, transparent around
    them. The transparent texels take the crown's green, so that a filter blending them with
    the crown's edge (alpha 0 beside 1) blends in no other colour."""
    x, y = i - (size - 1) / 2, j - size * 3 / 8
    if x * x + y * y < (size * 0.34) ** 2:
        shade = 110 + (i * 7 + j * 3) % 50
        return (40, shade, 45, 255)
    if abs(x) < size / 16 and j >= size * 5 / 8:
        return (105, 70, 40, 255)
    return (45, 130, 50, 0)


def write_torus(path, major=1.0, minor=0.4, segments=48, rings=24):
    """A parametric surface for the demo (the lecture's are the disc, cylinder, sphere,
    triangle and triangle mesh):
    a torus meshed at (phi, theta) = (2 pi u, 2 pi v)."""
    lines = ["# torus, R = %g, r = %g; u around the axis, v around the tube" % (major, minor)]
    for a in range(segments + 1):
        for b in range(rings + 1):
            phi, theta = 2 * math.pi * a / segments, 2 * math.pi * b / rings
            x = (major + minor * math.cos(theta)) * math.cos(phi)
            z = -(major + minor * math.cos(theta)) * math.sin(phi)
            y = minor * math.sin(theta)
            lines.append("v %.6f %.6f %.6f" % (x, y, z))
            lines.append("vn %.6f %.6f %.6f" % (math.cos(theta) * math.cos(phi), math.sin(theta),
                                                -math.cos(theta) * math.sin(phi)))
            lines.append("vt %.6f %.6f" % (a / segments, b / rings))
    for a in range(segments):
        for b in range(rings):
            k = lambda aa, bb: aa * (rings + 1) + bb + 1
            p, q, r, s = k(a, b), k(a + 1, b), k(a + 1, b + 1), k(a, b + 1)
            lines.append("f %d/%d/%d %d/%d/%d %d/%d/%d %d/%d/%d" % (p, p, p, q, q, q, r, r, r, s, s, s))
    open(path, "w").write("\n".join(lines) + "\n")


def write_cube(path):
    """A unit cube with per-face UVs and two materials (top/bottom 'cap', sides 'side')."""
    corners = [(x, y, z) for x in (-0.5, 0.5) for y in (-0.5, 0.5) for z in (-0.5, 0.5)]
    idx = {c: n + 1 for n, c in enumerate(corners)}
    faces = [  # counter-clockwise seen from outside; material
        ([(0.5, -0.5, 0.5), (0.5, -0.5, -0.5), (0.5, 0.5, -0.5), (0.5, 0.5, 0.5)], (1, 0, 0), "side"),
        ([(-0.5, -0.5, -0.5), (-0.5, -0.5, 0.5), (-0.5, 0.5, 0.5), (-0.5, 0.5, -0.5)], (-1, 0, 0), "side"),
        ([(-0.5, 0.5, 0.5), (0.5, 0.5, 0.5), (0.5, 0.5, -0.5), (-0.5, 0.5, -0.5)], (0, 1, 0), "cap"),
        ([(-0.5, -0.5, -0.5), (0.5, -0.5, -0.5), (0.5, -0.5, 0.5), (-0.5, -0.5, 0.5)], (0, -1, 0), "cap"),
        ([(-0.5, -0.5, 0.5), (0.5, -0.5, 0.5), (0.5, 0.5, 0.5), (-0.5, 0.5, 0.5)], (0, 0, 1), "side"),
        ([(0.5, -0.5, -0.5), (-0.5, -0.5, -0.5), (-0.5, 0.5, -0.5), (0.5, 0.5, -0.5)], (0, 0, -1), "side"),
    ]
    lines = ["# unit cube, two materials, UVs (0,0)-(1,1) on each face", "mtllib cube.mtl"]
    lines += ["v %g %g %g" % c for c in corners]
    lines += ["vt 0 0", "vt 1 0", "vt 1 1", "vt 0 1"]
    for _, n, _ in faces:
        lines.append("vn %g %g %g" % n)
    current = None
    for f, (quad, _, material) in enumerate(faces):
        if material != current:
            lines.append("usemtl " + material)
            current = material
        lines.append("f " + " ".join("%d/%d/%d" % (idx[c], t + 1, f + 1) for t, c in enumerate(quad)))
    open(path, "w").write("\n".join(lines) + "\n")
    open(path.replace(".obj", ".mtl"), "w").write(
        "# materials of cube.obj\n"
        "newmtl side\nKd 0.8 0.8 0.8\nmap_Kd textures/uvgrid.png\n\n"
        "newmtl cap\nKd 0.9 0.35 0.1\n")


if __name__ == "__main__":
    write_png("models/textures/checker.png", 256, 256, checker)
    write_png("models/textures/uvgrid.png", 256, 256, uvgrid)
    write_png("models/textures/detail.png", 1024, 1024, detail)
    write_png("models/textures/tree.png", 64, 64, tree)
    write_torus("models/torus.obj")
    write_cube("models/cube.obj")
