#!/usr/bin/env python3
"""How well a remesh keeps its input's sharp features (docs/cvt.md).

  python3 tools/crease_fidelity.py INPUT.off REMESH.off --angle 30 [--json]

The input's feature edges are its interior edges whose dihedral angle (between
the normals of their two faces) exceeds --angle degrees, as `locus cvt
--features` finds them; their corners are the vertices where one or more than
two of them meet. Each feature edge is sampled at --samples points; printed:
the largest and the mean distance from a sample to the nearest remesh edge
(a crease the remesh keeps lies on remesh edges: 0), relative to the input's
bounding-box diagonal, and how many corners have a remesh vertex within 1e-6
of the diagonal. An independent check: it reads the OFF files itself and
shares no code with locus.
"""
import argparse
import json
import sys

import numpy as np


def read_off(path):
    with open(path) as f:
        words = []
        for line in f:
            line = line.split("#", 1)[0].strip()
            if line:
                words.extend(line.split())
    if words[0] != "OFF":
        sys.exit(f"{path}: not an OFF file")
    nv, nf = int(words[1]), int(words[2])
    at = 4
    v = np.array(words[at:at + 3 * nv], dtype=float).reshape(nv, 3)
    at += 3 * nv
    faces = []
    for _ in range(nf):
        k = int(words[at])
        idx = [int(w) for w in words[at + 1:at + 1 + k]]
        at += 1 + k
        for i in range(1, k - 1):  # fans
            faces.append((idx[0], idx[i], idx[i + 1]))
    return v, np.array(faces, dtype=np.int64)


def feature_edges(v, f, angle):
    n = np.cross(v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]])
    edge_faces = {}
    for fi, t in enumerate(f):
        for k in range(3):
            a, b = int(t[k]), int(t[(k + 1) % 3])
            edge_faces.setdefault((min(a, b), max(a, b)), []).append(fi)
    cos_max = np.cos(np.radians(angle))
    out = []
    for e, fs in edge_faces.items():
        if len(fs) != 2:
            continue
        na, nb = n[fs[0]], n[fs[1]]
        la, lb = np.linalg.norm(na), np.linalg.norm(nb)
        if la > 0 and lb > 0 and na @ nb < cos_max * la * lb:
            out.append(e)
    return np.array(out, dtype=np.int64).reshape(-1, 2)


def unique_edges(f):
    e = np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]])
    return np.unique(np.sort(e, axis=1), axis=0)


def point_segment_min(p, a, b, chunk=512):
    """Per point of p: the distance to the nearest segment a[i]-b[i]."""
    d = b - a
    dd = np.maximum((d * d).sum(1), 1e-300)
    best = np.empty(len(p))
    for s in range(0, len(p), chunk):
        q = p[s:s + chunk, None, :]
        t = np.clip(((q - a[None]) * d[None]).sum(2) / dd[None], 0, 1)
        r = q - (a[None] + t[..., None] * d[None])
        best[s:s + chunk] = np.sqrt((r * r).sum(2).min(1))
    return best


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("input")
    ap.add_argument("remesh")
    ap.add_argument("--angle", type=float, default=30)
    ap.add_argument("--samples", type=int, default=8, help="points per feature edge (its ends included)")
    ap.add_argument("--json", action="store_true")
    a = ap.parse_args()
    v, f = read_off(a.input)
    rv, rf = read_off(a.remesh)
    diag = float(np.linalg.norm(v.max(0) - v.min(0)))
    fe = feature_edges(v, f, a.angle)
    out = {"feature_edges": int(len(fe)), "crease_max_rel": 0.0, "crease_mean_rel": 0.0, "corners": 0,
           "corners_kept": 0}
    if len(fe):
        t = np.linspace(0, 1, a.samples)
        p = (v[fe[:, 0]][:, None, :] * (1 - t)[None, :, None] + v[fe[:, 1]][:, None, :] * t[None, :, None]).reshape(-1, 3)
        re = unique_edges(rf)
        dist = point_segment_min(p, rv[re[:, 0]], rv[re[:, 1]]) / diag
        out["crease_max_rel"] = float(dist.max())
        out["crease_mean_rel"] = float(dist.mean())
        deg = np.bincount(fe.ravel(), minlength=len(v))
        corners = np.nonzero((deg > 0) & (deg != 2))[0]
        out["corners"] = int(len(corners))
        if len(corners):
            gap = np.sqrt(((v[corners][:, None, :] - rv[None]) ** 2).sum(2)).min(1) / diag
            out["corners_kept"] = int((gap < 1e-6).sum())
    if a.json:
        print(json.dumps(out))
    else:
        print(f"feature edges {out['feature_edges']}: crease distance max {100 * out['crease_max_rel']:.3f}% "
              f"mean {100 * out['crease_mean_rel']:.4f}% of the diagonal; corners kept "
              f"{out['corners_kept']} of {out['corners']}")


if __name__ == "__main__":
    main()
