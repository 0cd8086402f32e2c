"""Writing locus results into Blender data: vertex groups, attributes, UV maps, new meshes.

Called on the main thread only, after the computation succeeded, so a
cancelled or failed call leaves the data as it was. Results are written in
Object Mode (Edit Mode keeps its own copy of the mesh and would overwrite
them); the mode is restored afterwards.
"""
import contextlib

import bpy
import numpy as np


@contextlib.contextmanager
def object_mode(context, obj):
    mode = obj.mode
    switch = mode != "OBJECT" and context.view_layer.objects.active == obj
    if switch:
        bpy.ops.object.mode_set(mode="OBJECT")
    try:
        yield
    finally:
        if switch:
            bpy.ops.object.mode_set(mode=mode)


def vertex_group(obj, name, weights, threshold=0.0):
    """Replaces the vertex group `name` with weights (one per mesh vertex; <= threshold and NaN: not in it)."""
    old = obj.vertex_groups.get(name)
    if old is not None:
        obj.vertex_groups.remove(old)
    group = obj.vertex_groups.new(name=name)
    w = np.nan_to_num(np.asarray(weights, np.float64), nan=0.0)
    for v in np.flatnonzero(w > threshold):
        group.add([int(v)], float(w[v]), "REPLACE")
    return group


def _replace_attribute(me, name):
    old = me.attributes.get(name)
    if old is not None:
        me.attributes.remove(old)


def color_attribute(me, name, rgba):
    """A per-vertex float colour attribute (replacing one of that name), made the active colour."""
    _replace_attribute(me, name)
    attr = me.color_attributes.new(name, "FLOAT_COLOR", "POINT")
    attr.data.foreach_set("color", np.ascontiguousarray(rgba, np.float32).ravel())
    me.color_attributes.active_color = attr
    me.color_attributes.render_color_index = me.color_attributes.active_color_index
    return attr


def float_attribute(me, name, values):
    """A per-vertex float attribute (NaN kept: geometry nodes can test it)."""
    _replace_attribute(me, name)
    attr = me.attributes.new(name, "FLOAT", "POINT")
    attr.data.foreach_set("value", np.ascontiguousarray(values, np.float32))
    return attr


def uv_map(me, name, uv, make_active=True):
    """A UV map from per-vertex uv (n, 2): every corner of a vertex gets its value."""
    layer = me.uv_layers.get(name) or me.uv_layers.new(name=name)
    loops = np.empty(len(me.loops), np.int32)
    me.loops.foreach_get("vertex_index", loops)
    layer.data.foreach_set("uv", np.ascontiguousarray(np.asarray(uv, np.float32)[loops]).ravel())
    if make_active:
        me.uv_layers.active = layer
    return layer


def new_mesh(name, V, F, face_material=None, materials=(), smooth=False):
    """A bpy Mesh from triangles: V (n, 3) local positions, F (m, 3) ids."""
    F = np.ascontiguousarray(F, np.int32)
    me = bpy.data.meshes.new(name)
    me.vertices.add(len(V))
    me.vertices.foreach_set("co", np.ascontiguousarray(V, np.float32).ravel())
    me.loops.add(F.size)
    me.loops.foreach_set("vertex_index", F.ravel())
    me.polygons.add(len(F))
    me.polygons.foreach_set("loop_start", np.arange(0, F.size, 3, dtype=np.int32))
    me.polygons.foreach_set("loop_total", np.full(len(F), 3, np.int32))
    for m in materials:
        me.materials.append(m)
    if face_material is not None and len(materials):
        me.polygons.foreach_set("material_index", np.ascontiguousarray(face_material, np.int32))
    me.polygons.foreach_set("use_smooth", np.full(len(F), bool(smooth)))
    me.update(calc_edges=True)
    me.validate(verbose=False)
    return me
