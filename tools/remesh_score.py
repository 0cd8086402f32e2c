#!/usr/bin/python3
"""An independent score of a remesh against its input, sharing no code with locus.

The remesh table (tools/remesh_table.py) reads the figures `locus cvt --json`
computes itself (remesh_quality.hpp); this script computes them again from the
two files alone, with numpy and scipy, so that a bug in the engine's own
statistics cannot make a row look right:

- topology: edge-manifold (no edge in more than two faces), vertex-manifold
  (the faces around each vertex form one fan), consistently oriented (or
  orientable by flips), no unreferenced vertex; components, boundary loops,
  Euler characteristic and the genus 2g = 2c - b - chi; compared with the
  input's when the input is an orientable surface without zero-area faces
  (otherwise the engine remeshes its manifold sheets: not rebuilt here);
- angles: each triangle's smallest angle, their minimum and mean, and the
  share below 25 and 30 degrees;
- the two-sided Hausdorff distance over the diagonal of the bounding box of
  the input's vertices in faces, on
  samples (every vertex and ~`--samples` points spread by area on each
  surface, then a grid of 861 points on each of the 200 faces holding the
  farthest samples, and a local search around the 20 farthest grid points;
  each point's distance to the 16 triangles of the other surface whose own
  samples are nearest is an upper bound, and the points are then taken in
  decreasing bound against every triangle until no bound exceeds the best
  exact distance: the maximum over the points, exactly, a close lower bound
  of the true distance);
- the input's angle bound: the smallest interior angle of its boundary
  corners (the angle sum of a boundary vertex, below 180 degrees) and of its
  components of one triangle. A remesh with a vertex at each such corner, or
  that keeps a one-triangle component, has a triangle no better than it: any
  triangulation that keeps a corner of angle a has an angle <= a there.

Reads OFF and OBJ (triangles, and polygons cut into triangles by ear clipping
in the plane of their Newell normal; a non-planar polygon's triangles are a
choice, which the engine's own ear clipping may make otherwise: counted). Needs python3-numpy and
python3-scipy (Debian packages; `bash tools/setup.sh --bench-peers` installs them).

  /usr/bin/python3 tools/remesh_score.py cache/meshes/cow.off /tmp/cow.obj
  /usr/bin/python3 tools/remesh_score.py --json INPUT REMESH
"""
import argparse
import json
import math
import sys

import numpy as np
from scipy.spatial import cKDTree


def newell_normal(p):
    """A polygon's normal scaled by twice its area (p: its corners in order, k x 3)."""
    q = np.roll(p, -1, axis=0)
    return np.array([((p[:, 1] - q[:, 1]) * (p[:, 2] + q[:, 2])).sum(), ((p[:, 2] - q[:, 2]) * (p[:, 0] + q[:, 0])).sum(),
                     ((p[:, 0] - q[:, 0]) * (p[:, 1] + q[:, 1])).sum()])


def edge_table(f):
    """The half-edges (3m x 2, face by face in blocks of m), the undirected edges,
    each half-edge's edge, and each edge's face count."""
    half = np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]])
    edges, inverse, count = np.unique(np.sort(half, axis=1), axis=0, return_inverse=True, return_counts=True)
    return half, edges, inverse.reshape(-1), count


def ear_clip(v, idx):
    """Triangles of polygon idx (vertex indices into v): its Newell normal's
    plane, then ears cut in turn (a convex corner holding no other corner);
    a fan where no ear is left (a polygon folded in that plane)."""
    if len(idx) == 3:
        return [list(idx)]
    p = np.asarray([v[i] for i in idx], float)
    n = newell_normal(p)
    ax = int(np.argmax(np.abs(n)))
    uv = np.delete(p, ax, axis=1)
    x, y = uv[:, 0], uv[:, 1]
    if np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y) < 0:
        uv[:, 0] = -uv[:, 0]  # counterclockwise in the plane
    def cross(o, a, b):
        return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
    ring, tris = list(range(len(idx))), []
    while len(ring) > 3:
        for k in range(len(ring)):
            i0, i1, i2 = ring[k - 1], ring[k], ring[(k + 1) % len(ring)]
            if cross(uv[i0], uv[i1], uv[i2]) <= 0:
                continue
            inside = any(cross(uv[i0], uv[i1], uv[j]) >= 0 and cross(uv[i1], uv[i2], uv[j]) >= 0 and
                         cross(uv[i2], uv[i0], uv[j]) >= 0 for j in ring if j not in (i0, i1, i2))
            if not inside:
                tris.append([idx[i0], idx[i1], idx[i2]])
                ring.pop(k)
                break
        else:
            tris += [[idx[ring[0]], idx[ring[k]], idx[ring[k + 1]]] for k in range(1, len(ring) - 1)]
            return tris
    tris.append([idx[i] for i in ring])
    return tris


def read_mesh(path, polygons=None):
    """(vertices n x 3 float, triangles m x 3 int) of an OFF or OBJ file; its
    faces of more than three corners are appended to `polygons` if given."""
    if path.lower().endswith(".obj"):
        vs, fs = [], []
        with open(path, encoding="utf-8", errors="replace") as f:
            for line in f:
                t = line.split()
                if not t:
                    continue
                if t[0] == "v":
                    vs.append([float(x) for x in t[1:4]])
                elif t[0] == "f":
                    idx = [int(x.split("/")[0]) for x in t[1:]]
                    idx = [i - 1 if i > 0 else len(vs) + i for i in idx]
                    fs.append(idx)
        if polygons is not None:
            polygons += [x for x in fs if len(x) > 3]
        if any(len(x) > 3 for x in fs):
            fs = [t for x in fs for t in ear_clip(vs, x)]
        return np.array(vs, float).reshape(-1, 3), np.array(fs, np.int64).reshape(-1, 3)
    # Line by line: a vertex line may carry colors or normals after its
    # position (COFF, NOFF), a face line colors after its indices.
    with open(path, encoding="utf-8", errors="replace") as f:
        lines = [t for t in (line.split("#")[0].split() for line in f) if t]
    if not lines or not lines[0][0].endswith("OFF"):
        sys.exit(f"remesh_score: {path}: neither OBJ nor OFF")
    head = lines[0][1:] if len(lines[0]) > 1 else lines[1]
    body = lines[1:] if len(lines[0]) > 1 else lines[2:]
    nv, nf = int(head[0]), int(head[1])
    v = np.array([[float(x) for x in t[:3]] for t in body[:nv]], float).reshape(nv, 3)
    fs = []
    for t in body[nv:nv + nf]:
        n = int(t[0])
        idx = [int(x) for x in t[1:1 + n]]
        if polygons is not None and n > 3:
            polygons.append(idx)
        fs += ear_clip(v, idx)
    return v, np.array(fs, np.int64).reshape(-1, 3)


def find(parent, x):
    while parent[x] != x:
        parent[x] = parent[parent[x]]
        x = parent[x]
    return x


def orientable_by_flips(f, inverse, by_edge, half):
    """Whether flipping some faces orients an edge-manifold mesh (a walk over its faces)."""
    m = len(f)
    flip = np.full(m, -1, np.int8)
    # The direction each face gives each of its edges: +1 if (a, b) with a < b.
    sign = np.where(half[:, 0] < half[:, 1], 1, -1)
    face_edges = [[] for _ in range(m)]
    for h, e in enumerate(inverse):
        face_edges[h % m].append((int(e), int(sign[h])))
    for start in range(m):
        if flip[start] >= 0:
            continue
        flip[start] = 0
        stack = [start]
        while stack:
            g = stack.pop()
            for e, sg in face_edges[g]:
                fs = by_edge[e]
                if len(fs) != 2:
                    continue
                o = fs[0] if fs[1] == g else fs[1]
                if o == g:
                    return False
                osg = next(x for ee, x in face_edges[o] if ee == e)
                # Neighbors agree when they give the edge opposite directions.
                want = flip[g] if osg != sg else 1 - flip[g]
                if flip[o] < 0:
                    flip[o] = want
                    stack.append(o)
                elif flip[o] != want:
                    return False
    return True


def nonplanar(v, polygons, tol):
    """Polygons whose corners leave the plane of their Newell normal by more than tol:
    their triangulation is a choice (the engine's ear clipping may choose another)."""
    count = 0
    for idx in polygons:
        p = v[idx]
        n = newell_normal(p)
        norm = np.linalg.norm(n)
        if norm > 0 and np.abs((p - p.mean(axis=0)) @ (n / norm)).max() > tol:
            count += 1
    return count


def topology(v, f):
    """Manifoldness, orientation, components, boundary loops, chi and genus."""
    nv = len(v)
    half, edges, inverse, count = edge_table(f)
    edge_manifold = bool(count.max(initial=0) <= 2)
    # Consistent orientation: no directed edge twice.
    _, dcount = np.unique(half, axis=0, return_counts=True)
    oriented = bool(dcount.max(initial=0) <= 1)
    used = np.zeros(nv, bool)
    used[f.reshape(-1)] = True
    # Vertex-manifold: the faces around a vertex joined through their edges at it form one fan.
    m = len(f)
    fan_parent = {}
    corner_faces = {}
    for k in range(3):
        for fi, vi in enumerate(f[:, k]):
            corner_faces.setdefault(int(vi), []).append(fi)
    face_of_half = np.tile(np.arange(m), 3)
    by_edge = {}
    for h, e in enumerate(inverse):
        by_edge.setdefault(int(e), []).append(int(face_of_half[h]))
    vertex_manifold = True
    for e, (a, b) in enumerate(edges):
        fs = by_edge[e]
        if len(fs) == 2:
            for x in (int(a), int(b)):
                p = fan_parent.setdefault(x, {})
                for g in fs:
                    p.setdefault(g, g)
                r0, r1 = find(p, fs[0]), find(p, fs[1])
                p[r0] = r1
    for x, fs in corner_faces.items():
        p = fan_parent.get(x, {})
        roots = {find(p, g) if g in p else ("alone", g) for g in fs}
        if len(roots) != 1:
            vertex_manifold = False
            break
    # Components over the edges of used vertices.
    parent = list(range(nv))
    for a, b in edges:
        ra, rb = find(parent, int(a)), find(parent, int(b))
        if ra != rb:
            parent[ra] = rb
    comps = len({find(parent, x) for x in range(nv) if used[x]})
    # Boundary loops: cycles of the boundary edges (each boundary vertex of a
    # manifold has two; at a pinch the directed edges, consistently oriented, pair up).
    bnd = edges[count == 1]
    bparent = {}
    for a, b in bnd:
        for x in (int(a), int(b)):
            bparent.setdefault(x, x)
    if vertex_manifold:
        for a, b in bnd:
            ra, rb = find(bparent, int(a)), find(bparent, int(b))
            if ra != rb:
                bparent[ra] = rb
        loops = len({find(bparent, x) for x in bparent})
    else:
        loops = -1
    chi = int(used.sum()) - len(edges) + m
    orientable = oriented or (edge_manifold and orientable_by_flips(f, inverse, by_edge, half))
    area = 0.5 * np.linalg.norm(np.cross(v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]]), axis=1)
    diag = float(np.linalg.norm(v.max(axis=0) - v.min(axis=0))) if nv else 0.0
    zero_area = int((area <= 1e-12 * diag * diag).sum())
    # The topology is defined on an orientable 2-manifold (its orientation may
    # need flips, unreferenced vertices do not count); `manifold` is that, oriented, every vertex used.
    surface = edge_manifold and vertex_manifold and orientable
    manifold = surface and oriented and bool(used.all())
    twice = 2 * comps - chi - loops
    genus = twice // 2 if surface and twice >= 0 and twice % 2 == 0 else -1
    return {"manifold": manifold, "surface": surface, "edge_manifold": edge_manifold, "vertex_manifold": vertex_manifold,
            "oriented": oriented, "orientable": bool(orientable), "zero_area_faces": zero_area,
            "unreferenced": int((~used).sum()), "components": comps,
            "boundary_loops": loops, "euler": chi, "genus": genus}


def corner_angles(v, f):
    """Each triangle's three angles in degrees (m x 3)."""
    out = np.zeros((len(f), 3))
    for k in range(3):
        p, q, r = v[f[:, k]], v[f[:, (k + 1) % 3]], v[f[:, (k + 2) % 3]]
        u, w = q - p, r - p
        nu, nw = np.linalg.norm(u, axis=1), np.linalg.norm(w, axis=1)
        c = np.einsum("ij,ij->i", u, w) / np.maximum(nu * nw, 1e-300)
        out[:, k] = np.degrees(np.arccos(np.clip(c, -1, 1)))
        out[(nu == 0) | (nw == 0), k] = 0
    return out


def angle_bound(v, f):
    """The input's smallest boundary corner and one-triangle component angle (degrees, or None)."""
    ang = corner_angles(v, f)
    _, edges, _, count = edge_table(f)
    bverts = np.unique(edges[count == 1].reshape(-1))
    sums = np.zeros(len(v))
    np.add.at(sums, f.reshape(-1), ang.reshape(-1))
    corner = float(sums[bverts].min()) if len(bverts) else None
    # Components of one triangle: all three of its edges on the boundary.
    idx = {tuple(e): c for e, c in zip(map(tuple, edges), count)}
    single = [fi for fi, t in enumerate(f)
              if all(idx[tuple(sorted((int(t[k]), int(t[(k + 1) % 3]))))] == 1 for k in range(3))]
    single_min = float(ang[single].min()) if single else None
    return corner, single_min, len(single)


def closest_on_triangles(p, a, b, c):
    """The closest points to p (n x 3) on triangles (a, b, c) (n x 3 each), by regions."""
    ab, ac, ap = b - a, c - a, p - a
    d1, d2 = np.einsum("ij,ij->i", ab, ap), np.einsum("ij,ij->i", ac, ap)
    bp = p - b
    d3, d4 = np.einsum("ij,ij->i", ab, bp), np.einsum("ij,ij->i", ac, bp)
    cp = p - c
    d5, d6 = np.einsum("ij,ij->i", ab, cp), np.einsum("ij,ij->i", ac, cp)
    va, vb, vc = d3 * d6 - d5 * d4, d5 * d2 - d1 * d6, d1 * d4 - d3 * d2
    denom = va + vb + vc
    with np.errstate(divide="ignore", invalid="ignore"):
        v = vb / denom
        w = vc / denom
    out = a + ab * v[:, None] + ac * w[:, None]  # inside
    # Edges, then vertices, each overriding where its region holds.
    with np.errstate(divide="ignore", invalid="ignore"):
        t_ab = d1 / (d1 - d3)
        t_ac = d2 / (d2 - d6)
        t_bc = (d4 - d3) / ((d4 - d3) + (d5 - d6))
    r_ab = (vc <= 0) & (d1 >= 0) & (d3 <= 0)
    r_ac = (vb <= 0) & (d2 >= 0) & (d6 <= 0)
    r_bc = (va <= 0) & ((d4 - d3) >= 0) & ((d5 - d6) >= 0)
    out[r_bc] = (b + (c - b) * t_bc[:, None])[r_bc]
    out[r_ac] = (a + ac * t_ac[:, None])[r_ac]
    out[r_ab] = (a + ab * t_ab[:, None])[r_ab]
    r_a = (d1 <= 0) & (d2 <= 0)
    r_b = (d3 >= 0) & (d4 <= d3)
    r_c = (d6 >= 0) & (d5 <= d6)
    out[r_a], out[r_b], out[r_c] = a[r_a], b[r_b], c[r_c]
    bad = ~np.isfinite(out).all(axis=1)  # a degenerate triangle: its nearest vertex
    if bad.any():
        cand = np.stack([a[bad], b[bad], c[bad]], axis=1)
        k = np.argmin(np.linalg.norm(cand - p[bad][:, None, :], axis=2), axis=1)
        out[bad] = cand[np.arange(len(k)), k]
    return out


def surface_samples(v, f, n, rng):
    """Every vertex, each face's centroid and ~n points spread by area: (points, face of each or -1)."""
    a, b, c = v[f[:, 0]], v[f[:, 1]], v[f[:, 2]]
    area = 0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1)
    pts = [(a + b + c) / 3]
    faces = [np.arange(len(f))]
    if area.sum() > 0 and n > 0:
        k = rng.poisson(n * area / area.sum())
        fi = np.repeat(np.arange(len(f)), k)
        r1, r2 = rng.random(len(fi)), rng.random(len(fi))
        s = np.sqrt(r1)
        pts.append(a[fi] * (1 - s)[:, None] + b[fi] * (s * (1 - r2))[:, None] + c[fi] * (s * r2)[:, None])
        faces.append(fi)
    return np.concatenate(pts), np.concatenate(faces)


def one_sided(src_pts, v, f, tree, tree_face, k=16):
    """Each source point's distance to the surface (v, f), exact to its k candidate triangles."""
    k = min(k, len(tree_face))
    best = np.full(len(src_pts), np.inf)
    step = 20000
    for s in range(0, len(src_pts), step):
        p = src_pts[s:s + step]
        _, nn = tree.query(p, k=k, workers=-1)
        nn = nn.reshape(len(p), -1)
        for j in range(nn.shape[1]):
            t = f[tree_face[nn[:, j]]]
            q = closest_on_triangles(p, v[t[:, 0]], v[t[:, 1]], v[t[:, 2]])
            best[s:s + step] = np.minimum(best[s:s + step], np.linalg.norm(q - p, axis=1))
    return best


def on_faces(v, f, faces, bary):
    """Points of barycentrics bary (k x 2: weights of corners 1 and 2) on faces (k)."""
    t = f[faces]
    w1, w2 = bary[:, 0:1], bary[:, 1:2]
    return v[t[:, 0]] * (1 - w1 - w2) + v[t[:, 1]] * w1 + v[t[:, 2]] * w2


def grid_bary(n):
    i, j = np.meshgrid(np.arange(n + 1), np.arange(n + 1))
    keep = i + j <= n
    return np.stack([i[keep] / n, j[keep] / n], axis=1)


def exact_distances(pts, v, f):
    """Each point's distance to every triangle of (v, f), the smallest: exact, in chunks."""
    a, b, c = v[f[:, 0]], v[f[:, 1]], v[f[:, 2]]
    step = max(1, 2000000 // max(1, len(f)))
    out = np.empty(len(pts))
    for s in range(0, len(pts), step):
        p = pts[s:s + step]
        n = len(p)
        pp = np.repeat(p, len(f), axis=0)
        q = closest_on_triangles(pp, np.tile(a, (n, 1)), np.tile(b, (n, 1)), np.tile(c, (n, 1)))
        out[s:s + step] = np.linalg.norm(q - pp, axis=1).reshape(n, len(f)).min(axis=1)
    return out


def exact_max(pts, upper, v, f, slack):
    """The largest exact distance over pts, given upper bounds: the points in
    decreasing bound, until the bound is no more than the best exact (+ slack)."""
    order = np.argsort(-upper)
    best, i = 0.0, 0
    chunk = max(16, 2000000 // max(1, len(f)))
    while i < len(order) and upper[order[i]] > best + slack:
        idx = order[i:i + chunk]
        idx = idx[upper[idx] > best + slack]
        best = max(best, float(exact_distances(pts[idx], v, f).max(initial=0)))
        i += chunk
    return best


def one_direction(vs, fs, ps, ts, vt, ft, tree, tree_face, refine_faces, refine_steps, slack, zoom=20):
    """Largest distance from surface s (its vertices and samples ps on faces ts) to
    surface t; then a grid of barycentric steps on the faces of s holding the
    farthest samples, and around the farthest grid points a search that halves
    its step six times. The candidates' distances (to 16 triangles each) are
    upper bounds; the largest is then made exact against every triangle."""
    used = np.unique(fs.reshape(-1))
    pts = [np.concatenate([vs[used], ps])]
    ups = [one_sided(pts[0], vt, ft, tree, tree_face)]
    d = ups[0][len(used):]
    if refine_faces > 0 and len(d):
        top = np.unique(ts[np.argsort(d)[-refine_faces:]])
        g = grid_bary(refine_steps)
        faces = np.repeat(top, len(g))
        bary = np.tile(g, (len(top), 1))
        pts.append(on_faces(vs, fs, faces, bary))
        ups.append(one_sided(pts[-1], vt, ft, tree, tree_face))
        offsets = np.stack(np.meshgrid(np.linspace(-1, 1, 7), np.linspace(-1, 1, 7)), axis=-1).reshape(-1, 2)
        for k in np.argsort(ups[1])[-zoom:]:
            centre, face, step = bary[k], faces[k], 1.0 / refine_steps
            for _ in range(6):
                cand = np.clip(centre + step * offsets, 0, 1)
                over = cand.sum(axis=1) > 1
                cand[over] /= cand[over].sum(axis=1, keepdims=True)
                pts.append(on_faces(vs, fs, np.full(len(cand), face), cand))
                ups.append(one_sided(pts[-1], vt, ft, tree, tree_face))
                centre = cand[int(np.argmax(ups[-1]))]
                step /= 2
    return exact_max(np.concatenate(pts), np.concatenate(ups), vt, ft, slack)


def hausdorff_rel(v0, f0, v1, f1, samples, seed=1, refine_faces=200, refine_steps=40):
    rng = np.random.default_rng(seed)
    # The box of the input's surface: its vertices in faces (an unreferenced one is no part of it).
    u0 = v0[np.unique(f0.reshape(-1))]
    diag = float(np.linalg.norm(u0.max(axis=0) - u0.min(axis=0)))
    p0, t0 = surface_samples(v0, f0, samples, rng)
    p1, t1 = surface_samples(v1, f1, samples, rng)
    tree0, tree1 = cKDTree(p0), cKDTree(p1)
    slack = 1e-6 * diag  # a point's bound this close to the best exact distance is not refined
    h = max(one_direction(v0, f0, p0, t0, v1, f1, tree1, t1, refine_faces, refine_steps, slack),
            one_direction(v1, f1, p1, t1, v0, f0, tree0, t0, refine_faces, refine_steps, slack))
    return h / diag if diag > 0 else 0.0


def score(input_path, remesh_path, samples=200000):
    polygons = []
    v0, f0 = read_mesh(input_path, polygons)
    v1, f1 = read_mesh(remesh_path)
    if len(f1) == 0:
        sys.exit(f"remesh_score: {remesh_path}: no faces")
    top_in, top_out = topology(v0, f0), topology(v1, f1)
    smallest = corner_angles(v1, f1).min(axis=1)
    corner, single_min, singles = angle_bound(v0, f0)
    bounds = [x for x in (corner, single_min) if x is not None]
    keys = ("genus", "components", "boundary_loops")
    return {
        "input": input_path, "remesh": remesh_path, "vertices": int(len(v1)), "faces": int(len(f1)),
        "input_topology": top_in, "remesh_topology": top_out,
        # On an input with defects (not a surface, or zero-area faces) the engine
        # remeshes its manifold sheets, whose topology this script does not rebuild: None.
        "topology_kept": (top_out["manifold"] and all(top_in[k] == top_out[k] for k in keys)
                          if top_in["surface"] and top_in["zero_area_faces"] == 0 else None),
        "min_angle_deg": float(smallest.min()), "mean_min_angle_deg": float(smallest.mean()),
        "pct_below_25_deg": float(100 * (smallest < 25).mean()),
        "pct_below_30_deg": float(100 * (smallest < 30).mean()),
        "hausdorff_rel": hausdorff_rel(v0, f0, v1, f1, samples),
        "input_sharpest_boundary_corner_deg": corner, "input_single_triangles": singles,
        "input_single_triangle_min_angle_deg": single_min,
        "input_angle_bound_deg": min(bounds) if bounds else None,
        "input_nonplanar_polygons": nonplanar(v0, polygons, 1e-4 * float(np.linalg.norm(v0.max(axis=0) - v0.min(axis=0)))),
    }


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("input")
    ap.add_argument("remesh")
    ap.add_argument("--samples", type=int, default=200000, help="area samples per surface (and every vertex)")
    ap.add_argument("--json", action="store_true", help="one JSON object instead of lines")
    a = ap.parse_args()
    s = score(a.input, a.remesh, a.samples)
    if a.json:
        print(json.dumps(s))
        return
    t = s["remesh_topology"]
    print(f"{a.remesh}: {s['vertices']} vertices, manifold {t['manifold']}, genus {t['genus']}, "
          f"components {t['components']}, boundary loops {t['boundary_loops']}, topology kept {s['topology_kept']}")
    print(f"smallest angle {s['min_angle_deg']:.2f}, mean smallest {s['mean_min_angle_deg']:.2f} degrees, "
          f"{s['pct_below_25_deg']:.2f}% below 25; Hausdorff {100 * s['hausdorff_rel']:.3f}% of the diagonal")
    b = s["input_angle_bound_deg"]
    print("input angle bound: " + ("none (closed, no one-triangle component)" if b is None else f"{b:.2f} degrees"))


if __name__ == "__main__":
    main()
