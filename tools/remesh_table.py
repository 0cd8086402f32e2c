#!/usr/bin/env python3
"""The remesh table: `locus cvt MESH --sites N -o out.obj --json` on sample meshes.

One row per mesh: exit status, wall time, whether the remesh kept the input's
genus, components and boundary loops (from the JSON's `remesh` and
`remesh.input`, both computed by remesh_quality.hpp), smallest angle, mean
smallest angle, delivered vs requested vertices, added sites, Hausdorff
distance. Targets (docs/cvt.md): exit 0 with the topology kept on every
manifold mesh; smallest angle >= 25 and mean >= 50 degrees on meshes with at
least 3000 vertices; delivered vertices within 2% of the requested. Every
mesh gets the same number of points, as geogram's vorpalite takes them (a
mesh with fewer vertices is remeshed on its subdivision); --cap-at-vertices
asks for at most one point per input vertex instead. A row breaking a target
is marked.

With --score (run it with /usr/bin/python3: numpy and scipy) every remesh is
scored again by tools/remesh_score.py, from the files alone: the row's
topology, angles and Hausdorff distance are then the independent ones, the
engine's own are kept beside them (`engine`) and a disagreement is marked,
and the input's angle bound (its sharpest boundary corner or one-triangle
component) is given: a smallest angle at that bound is the input's. On an
input with defects (non-manifold, zero-area faces) the topology's verdict
stays the engine's, against its manifold sheets ("yes (engine)"); on an
input with non-planar polygons the two Hausdorff distances are not compared
(each triangulates them its own way: two surfaces).

  python3 tools/remesh_table.py --locus build/locus --min-vertices 3000
  python3 tools/remesh_table.py --meshes three_peaks cow camel --json-out t.json
  /usr/bin/python3 tools/remesh_table.py --score --json-out t.json
"""
import argparse
import json
import os
import re
import subprocess
import sys
import tempfile
import time


def off_vertex_count(path):
    """Vertices of an OFF file (its header), or -1."""
    with open(path, encoding="utf-8", errors="replace") as f:
        toks = []
        for line in f:
            toks += line.split("#")[0].split()
            if len(toks) >= 4:
                break
    if not toks or not toks[0].endswith("OFF"):
        return -1
    try:
        return int(toks[1])
    except (IndexError, ValueError):
        return -1


def run_one(locus, path, sites, timeout, extra, scorer=None):
    """One remesh: (exit status, wall seconds, JSON or None, last stderr line, independent score or None)."""
    with tempfile.TemporaryDirectory() as tmp:
        cmd = [locus, "cvt", path, "--sites", str(sites), "-o", os.path.join(tmp, "out.obj"), "--json"] + extra
        t0 = time.monotonic()
        try:
            p = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
        except subprocess.TimeoutExpired:
            return None, time.monotonic() - t0, None, "timeout", None
        wall = time.monotonic() - t0
        try:
            j = json.loads(p.stdout) if p.stdout.strip() else None
        except json.JSONDecodeError:
            j = None
        err = p.stderr.strip().splitlines()
        out = os.path.join(tmp, "out.obj")
        sc = None
        if scorer and p.returncode == 0 and os.path.exists(out):
            try:
                sc = scorer(path, out)
            except (SystemExit, ValueError, IndexError) as e:  # an unreadable file: the row keeps the engine's figures
                print("remesh_table: %s: not scored: %s" % (path, e), file=sys.stderr)
        return p.returncode, wall, j, (err[-1] if err else ""), sc


def independent(r, sc):
    """The row's figures from the independent score; the engine's kept beside them, disagreements marked."""
    engine = {k: r[k] for k in ("kept", "topology", "min_angle", "mean_min_angle", "hausdorff_pct")}
    t = sc["remesh_topology"]
    # On an input with defects the engine's comparison (with its manifold sheets) stands.
    if sc["topology_kept"] is not None:
        r["kept"] = bool(sc["topology_kept"])
    else:
        r["kept_by"] = "engine"
    r["topology"] = "g%s c%s b%s" % (t["genus"], t["components"], t["boundary_loops"])
    r["min_angle"] = round(sc["min_angle_deg"], 1)
    r["mean_min_angle"] = round(sc["mean_min_angle_deg"], 1)
    r["hausdorff_pct"] = round(100 * sc["hausdorff_rel"], 2)
    b = sc["input_angle_bound_deg"]
    r["input_bound"] = None if b is None else round(b, 1)
    r["engine"] = engine
    r["disagree"] = [k for k in ("kept", "topology", "min_angle", "mean_min_angle") if engine[k] != r[k]]
    # Both are distances met on the surfaces (lower bounds), the engine's within
    # 1% of the true one: more than 2% apart is a disagreement. Not compared: an
    # input with defects (the engine measures to its sheets, without the dropped
    # faces) or with non-planar polygons (two triangulations, two surfaces).
    h = engine["hausdorff_pct"]
    r["nonplanar_polygons"] = sc["input_nonplanar_polygons"]
    if h is not None and not r.get("kept_by") and not r["nonplanar_polygons"] and abs(h - r["hausdorff_pct"]) > 0.02 * max(h, r["hausdorff_pct"]) + 0.005:
        r["disagree"].append("hausdorff")


def row_of(name, nv, sites, code, wall, j, err, angle_min_vertices, sc=None):
    r = {"mesh": name, "input_vertices": nv, "exit": code, "wall_s": round(wall, 2)}
    rem = (j or {}).get("remesh")
    if code != 0 or not rem:
        r["error"] = err[:160]
        return r
    inp = rem.get("input", {})
    r["kept"] = bool(rem["manifold"]) and all(rem[k] == inp.get(k) for k in ("genus", "components", "boundary_loops"))
    r["topology"] = "g%s c%s b%s" % (rem["genus"], rem["components"], rem["boundary_loops"])
    r["min_angle"] = round(rem["min_angle_deg"], 1)
    r["mean_min_angle"] = round(rem["mean_min_angle_deg"], 1)
    r["delivered"] = rem["vertices"]
    r["requested"] = sites
    r["added_sites"] = rem.get("added_sites", 0)
    r["hausdorff_pct"] = round(100 * rem["hausdorff_rel"], 2) if rem.get("hausdorff_rel", -1) >= 0 else None
    if sc:
        independent(r, sc)
    fails = []
    if not r["kept"]:
        fails.append("topology")
    if nv >= angle_min_vertices and (r["min_angle"] < 25 or r["mean_min_angle"] < 50):
        fails.append("angles")
    if abs(r["delivered"] - sites) > 0.02 * sites:
        fails.append("density")
    if r.get("disagree"):
        fails.append("engine's figures: " + "/".join(r["disagree"]))
    r["fails"] = fails
    return r


def min_cell(r):
    if "input_bound" not in r:
        return "%.1f" % r["min_angle"]
    return "%.1f (%s)" % (r["min_angle"], "-" if r["input_bound"] is None else "%.1f" % r["input_bound"])


def markdown(rows):
    scored = any("input_bound" in r for r in rows)
    head = "| mesh | n | exit | wall s | topology kept | min ° | mean min ° | delivered | added | Hausdorff % | fails |"
    if scored:
        head = head.replace("| min ° |", "| min ° (input bound) |")
    out = [head, "|" + "---|" * 11]
    for r in rows:
        if "error" in r:
            out.append("| %s | %d | %s | %.2f | - | - | - | - | - | - | %s |" %
                       (r["mesh"], r["input_vertices"], r["exit"], r["wall_s"], r["error"].replace("|", "/")))
            continue
        out.append("| %s | %d | %d | %.2f | %s (%s) | %s | %.1f | %d | %d | %s | %s |" % (
            r["mesh"], r["input_vertices"], r["exit"], r["wall_s"],
            ("yes" if r["kept"] else "NO") + (" (engine)" if r.get("kept_by") else ""), r["topology"],
            min_cell(r), r["mean_min_angle"], r["delivered"], r["added_sites"],
            "-" if r["hausdorff_pct"] is None else "%.2f" % r["hausdorff_pct"], ", ".join(r["fails"]) or "-"))
    return "\n".join(out)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--locus", default="build/locus")
    ap.add_argument("--dir", default="cache/meshes")
    ap.add_argument("--sites", type=int, default=1000)
    ap.add_argument("--min-vertices", type=int, default=0, help="only meshes with at least this many vertices")
    ap.add_argument("--angle-min-vertices", type=int, default=3000, help="angle targets from this many vertices")
    ap.add_argument("--meshes", nargs="*", help="mesh names (without .off); default: every OFF in --dir")
    ap.add_argument("--skip", nargs="*", default=[], help="mesh names to leave out")
    ap.add_argument("--cap-at-vertices", action="store_true", help="at most one point per input vertex")
    ap.add_argument("--timeout", type=float, default=900)
    ap.add_argument("--json-out", help="also write the rows as JSON")
    ap.add_argument("--score", action="store_true", help="score every remesh again with tools/remesh_score.py")
    ap.add_argument("extra", nargs="*", help="after --: more `locus cvt` options")
    a = ap.parse_args()
    scorer = None
    if a.score:
        sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
        try:
            import remesh_score
        except ImportError as e:
            sys.exit("remesh_table: --score needs numpy and scipy (python3-numpy, python3-scipy: bash tools/setup.sh --bench-peers; run with /usr/bin/python3): %s" % e)
        scorer = remesh_score.score
    names = a.meshes or sorted(re.sub(r"\.off$", "", f) for f in os.listdir(a.dir) if f.endswith(".off"))
    rows = []
    for name in names:
        if name in a.skip:
            continue
        path = os.path.join(a.dir, name + ".off")
        nv = off_vertex_count(path)
        if nv < a.min_vertices or nv < 1:
            continue
        sites = min(a.sites, nv) if a.cap_at_vertices else a.sites
        code, wall, j, err, sc = run_one(a.locus, path, sites, a.timeout, a.extra, scorer)
        r = row_of(name, nv, sites, code, wall, j, err, a.angle_min_vertices, sc)
        rows.append(r)
        print(json.dumps(r), file=sys.stderr, flush=True)
    print(markdown(rows))
    bad = [r["mesh"] for r in rows if "error" in r or r["fails"]]
    print("\n%d meshes, %d off target%s" % (len(rows), len(bad), (": " + ", ".join(bad)) if bad else ""))
    if a.json_out:
        with open(a.json_out, "w", encoding="utf-8") as f:
            json.dump(rows, f, indent=1)
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
