#!/usr/bin/env python3
"""ctest `blender`: the add-on (blender/locus_addon) in Debian's Blender, checked against the locus module.

    python3 tests/blender/check_addon.py --source-dir . --module-dir build/python [--keep DIR]

1. `blender -b --factory-startup --addons locus_addon` runs in_blender.py:
   every operator, twice, on the default cube subdivided (quads, scaled,
   rotated, a Cast modifier), armadillo and a non-manifold quad grid; what
   Blender holds afterwards is saved.
2. A second Blender opens the saved .blend (the results are there) and
   installs the add-on from a zip, as Preferences > Install does.
3. Here, outside Blender, the locus module computes the same numbers from the
   same input arrays, and they are compared (to float32, what Blender stores).
   Where the module refuses a mesh (locus.Error), the operator must have
   refused it with that message, as a report, with nothing written.
   Inside Blender also: the add-on's Esc path (progress callback) gives
   locus.Cancelled, a Ctrl-C during a main-thread call KeyboardInterrupt.
Prints each operator's wall time on every mesh, first call and second call
(the Session cached). Without Blender the test prints "SKIPPED:" (ctest's
SKIP_REGULAR_EXPRESSION).
"""
import argparse
import json
import os
import pathlib
import shutil
import subprocess
import sys
import tempfile
import zipfile

import numpy as np

HERE = pathlib.Path(__file__).resolve().parent
RAMP_LOW = np.array([0.267, 0.005, 0.329])  # colormap.ramp(0): the colour at a source


def blender_run(blender, args, env, timeout=1200):
    r = subprocess.run([blender, "-b", "--factory-startup", *args], env=env, capture_output=True, text=True,
                       timeout=timeout)
    output = r.stdout + r.stderr
    if r.returncode != 0 or "Traceback" in output:
        sys.exit(f"FAILED: blender {' '.join(args[:6])} ... exited {r.returncode}\n{output[-6000:]}")
    return output


def faces(d):
    offsets, indices = d["offsets"], d["indices"]
    k = np.diff(offsets)
    if (k == k[0]).all():
        return indices.reshape(-1, int(k[0]))
    return (offsets, indices)


def stretch(linear):
    w, q = np.linalg.eigh(linear.T @ linear)
    return (q * np.sqrt(w)) @ q.T


class Checker:
    def __init__(self, locus, runs):
        self.locus, self.runs, self.failures, self.checked = locus, runs, [], 0

    def record(self, mesh, op):
        return next((r for r in self.runs if r["mesh"] == mesh and r["op"] == op and "name" not in r["props"]), None)

    def expect(self, mesh, op, compare, written=lambda: False):
        """compare() computes the reference and asserts; a locus.Error there must be the operator's report."""
        rec = self.record(mesh, op)
        if rec is None:
            print(f"  {mesh:11s} {op:16s} not run")
            return
        try:
            compare()
        except self.locus.Error as e:
            for call in [k for k in ("first", "second") if k in rec]:
                if str(e) not in rec[call].get("error", ""):
                    self.failures.append(f"{mesh} {op}: locus refuses ({e}) but the operator's {call} call gave "
                                         f"{rec[call]}")
            if written():
                self.failures.append(f"{mesh} {op}: refused, but data was written")
            print(f"  {mesh:11s} {op:16s} refused as locus refuses it: {rec['first']['error'].strip()}")
            self.checked += 1
            return
        except AssertionError as e:
            self.failures.append(f"{mesh} {op}: {e}")
            return
        for call in [k for k in ("first", "second") if k in rec]:
            if "error" in rec[call]:
                self.failures.append(f"{mesh} {op}: the operator failed ({rec[call]['error']}) where locus works")
        self.checked += 1
        print(f"  {mesh:11s} {op:16s} equal to the module's numbers")


def close(a, b, what, rtol=2e-5, atol=0.0):
    a, b = np.asarray(a, np.float64), np.asarray(b, np.float64)
    assert a.shape == b.shape, f"{what}: shape {a.shape} vs {b.shape}"
    same_nan = np.isnan(a) == np.isnan(b)
    assert same_nan.all(), f"{what}: NaN at different vertices"
    ok = np.isclose(a, b, rtol=rtol, atol=atol) | np.isnan(a)
    assert ok.all(), f"{what}: {np.count_nonzero(~ok)} differ, worst {np.nanmax(np.abs(a - b)):.3g}"


def check_mesh(c, name, d):
    locus = c.locus
    F = faces(d)
    S = stretch(d["linear"])
    if name == "cube":  # scale (1, 1, 2) under a rotation: the metric frame is that scale
        assert np.allclose(S, np.diag([1.0, 1.0, 2.0]), atol=1e-5), S
    raw = d["V"].astype(np.float64) @ S
    V = d["V_eval"].astype(np.float64) @ S if "V_eval" in d else raw
    radius = float(d["radius"])
    extent = float(np.linalg.norm(V.max(0) - V.min(0)))

    def geodesic():
        ref = locus.geodesic_distance(V, F, d["sources"])
        close(d["geodesic_distance"], ref, "distance attribute", atol=1e-6 * extent)
        close(d["geodesic_weight"], np.clip(1 - np.nan_to_num(ref, nan=np.inf) / radius, 0, 1), "vertex group",
              atol=2e-6)
        assert np.allclose(d["geodesic_color"][d["sources"], :3], RAMP_LOW, atol=1e-3), "colour at the sources"
        if "raw_distance" in d:
            close(d["raw_distance"], locus.geodesic_distance(raw, F, d["sources"]), "raw mesh", atol=1e-6 * extent)
            assert not np.allclose(d["raw_distance"], d["geodesic_distance"]), "modifiers made no difference"

    def logmap():
        center, r = int(d["center"]), radius / 2
        d0 = locus.geodesic_distance(V, F, center)
        fraction = min(1.0, max(int(np.count_nonzero(d0 <= 1.5 * r)), 8) / len(V))
        ref = locus.logmap(V, F, center, fraction)
        want = np.full((len(V), 2), -1.0)
        want[ref.patch, 0] = 0.5 + ref.u / (2 * r)
        want[ref.patch, 1] = 0.5 + ref.v / (2 * r)
        close(d["decal_uv"], want, "decal UV", atol=1e-5)
        # Independently: the UV radius is the geodesic distance (a log map's radial coordinate).
        inner = ref.patch[(d0[ref.patch] > 0.2 * r) & (d0[ref.patch] < r)]
        radial = 2 * r * np.linalg.norm(d["decal_uv"][inner] - 0.5, axis=1)
        assert np.median(np.abs(radial / d0[inner] - 1)) < 0.05, "UV radius is not the geodesic distance"

    def hks():
        close(d["hks"], locus.hks(V, F, [1.0, 4.0], method="subset"), "HKS attributes")

    def remesh():
        sites, rV, rF, labels = locus.cvt(V, F, int(c.record(name, "remesh")["props"]["points"]), 10, 1)
        close(d["remesh_V"].astype(np.float64) @ S, rV, "remesh positions", atol=1e-6 * extent)
        assert np.array_equal(d["remesh_F"], rF), "remesh triangles"

    def skin():
        segments = d["bone_segments"] @ S  # each bone a handle: the vertices nearest its segment
        w = locus.Session(raw, F).skinweights_command(bone=list(segments), t="1h2").weights
        close(d["skin"], np.where(w > 1e-3, w, 0.0), "vertex groups per bone", atol=2e-6)
        assert bool(d["armature_modifier"]), "no Armature modifier added"

    c.expect(name, "geodesic", geodesic, lambda: d["geodesic_distance"].size > 0 or d["geodesic_weight"].any())
    c.expect(name, "logmap_decal", logmap, lambda: "decal_uv" in d)
    c.expect(name, "heat_signature", hks, lambda: d["hks"].size > 0)
    c.expect(name, "remesh", remesh, lambda: "remesh_V" in d)
    c.expect(name, "skinning_weights", skin, lambda: "skin" in d and d["skin"].any())


def timing_table(runs):
    lines = [f"{'mesh':11s} {'operator':16s} {'1st wall':>9s} {'1st calc':>9s} {'session':>8s} "
             f"{'2nd wall':>9s} {'2nd calc':>9s} {'session':>8s}"]
    for r in runs:
        if r["mesh"] == "cube-cache":
            continue
        a, b = r["first"], r.get("second", {"wall_s": float("nan"), "compute_s": float("nan"), "session": "-"})
        if "error" in a:
            lines.append(f"{r['mesh']:11s} {r['op']:16s} {a['wall_s']:9.3f} refused: {a['error'][:60]}")
            continue
        lines.append(f"{r['mesh']:11s} {r['op'] + ('(raw)' if 'use_modifiers' in r['props'] else ''):16s} "
                     f"{a['wall_s']:9.3f} {a['compute_s']:9.3f} {a['session']:>8s} "
                     f"{b['wall_s']:9.3f} {b['compute_s']:9.3f} {b['session']:>8s}")
    return "\n".join(lines)


def make_zip(source, path):
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as z:
        for f in sorted(source.rglob("*.py")):
            z.write(f, f"locus_addon/{f.relative_to(source)}")


REOPEN = """
import bpy, sys
me = bpy.data.objects['armadillo'].data
assert 'locus_geodesic_distance' in me.attributes and 'locus_decal' in me.uv_layers, 'results not saved'
assert bpy.data.objects['Cube'].vertex_groups.get('bone0') is not None
bpy.ops.preferences.addon_install(filepath=sys.argv[-2])
bpy.ops.preferences.addon_enable(module='locus_addon')
assert hasattr(bpy.types, 'LOCUS_PT_panel') and 'remesh' in dir(bpy.ops.locus), 'zip install failed'
bpy.context.preferences.addons['locus_addon'].preferences.module_path = sys.argv[-1]
obj = bpy.data.objects['armadillo']
bpy.context.view_layer.objects.active = obj
assert bpy.ops.locus.heat_signature(name='after_reopen') == {'FINISHED'}
assert 'after_reopen_0' in obj.data.attributes
print('REOPEN-AND-ZIP-OK')
"""


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--source-dir", type=pathlib.Path, default=HERE.parents[1])
    ap.add_argument("--module-dir", type=pathlib.Path, required=True)
    ap.add_argument("--keep", type=pathlib.Path, help="keep the outputs (saved .blend, arrays) here")
    args = ap.parse_args()
    blender = os.environ.get("BLENDER") or shutil.which("blender")
    if not blender:
        print("SKIPPED: blender is not installed (apt-get install -y --no-install-recommends blender)")
        return
    armadillo = args.source_dir / "cache" / "meshes" / "armadillo.off"
    if not armadillo.exists():
        print(f"SKIPPED: needs {armadillo} (bash tools/fetch_meshes.sh)")
        return
    sys.path.insert(0, str(args.module_dir))
    import locus

    tmp = pathlib.Path(tempfile.mkdtemp(prefix="locus-blender-"))
    out = args.keep or tmp / "out"
    out.mkdir(parents=True, exist_ok=True)
    addon = args.source_dir / "blender" / "locus_addon"
    shutil.copytree(addon, tmp / "scripts" / "addons" / "locus_addon", ignore=shutil.ignore_patterns("__pycache__"))
    env = dict(os.environ, BLENDER_USER_SCRIPTS=str(tmp / "scripts"), BLENDER_USER_CONFIG=str(tmp / "config"),
               LOCUS_MODULE_DIR=str(args.module_dir.resolve()))
    blender_run(blender, ["--addons", "locus_addon", "--python-exit-code", "1", "--python",
                          str(HERE / "in_blender.py"), "--", str(out), str(args.module_dir.resolve()), str(armadillo)], env)
    report = json.loads((out / "runs.json").read_text())
    print(f"Blender {report['info']['blender']}, locus from {report['info']['locus_file']}")
    zip_path = tmp / "locus_addon.zip"
    make_zip(addon, zip_path)
    env2 = dict(env, BLENDER_USER_SCRIPTS=str(tmp / "scripts2"))
    del env2["LOCUS_MODULE_DIR"]  # the preference names it this time
    text = blender_run(blender, [str(out / "saved.blend"), "--python-exit-code", "1", "--python-expr", REOPEN,
                                 "--", str(zip_path), str(args.module_dir.resolve())], env2)
    assert "REOPEN-AND-ZIP-OK" in text, text[-3000:]
    print("saved .blend reopens with the results; the zip installs and enables")

    blender_run(blender, ["--python", str(HERE / "sigint_in_blender.py"), "--", str(out / "sigint.json"),
                          str(args.module_dir.resolve()), str(armadillo)], env)
    report["info"].update(json.loads((out / "sigint.json").read_text()))
    c = Checker(locus, report["runs"])
    if report["info"]["cache"] != ["cached", "moved", "cached", "new"]:
        c.failures.append(f"Session cache: {report['info']['cache']}, expected cached, moved, cached, new")
    print(f"Session cache as the cube changes (same, moved vertex, same, triangulated): {report['info']['cache']}")
    modal = report["info"]["modal"]
    if modal["modal_done"]["results"][-1] != ["FINISHED"] or not modal["modal_done"]["written"]:
        c.failures.append(f"the interface path (invoke, timer events) did not finish and write: {modal['modal_done']}")
    if modal["modal_esc"]["results"][-1] != ["CANCELLED"] or modal["modal_esc"]["written"]:
        c.failures.append(f"Esc did not cancel without writing: {modal['modal_esc']}")
    print(f"interface path: {modal['modal_done']['results']}; with Esc: {modal['modal_esc']['results']}, "
          f"{modal['modal_esc']['reports']}")
    if report["info"]["sigint"] != "KeyboardInterrupt":
        c.failures.append(f"Ctrl-C during a call in Blender gave {report['info']['sigint']}, not KeyboardInterrupt")
    if not report["info"]["esc_is_cancelled"]:
        c.failures.append(f"Esc (cancel from the progress callback) raised {report['info']['esc_error']}")
    for name in ("cube", "armadillo", "nonmanifold"):
        check_mesh(c, name, np.load(out / f"{name}.npz"))
    print(timing_table(report["runs"]))
    if not args.keep:
        shutil.rmtree(tmp, ignore_errors=True)
    if c.failures:
        sys.exit("FAILED:\n  " + "\n  ".join(c.failures))
    print(f"OK: {c.checked} operator results equal the module's")


if __name__ == "__main__":
    main()
