#!/usr/bin/env python3
"""Plant mesh defects into a clean triangle mesh, one output file per kind.

The defect kinds the robust Laplacian (kernels/include/locus/kernels/mesh/
robust_laplacian.hpp) is made for and the defect detection (mesh_defects.hpp)
reports, planted the way kernels/src/mesh/mesh_defects_plant.cpp plants them for
the tests (the same constructions and the same rule for the sites, so the same
input mesh gets the same defects; this script's icosphere numbers its vertices
as the kernels' make_icosphere may not):

  fin            a triangle on an existing edge, apex h above the edge midpoint (non-manifold edge)
  bowtie         two non-adjacent faces of a vertex's fan removed (non-manifold vertex)
  zero_area      a face split at an edge midpoint on one side only, the crack closed by a flat triangle
  needle         an edge split at 1e-6 of its length on both sides (two needle triangles)
  flipped_patch  the faces of a vertex's fan reversed (inconsistent orientation)
  unreferenced   a vertex in no face
  duplicate_face a face given twice

The original vertices keep their ids and positions (new ones are appended), so
distances at them can be compared with the clean mesh's, e.g. with the great-circle
distance on the unit icosphere.

  python3 tools/mesh_defects/plant_defects.py --level 5 --count 8 --out /tmp/defects
  python3 tools/mesh_defects/plant_defects.py --input cache/meshes/bunny.off --out /tmp/defects

writes OUT/<name>_clean.off and OUT/<name>_<kind>.off (OBJ with --obj).
"""
import argparse
import math
import os
import sys

KINDS = ["fin", "bowtie", "zero_area", "needle", "flipped_patch", "unreferenced", "duplicate_face"]


def icosphere(level):
    """Icosahedron subdivided 1:4 `level` times, vertices projected on the unit sphere."""
    t = (1.0 + math.sqrt(5.0)) / 2.0
    V = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t),
         (0, -1, -t), (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    V = [tuple(c / math.sqrt(sum(q * q for q in v)) for c in v) for v in V]
    F = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4), (11, 10, 2),
         (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9), (4, 9, 5),
         (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    for _ in range(level):
        mid = {}

        def midpoint(a, b):
            key = (min(a, b), max(a, b))
            if key not in mid:
                p = [(V[a][k] + V[b][k]) / 2 for k in range(3)]
                r = math.sqrt(sum(c * c for c in p))
                V.append(tuple(c / r for c in p))
                mid[key] = len(V) - 1
            return mid[key]

        G = []
        for a, b, c in F:
            ab, bc, ca = midpoint(a, b), midpoint(b, c), midpoint(c, a)
            G += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        F = G
    return [list(v) for v in V], [list(f) for f in F]


def read_mesh(path):
    V, F = [], []
    with open(path) as fh:
        if path.lower().endswith(".off"):
            tokens = [t for line in fh for t in line.split("#")[0].split()]
            if tokens[0].upper() != "OFF":
                sys.exit(f"{path}: not an OFF file")
            nv, nf = int(tokens[1]), int(tokens[2])
            pos = 4
            for _ in range(nv):
                V.append([float(tokens[pos + k]) for k in range(3)])
                pos += 3
            for _ in range(nf):
                d = int(tokens[pos])
                face = [int(tokens[pos + 1 + k]) for k in range(d)]
                pos += 1 + d
                F += [[face[0], face[k], face[k + 1]] for k in range(1, d - 1)]
        else:
            for line in fh:
                w = line.split()
                if w and w[0] == "v":
                    V.append([float(c) for c in w[1:4]])
                elif w and w[0] == "f":
                    face = [int(c.split("/")[0]) - 1 for c in w[1:]]
                    F += [[face[0], face[k], face[k + 1]] for k in range(1, len(face) - 1)]
    return V, F


def write_mesh(path, V, F):
    with open(path, "w") as fh:
        if path.endswith(".obj"):
            fh.writelines(f"v {x!r} {y!r} {z!r}\n" for x, y, z in V)
            fh.writelines(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in F)
        else:
            fh.write(f"OFF\n{len(V)} {len(F)} 0\n")
            fh.writelines(f"{x!r} {y!r} {z!r}\n" for x, y, z in V)
            fh.writelines(f"3 {a} {b} {c}\n" for a, b, c in F)


def mean_edge_length(V, F):
    edges = {(min(a, b), max(a, b)) for f in F for a, b in zip(f, f[1:] + f[:1])}
    return sum(math.dist(V[a], V[b]) for a, b in edges) / max(len(edges), 1)


def face_at(F, v):
    return next((i for i, f in enumerate(F) if v in f), -1)


def across(F, f, a, b):
    """The face other than f running b -> a, or -1."""
    for g, G in enumerate(F):
        if g != f and b in G and G[(G.index(b) + 1) % 3] == a:
            return g
    return -1


def split_edge(V, F, f, t, both_sides):
    a, b, c = F[f]
    g = across(F, f, a, b)
    if g < 0:
        return
    G = F[g]
    d = G[(G.index(a) + 1) % 3]
    V.append([V[a][k] + t * (V[b][k] - V[a][k]) for k in range(3)])
    p = len(V) - 1
    F[f] = [a, p, c]
    F.append([p, b, c])
    if both_sides:
        F[g] = [b, p, d]
        F.append([p, a, d])
    else:
        F.append([p, a, b])


def plant_at(V, F, kind, v, h):
    f = face_at(F, v)
    if f < 0:
        return
    k = F[f].index(v)
    R = F[f][k:] + F[f][:k]  # starts at v
    if kind == "fin":
        m = [(V[R[0]][q] + V[R[1]][q]) / 2 for q in range(3)]
        r = math.sqrt(sum(c * c for c in m))
        u = h / r if r > 0 else 0.0
        V.append([m[0] * (1 + u), m[1] * (1 + u), m[2] * (1 + u) + (0.0 if r > 0 else h)])
        F.append([R[0], R[1], len(V) - 1])
    elif kind == "bowtie":
        fan = [g for g, G in enumerate(F) if v in G]
        for q in fan[1:]:
            if sum(w in F[fan[0]] for w in F[q]) == 1:
                del F[q]
                del F[fan[0]]
                break
    elif kind == "zero_area":
        F[f] = R
        split_edge(V, F, f, 0.5, False)
    elif kind == "needle":
        F[f] = R
        split_edge(V, F, f, 1e-6, True)
    elif kind == "flipped_patch":
        for G in F:
            if v in G:
                G[1], G[2] = G[2], G[1]
    elif kind == "unreferenced":
        V.append([2.0 * c for c in V[v]])
    elif kind == "duplicate_face":
        F.append(list(F[f]))


def plant(V0, F0, kind, count):
    V, F = [list(v) for v in V0], [list(f) for f in F0]
    h = mean_edge_length(V0, F0)
    nv = len(V0)
    for q in range(count):
        plant_at(V, F, kind, nv - 1 - q * nv // max(count, 1), h)
    return V, F


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--level", type=int, default=5, help="icosphere subdivision level (default 5)")
    ap.add_argument("--input", help="a triangle mesh (OFF or OBJ) instead of the icosphere")
    ap.add_argument("--count", type=int, default=8, help="sites per defect kind (default 8)")
    ap.add_argument("--kinds", default=",".join(KINDS), help="comma-separated kinds (default all)")
    ap.add_argument("--out", required=True, help="output directory")
    ap.add_argument("--obj", action="store_true", help="write OBJ instead of OFF")
    a = ap.parse_args()
    if a.input:
        V, F = read_mesh(a.input)
        name = os.path.splitext(os.path.basename(a.input))[0]
    else:
        V, F = icosphere(a.level)
        name = f"icosphere{a.level}"
    os.makedirs(a.out, exist_ok=True)
    ext = "obj" if a.obj else "off"
    write_mesh(os.path.join(a.out, f"{name}_clean.{ext}"), V, F)
    for kind in a.kinds.split(","):
        if kind not in KINDS:
            sys.exit(f"unknown defect kind {kind!r}; known: {', '.join(KINDS)}")
        Vd, Fd = plant(V, F, kind, a.count)
        path = os.path.join(a.out, f"{name}_{kind}.{ext}")
        write_mesh(path, Vd, Fd)
        print(f"{path}: {len(Vd)} vertices, {len(Fd)} faces")


if __name__ == "__main__":
    main()
