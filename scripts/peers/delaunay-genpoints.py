#!/usr/bin/env python3
"""Reproducible point sets in qhull's text format for scripts/peers/bench-delaunay.sh.

usage: delaunay-genpoints.py uniform N OUT
       delaunay-genpoints.py boxlevel ROOMS_X ROOMS_Y FLOORS JITTER OUT

`boxlevel` is a generated level of rectangular rooms (16x16x8 cells of 24 units, walls
one cell thick) sampled on the regular 24-unit grid of their walls, floors and ceilings:
exactly coplanar and cospherical, like real wall samples. JITTER > 0 adds a uniform
offset in [-JITTER, JITTER] to each coordinate (seeded).
"""
import random
import sys

GRID = 24


def write(path, pts):
    with open(path, "w") as f:
        f.write("3\n%d\n" % len(pts))
        f.write("".join("%r %r %r\n" % p for p in pts))


def uniform(n):
    rng = random.Random(12345)
    return [(rng.random() * 1000.0, rng.random() * 1000.0, rng.random() * 1000.0) for _ in range(n)]


def box_faces(x0, y0, z0, nx, ny, nz):
    """Grid points on the six faces of the box [x0, x0+nx] x ... (in grid units)."""
    out = set()
    for i in range(nx + 1):
        for j in range(ny + 1):
            out.add((x0 + i, y0 + j, z0))
            out.add((x0 + i, y0 + j, z0 + nz))
    for i in range(nx + 1):
        for k in range(nz + 1):
            out.add((x0 + i, y0, z0 + k))
            out.add((x0 + i, y0 + ny, z0 + k))
    for j in range(ny + 1):
        for k in range(nz + 1):
            out.add((x0, y0 + j, z0 + k))
            out.add((x0 + nx, y0 + j, z0 + k))
    return out


def boxlevel(rx, ry, floors, jitter):
    room, height, wall = 16, 8, 1
    cells = set()
    for a in range(rx):
        for b in range(ry):
            for c in range(floors):
                cells |= box_faces(a * (room + wall), b * (room + wall), c * (height + wall),
                                   room, room, height)
    pts = sorted(cells)
    rng = random.Random(777)
    out = []
    for (i, j, k) in pts:
        p = (float(i * GRID), float(j * GRID), float(k * GRID))
        if jitter > 0:
            p = tuple(c + rng.uniform(-jitter, jitter) for c in p)
        out.append(p)
    rng.shuffle(out)
    return out


def main():
    kind = sys.argv[1]
    if kind == "uniform":
        write(sys.argv[3], uniform(int(sys.argv[2])))
    elif kind == "boxlevel":
        rx, ry, floors = int(sys.argv[2]), int(sys.argv[3]), int(sys.argv[4])
        write(sys.argv[6], boxlevel(rx, ry, floors, float(sys.argv[5])))
    else:
        sys.exit("unknown kind " + kind)


if __name__ == "__main__":
    main()
