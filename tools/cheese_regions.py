#!/usr/bin/env python3
"""Where a remesh of cheese loses its angles, and what its tunnels allow (docs/cvt.md).

  python3 tools/cheese_regions.py REMESH.obj
  python3 tools/cheese_regions.py --antiprism 1000 1200 1500 2000 4000

cache/meshes/cheese.off is the cube [-0.05, 0.05]^3 drilled along all three
axes by a 4 x 4 grid of tunnels of radius 0.0063 at -0.0375, -0.0125, 0.0125,
0.0375: a lattice whose 64 nodes are where three tunnels cross (the lattice
was measured on the input: the wall triangles' axes cluster there).

REMESH: per triangle its smallest angle (law of cosines, computed here), the
triangles grouped by where their centroid lies: the outer shell (within 0.004
of the cube's faces: its flat faces, its edges and the openings' rims), a
lattice node (all three coordinates within 0.0094 of a lattice line), a
tunnel segment (two of them), elsewhere; printed: count, mean smallest angle
and how many are below 40 degrees. Reads OBJ or OFF itself, shares no code
with locus.

--antiprism N...: for a straight tunnel of that radius at the vertex density
of N points spread uniformly over cheese's area (the remesh edge
e = sqrt(2 A / (sqrt(3) N))), the best antiprism (k vertices per ring, each
ring turned half a step against the last; all edges chords of the cylinder):
its k, ring spacing and smallest angle.
"""
import argparse
import math
import sys

import numpy as np

RADIUS = 0.0063
LATTICE = np.array([-0.0375, -0.0125, 0.0125, 0.0375])
CHEESE_AREA = 0.13349  # of cache/meshes/cheese.off (sum of its triangles' areas)


def read_mesh(path):
    verts, faces = [], []
    if path.endswith(".obj"):
        with open(path) as f:
            for line in f:
                t = line.split()
                if t and t[0] == "v":
                    verts.append([float(x) for x in t[1:4]])
                elif t and t[0] == "f":
                    faces.append([int(x.split("/")[0]) - 1 for x in t[1:4]])
        return np.array(verts), np.array(faces)
    with open(path) as f:
        words = [w for line in f for w in line.split("#", 1)[0].split()]
    nv, nf = int(words[1]), int(words[2])
    v = np.array(words[4:4 + 3 * nv], float).reshape(-1, 3)
    fa = np.array(words[4 + 3 * nv:4 + 3 * nv + 4 * nf], int).reshape(-1, 4)
    if np.any(fa[:, 0] != 3):
        sys.exit("only triangles")
    return v, fa[:, 1:]


def smallest_angles(v, f):
    a, b, c = v[f[:, 0]], v[f[:, 1]], v[f[:, 2]]
    la, lb, lc = (np.linalg.norm(b - c, axis=1), np.linalg.norm(c - a, axis=1), np.linalg.norm(a - b, axis=1))

    def opposite(x, y, z):  # the angle opposite side x
        return np.degrees(np.arccos(np.clip((y * y + z * z - x * x) / (2 * y * z), -1, 1)))

    return np.minimum(np.minimum(opposite(la, lb, lc), opposite(lb, lc, la)), opposite(lc, la, lb)), (a + b + c) / 3


def regions(path):
    v, f = read_mesh(path)
    ang, cen = smallest_angles(v, f)
    near = np.abs(cen[:, :, None] - LATTICE[None, None, :]).min(2) < 0.5 * (0.025 / 2 + RADIUS)
    lines = near.sum(1)
    outer = np.abs(cen).max(1) > 0.05 - 0.004
    kind = np.where(outer, 0, np.where(lines == 3, 1, np.where(lines == 2, 2, 3)))
    print("%s: %d vertices, %d triangles, mean smallest angle %.2f, smallest %.2f" %
          (path, len(v), len(f), ang.mean(), ang.min()))
    for k, name in enumerate(["outer shell", "lattice node", "tunnel segment", "elsewhere"]):
        s = kind == k
        if s.any():
            print("  %-15s %5d triangles  mean %.1f  below 40: %d" % (name, s.sum(), ang[s].mean(), (ang[s] < 40).sum()))


def antiprism(n):
    e = math.sqrt(2 * CHEESE_AREA / (math.sqrt(3) * n))
    per_length = 2 * math.pi * RADIUS / (math.sqrt(3) / 2 * e * e)  # vertices per unit of tunnel length
    best = None
    for k in range(3, 13):
        s = k / per_length
        ring = 2 * RADIUS * math.sin(math.pi / k)
        side = math.hypot(2 * RADIUS * math.sin(math.pi / (2 * k)), s)
        apex = 2 * math.degrees(math.asin(min(1.0, ring / (2 * side))))
        worst = min(apex, (180 - apex) / 2)
        if best is None or worst > best[2]:
            best = (k, s, worst)
    print("N %d: e %.4f, circumference / e %.2f; antiprism k %d, ring spacing %.4f, smallest angle %.1f" %
          ((n, e, 2 * math.pi * RADIUS / e) + best))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("remesh", nargs="?")
    ap.add_argument("--antiprism", type=int, nargs="+")
    args = ap.parse_args()
    if args.remesh:
        regions(args.remesh)
    for n in args.antiprism or []:
        antiprism(n)
    if not args.remesh and not args.antiprism:
        ap.error("a remesh or --antiprism")


if __name__ == "__main__":
    main()
