#!/usr/bin/env python3
"""Writes presets/meshes/body.ply: a small bird-like body for pelts laid on a mesh.

An egg-shaped body 0.2 units long along y (head toward +y, tail toward -y), wider than high, as
rings of vertices between two poles. Each vertex carries its outward normal (nx ny nz), the flow
(tx ty tz: unit, along the body toward the tail, in the tangent plane) and a relative feather
density that rises toward the head (smaller, denser feathers there). Run from the repository root:
    python3 scripts/make_body_mesh.py
"""
import math
import sys

LENGTH, WIDTH, HEIGHT = 0.2, 0.09, 0.075
RINGS, SEGMENTS = 18, 24


def point(t, phi):
    """The body surface at t in [0, 1] (tail to head) and angle phi about the long axis."""
    # Egg profile: fullest behind the middle, a narrower head end.
    r = math.sin(math.pi * t) ** 0.8 * (1.0 - 0.25 * t)
    return (0.5 * WIDTH * r * math.cos(phi), LENGTH * (t - 0.5), 0.5 * HEIGHT * r * math.sin(phi))


def sub(a, b):
    return tuple(x - y for x, y in zip(a, b))


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def unit(a):
    n = math.sqrt(sum(x * x for x in a))
    return tuple(x / n for x in a)


def vertex(t, phi):
    h = 1e-4
    p = point(t, phi)
    dt = sub(point(min(t + h, 1.0), phi), point(max(t - h, 0.0), phi))
    dphi = sub(point(t, phi + h), point(t, phi - h))
    n = unit(cross(dt, dphi))
    flow = unit(tuple(-x for x in dt))  # toward the tail
    density = 1.0 + 1.5 * t * t  # 2.5 times as dense at the head as at the tail
    return p + n + flow + (density,)


def main():
    verts = [(0.0, -0.5 * LENGTH, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0, -1.0, 1.0)]  # tail pole
    for i in range(1, RINGS):
        for j in range(SEGMENTS):
            verts.append(vertex(i / RINGS, 2.0 * math.pi * j / SEGMENTS))
    verts.append((0.0, 0.5 * LENGTH, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, -1.0, 2.5))  # head pole
    faces = []
    ring = lambda i, j: 1 + (i - 1) * SEGMENTS + j % SEGMENTS
    head = len(verts) - 1
    for j in range(SEGMENTS):
        # Counter-clockwise seen from outside (normal side).
        faces.append((0, ring(1, j), ring(1, j + 1)))
        for i in range(1, RINGS - 1):
            a, b, c, d = ring(i, j), ring(i, j + 1), ring(i + 1, j), ring(i + 1, j + 1)
            faces.append((a, c, b))
            faces.append((b, c, d))
        faces.append((ring(RINGS - 1, j), head, ring(RINGS - 1, j + 1)))
    out = sys.argv[1] if len(sys.argv) > 1 else "presets/meshes/body.ply"
    with open(out, "w") as f:
        f.write("ply\nformat ascii 1.0\ncomment plumage example body: scripts/make_body_mesh.py\n")
        f.write("element vertex %d\n" % len(verts))
        for name in ("x", "y", "z", "nx", "ny", "nz", "tx", "ty", "tz", "density"):
            f.write("property float %s\n" % name)
        f.write("element face %d\nproperty list uchar int vertex_indices\nend_header\n" % len(faces))
        for v in verts:
            f.write(" ".join("%.5g" % x for x in v) + "\n")
        for a, b, c in faces:
            f.write("3 %d %d %d\n" % (a, b, c))


if __name__ == "__main__":
    main()
