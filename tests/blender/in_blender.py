"""Runs every locus operator inside Blender and saves what it wrote (run by check_addon.py).

    blender -b --factory-startup --addons locus_addon --python-exit-code 1 \
        --python tests/blender/in_blender.py -- OUT_DIR MODULE_DIR ARMADILLO.off

Three meshes: the default cube subdivided (quads; scaled (1, 1, 2) and
rotated, with a Cast modifier: the evaluated and the raw mesh), armadillo
(triangles) and a non-manifold quad grid with a fin on an interior edge
line. For each, every operator runs twice (the second call reuses the cached
Session); the data it wrote is read back from Blender and saved with the
input arrays to OUT_DIR/<mesh>.npz, the timings and reports to
OUT_DIR/runs.json. check_addon.py recomputes the numbers with the locus
module outside Blender and compares.
"""
import json
import os
import pathlib
import sys
import time

import bmesh
import bpy
import numpy as np

OUT, MODULE_DIR, ARMADILLO = (pathlib.Path(a) for a in sys.argv[sys.argv.index("--") + 1:][:3])
ADDON = "locus_addon"
runs = []


def mesh_object(name, V, faces):
    me = bpy.data.meshes.new(name)
    me.from_pydata([tuple(map(float, v)) for v in V], [], [list(map(int, f)) for f in faces])
    me.update()
    obj = bpy.data.objects.new(name, me)
    bpy.context.scene.collection.objects.link(obj)
    return obj


def activate(obj):
    for o in bpy.context.view_layer.objects:
        o.select_set(False)
    obj.select_set(True)
    bpy.context.view_layer.objects.active = obj


def select_vertices(obj, ids, active):
    """Selects vertices `ids` with `active` as the active vertex (select history), in Object Mode."""
    bm = bmesh.new()
    bm.from_mesh(obj.data)
    bm.verts.ensure_lookup_table()
    for v in bm.verts:
        v.select = False
    for i in ids:
        bm.verts[i].select = True
    bm.select_history.clear()
    bm.select_history.add(bm.verts[active])
    bm.to_mesh(obj.data)
    bm.free()
    obj.data.update()


def run(mesh, obj, op, also_select=None, calls=2, **props):
    """Calls bpy.ops.locus.<op> on obj (twice: the second reuses the Session); records wall times,
    the add-on's own timings and the outcome."""
    record = {"mesh": mesh, "op": op, "props": props}
    for call in ("first", "second")[:calls]:
        activate(obj)
        if also_select is not None:
            also_select.select_set(True)
        t0 = time.perf_counter()
        try:
            result = getattr(bpy.ops.locus, op)(**props)
            record[call] = {"result": sorted(result), "wall_s": time.perf_counter() - t0}
            record[call].update(sys.modules[ADDON].operator_base.LAST_RUN.get(f"LOCUS_OT_{op}", {}))
            sys.modules[ADDON].operator_base.LAST_RUN.clear()
        except RuntimeError as e:  # an ERROR report of the operator
            record[call] = {"error": str(e), "wall_s": time.perf_counter() - t0}
        print(f"locus-check: {mesh} {op} {call} call {record[call]}", flush=True)
    runs.append(record)
    return record


def vertex_group_weights(obj, name):
    w = np.zeros(len(obj.data.vertices))
    group = obj.vertex_groups.get(name)
    if group is None:
        return w
    for v in obj.data.vertices:
        for g in v.groups:
            if g.group == group.index:
                w[v.index] = g.weight
    return w


def attribute(me, name, field="value", width=1):
    a = me.attributes.get(name)
    if a is None:
        return np.zeros(0)
    out = np.empty(len(a.data) * width, np.float32)
    a.data.foreach_get(field, out)
    return out.reshape(-1, width) if width > 1 else out


def per_vertex_uv(me, name):
    layer = me.uv_layers[name]
    uv = np.empty(2 * len(me.loops), np.float32)
    layer.data.foreach_get("uv", uv)
    loops = np.empty(len(me.loops), np.int32)
    me.loops.foreach_get("vertex_index", loops)
    out = np.full((len(me.vertices), 2), np.nan, np.float32)
    out[loops] = uv.reshape(-1, 2)
    return out


def mesh_arrays(me):
    co = np.empty(3 * len(me.vertices), np.float32)
    me.vertices.foreach_get("co", co)
    totals = np.empty(len(me.polygons), np.int32)
    me.polygons.foreach_get("loop_total", totals)
    loops = np.empty(len(me.loops), np.int32)
    me.loops.foreach_get("vertex_index", loops)
    return co.reshape(-1, 3), np.concatenate([[0], np.cumsum(totals)]).astype(np.int32), loops


def armature_for(obj, V, bone_count):
    """An armature of bone_count bones stacked along the mesh's tallest axis, in the middle of the box."""
    lo, hi = V.min(0), V.max(0)
    axis = int(np.argmax(hi - lo))
    mid = (lo + hi) / 2
    arm_data = bpy.data.armatures.new(obj.name + "_rig")
    arm = bpy.data.objects.new(obj.name + "_rig", arm_data)
    bpy.context.scene.collection.objects.link(arm)
    arm.matrix_world = obj.matrix_world.copy()
    activate(arm)
    bpy.ops.object.mode_set(mode="EDIT")
    for b in range(bone_count):
        bone = arm_data.edit_bones.new(f"bone{b}")
        head, tail = mid.copy(), mid.copy()
        head[axis] = lo[axis] + (hi[axis] - lo[axis]) * (0.1 + 0.8 * b / bone_count)
        tail[axis] = lo[axis] + (hi[axis] - lo[axis]) * (0.1 + 0.8 * (b + 1) / bone_count)
        bone.head, bone.tail = tuple(head), tuple(tail)
    bpy.ops.object.mode_set(mode="OBJECT")
    return arm


def bone_segments(arm, obj):
    to_local = np.linalg.inv(np.array(obj.matrix_world)) @ np.array(arm.matrix_world)
    seg = [[(to_local @ np.append(np.array(p), 1.0))[:3] for p in (b.head_local, b.tail_local)]
           for b in arm.data.bones if b.use_deform]
    return np.array(seg), [b.name for b in arm.data.bones if b.use_deform]


def exercise(name, obj, sources, center, radius, bones, points, skin=True):
    """Every operator on obj (twice each); the inputs and what Blender holds afterwards, saved to <name>.npz."""
    me = obj.data
    V, offsets, indices = mesh_arrays(me)
    data = {"V": V, "offsets": offsets, "indices": indices, "linear": np.array(obj.matrix_world)[:3, :3],
            "sources": np.array(sources), "center": np.array(center), "radius": np.array(radius)}
    if len(obj.modifiers):
        evaluated = obj.evaluated_get(bpy.context.evaluated_depsgraph_get())
        data["V_eval"] = mesh_arrays(evaluated.to_mesh())[0]
        evaluated.to_mesh_clear()
    select_vertices(obj, sources, sources[0])
    run(name, obj, "geodesic", radius=radius)
    data["geodesic_distance"] = attribute(me, "locus_geodesic_distance")
    data["geodesic_weight"] = vertex_group_weights(obj, "locus_geodesic")
    data["geodesic_color"] = attribute(me, "locus_geodesic_color", "color", 4)
    if len(obj.modifiers):
        run(name, obj, "geodesic", radius=radius, use_modifiers=False, name="locus_raw")
        data["raw_distance"] = attribute(me, "locus_raw_distance")
    select_vertices(obj, [center], center)
    run(name, obj, "logmap_decal", radius=radius / 2)
    if "locus_decal" in me.uv_layers:
        data["decal_uv"] = per_vertex_uv(me, "locus_decal")
    run(name, obj, "heat_signature", t_factor=1.0, scales=2)
    data["hks"] = np.stack([attribute(me, "locus_hks_0"), attribute(me, "locus_hks_1")], axis=1)
    before = {o.name for o in bpy.data.objects}
    run(name, obj, "remesh", points=points)
    made = sorted({o.name for o in bpy.data.objects} - before)
    if made:
        rV, r_offsets, r_indices = mesh_arrays(bpy.data.objects[made[0]].data)
        data["remesh_V"], data["remesh_F"] = rV, r_indices.reshape(-1, 3)
        data["remesh_matrix"] = np.array(bpy.data.objects[made[0]].matrix_world)
    if not skin:
        np.savez(OUT / f"{name}.npz", **data)
        return
    arm = armature_for(obj, V, bones)
    run(name, obj, "skinning_weights", also_select=arm, calls=1)
    data["bone_segments"], bone_names = bone_segments(arm, obj)
    data["skin"] = np.stack([vertex_group_weights(obj, b) for b in bone_names], axis=1)
    data["armature_modifier"] = np.array(any(m.type == "ARMATURE" and m.object == arm for m in obj.modifiers))
    np.savez(OUT / f"{name}.npz", **data)


def cube():
    """The default cube, each face cut 7 times (8 x 8 quads), scaled (1, 1, 2), rotated, with a Cast modifier."""
    obj = bpy.data.objects["Cube"]
    activate(obj)
    bpy.ops.object.mode_set(mode="EDIT")
    bpy.ops.mesh.select_all(action="SELECT")
    bpy.ops.mesh.subdivide(number_cuts=7)
    bpy.ops.object.mode_set(mode="OBJECT")
    obj.scale = (1.0, 1.0, 2.0)
    obj.rotation_euler = (0.3, 0.2, 0.1)
    obj.location = (1.0, 2.0, 3.0)
    cast = obj.modifiers.new("Cast", "CAST")
    cast.factor = 0.5
    bpy.context.view_layer.update()
    return obj


def non_manifold():
    """A 12 x 12 quad grid with a fin of quads standing on an interior edge line: edges with three faces."""
    n = 12
    V = [(x, y, 0.0) for y in range(n + 1) for x in range(n + 1)]
    F = [(y * (n + 1) + x, y * (n + 1) + x + 1, (y + 1) * (n + 1) + x + 1, (y + 1) * (n + 1) + x)
         for y in range(n) for x in range(n)]
    row = 6 * (n + 1)
    top = len(V)
    V += [(x, 6.0, 1.0) for x in range(2, 10)]
    F += [(row + x, row + x + 1, top + x - 1, top + x - 2) for x in range(2, 9)]
    return mesh_object("nonmanifold", np.array(V) * 0.1, F)


def armadillo():
    locus = sys.modules[ADDON].engine.locus()
    V, F = locus.read_mesh(str(ARMADILLO))
    me = bpy.data.meshes.new("armadillo")
    me.vertices.add(len(V))
    me.vertices.foreach_set("co", V.astype(np.float32).ravel())
    me.loops.add(F.size)
    me.loops.foreach_set("vertex_index", F.astype(np.int32).ravel())
    me.polygons.add(len(F))
    me.polygons.foreach_set("loop_start", np.arange(0, F.size, 3, dtype=np.int32))
    me.polygons.foreach_set("loop_total", np.full(len(F), 3, np.int32))
    me.update(calc_edges=True)
    obj = bpy.data.objects.new("armadillo", me)
    bpy.context.scene.collection.objects.link(obj)
    return obj


def host_checks():
    """Esc's path (the progress callback asks to stop) gives locus.Cancelled; the add-on writes nothing then."""
    addon = sys.modules[ADDON]
    locus = addon.engine.locus()
    V, F = locus.read_mesh(str(ARMADILLO))
    s = locus.Session(V, F)
    j = addon.job.Job(lambda progress: s.geodesic_distance(0, progress=progress))
    j.cancel = True
    j.start()
    j._thread.join()
    return {"esc_error": type(j.error).__name__, "esc_is_cancelled": isinstance(j.error, locus.Cancelled),
            "locus_file": locus.__file__, "blender": bpy.app.version_string}


def cache_check(obj):
    """The Session cache follows the mesh: new positions keep it (set_positions), new faces replace it."""
    select_vertices(obj, [0], 0)
    seen = [run("cube-cache", obj, "geodesic", calls=1, name="cache", use_modifiers=False)["first"]["session"]]
    obj.data.vertices[1].co.x += 0.05
    obj.data.update()
    seen.append(run("cube-cache", obj, "geodesic", calls=1, name="cache", use_modifiers=False)["first"]["session"])
    seen.append(run("cube-cache", obj, "geodesic", calls=1, name="cache", use_modifiers=False)["first"]["session"])
    activate(obj)
    bpy.ops.object.mode_set(mode="EDIT")
    bpy.ops.mesh.select_all(action="SELECT")
    bpy.ops.mesh.quads_convert_to_tris()
    bpy.ops.object.mode_set(mode="OBJECT")
    select_vertices(obj, [0], 0)
    seen.append(run("cube-cache", obj, "geodesic", calls=1, name="cache", use_modifiers=False)["first"]["session"])
    return seen


class _Recorder:
    """Stand-ins for what modal operators get from a window: the window manager, workspace, events."""

    def __init__(self):
        self.calls = []

    def __getattr__(self, name):
        return lambda *args, **kwargs: self.calls.append((name, args)) or name


def modal_check(obj):
    """The interface path (invoke + modal with timer events, Esc) driven by hand, as a window would.

    Background Blender has no event loop, so an object with the operator's
    mixin and the geodesic operator's prepare() stands in for the registered
    operator; it computes on the worker thread and writes on the last timer
    event, and after Esc it writes nothing."""
    addon = sys.modules[ADDON]
    base, ops = addon.operator_base, addon.operators

    class Modal(base.LocusOperator):
        bl_label, bl_idname = "modal check", "LOCUS_OT_modal_check"
        radius, t_factor, use_modifiers = 0.0, 0.0, False
        prepare = ops.LOCUS_OT_geodesic.prepare

        def __init__(self, name):
            self.name, self.reports = name, []

        def report(self, kind, text):
            self.reports.append((sorted(kind), text))

        def _interactive(self, context):
            return True

    Event = type("Event", (), {})
    timer, esc = Event(), Event()
    timer.type, timer.value, esc.type, esc.value = "TIMER", "NOTHING", "ESC", "PRESS"
    out = {}
    for name, events in (("modal_done", []), ("modal_esc", [esc])):
        activate(obj)
        select_vertices(obj, [0], 0)
        ctx = type("Context", (), {})()
        ctx.active_object, ctx.window, ctx.window_manager = obj, object(), _Recorder()
        ctx.workspace, ctx.view_layer, ctx.preferences = _Recorder(), bpy.context.view_layer, bpy.context.preferences
        op = Modal(name)
        results = [sorted(op.invoke(ctx, None))]
        for e in events:
            results.append(sorted(op.modal(ctx, e)))
        for _ in range(3000):
            r = op.modal(ctx, timer)
            if r != {"PASS_THROUGH"}:
                results.append(sorted(r))
                break
            time.sleep(0.01)
        out[name] = {"results": results, "written": obj.vertex_groups.get(name) is not None,
                     "reports": op.reports, "status": [c for c in ctx.workspace.calls][-1:]}
    return out


def main():
    # --addons enabled it (without preferences: LOCUS_MODULE_DIR names the module's folder).
    assert ADDON in sys.modules and hasattr(bpy.types, "LOCUS_PT_panel") and "remesh" in dir(bpy.ops.locus)
    info = host_checks()
    exercise("cube", cube(), sources=[0, 5], center=10, radius=1.5, bones=2, points=300)
    exercise("armadillo", armadillo(), sources=[0], center=100, radius=30.0, bones=4, points=1000)
    exercise("nonmanifold", non_manifold(), sources=[0], center=20, radius=0.5, bones=2, points=60)
    saved = OUT / "saved.blend"
    bpy.ops.wm.save_as_mainfile(filepath=str(saved))
    info["saved"] = str(saved)
    info["modal"] = modal_check(bpy.data.objects["Cube"])
    info["cache"] = cache_check(bpy.data.objects["Cube"])
    (OUT / "runs.json").write_text(json.dumps({"info": info, "runs": runs}, indent=1, default=str))


main()
