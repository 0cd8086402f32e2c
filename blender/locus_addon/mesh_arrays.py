"""A Blender mesh as the arrays locus takes, in a metric frame, and results mapped back.

Positions: the object's scale and shear are applied, rotation and location
are not (V = S v, with matrix_world's linear part = R S, S symmetric): distances
and radii are in scene units on scaled objects, while moving or rotating the
object leaves V, hence the cached Session, unchanged.

Faces: triangles as (m, 3); quads, n-gons and mixed meshes as a uniform
(m, k) array or (offsets, indices), the polygon path of locus.Session.
Loose vertices (in no face; locus refuses unreferenced vertices) are left
out and get no value (NaN, weight 0) in per-vertex results.
"""
import numpy as np

from . import engine


class MeshArrays:
    """V (n, 3) float64, F, and how they relate to the Blender mesh they came from."""

    def __init__(self, co, starts, totals, loop_vertices, materials, linear):
        nv = len(co)
        self.num_mesh_vertices = nv
        self.totals = totals
        self.materials = materials
        offsets = np.zeros(len(totals) + 1, np.int64)
        np.cumsum(totals, out=offsets[1:])
        if np.array_equal(starts, offsets[:-1]):
            indices = loop_vertices
        else:  # loops not in polygon order: gather each polygon's
            indices = np.concatenate([loop_vertices[s:s + t] for s, t in zip(starts, totals)]) \
                if len(totals) else loop_vertices[:0]
        used = np.zeros(nv, bool)
        used[indices] = True
        self.kept = None if used.all() else np.flatnonzero(used).astype(np.int32)
        if self.kept is not None:  # renumber without the loose vertices
            new_id = np.full(nv, -1, np.int32)
            new_id[self.kept] = np.arange(len(self.kept), dtype=np.int32)
            indices = new_id[indices]
            co = co[self.kept]
        self.stretch = stretch_of(linear)
        self.V = np.ascontiguousarray(co.astype(np.float64) @ self.stretch.T)
        if len(totals) and (totals == totals[0]).all():
            self.F = np.ascontiguousarray(indices.reshape(-1, int(totals[0])), dtype=np.int32)
        else:
            self.F = (offsets.astype(np.int32), np.ascontiguousarray(indices, dtype=np.int32))
        faces = self.F if isinstance(self.F, np.ndarray) else np.concatenate(self.F)
        self.faces_key = engine.digest(np.asarray(faces), np.asarray(totals))
        self.positions_key = engine.digest(self.V)

    def session_ids(self, mesh_ids):
        """Mesh vertex ids -> the ids of V (loose vertices dropped)."""
        mesh_ids = np.asarray(mesh_ids, np.int64)
        if self.kept is None:
            return mesh_ids.astype(np.int32)
        pos = np.searchsorted(self.kept, mesh_ids)
        ok = (pos < len(self.kept)) & (self.kept[np.minimum(pos, len(self.kept) - 1)] == mesh_ids)
        return pos[ok].astype(np.int32)

    def to_mesh(self, values, fill):
        """Per-V values -> per-mesh-vertex values (`fill` at loose vertices)."""
        values = np.asarray(values)
        if self.kept is None:
            return values
        out = np.full((self.num_mesh_vertices,) + values.shape[1:], fill, values.dtype)
        out[self.kept] = values
        return out

    def to_local(self, V):
        """Positions in the metric frame -> the object's local coordinates."""
        return np.asarray(V) @ np.linalg.inv(self.stretch).T


def stretch_of(linear):
    """S of the polar decomposition linear = R S (S symmetric positive semi-definite)."""
    a = np.asarray(linear, np.float64)
    w, q = np.linalg.eigh(a.T @ a)
    return (q * np.sqrt(np.maximum(w, 0.0))) @ q.T


def read_mesh(me, linear):
    """MeshArrays of the bpy Mesh `me` with matrix_world's 3x3 part `linear`."""
    nv, npoly, nloop = len(me.vertices), len(me.polygons), len(me.loops)
    if npoly == 0:
        raise ValueError(f"mesh '{me.name}' has no faces")
    co = np.empty(3 * nv, np.float32)
    me.vertices.foreach_get("co", co)
    starts = np.empty(npoly, np.int32)
    totals = np.empty(npoly, np.int32)
    materials = np.empty(npoly, np.int32)
    me.polygons.foreach_get("loop_start", starts)
    me.polygons.foreach_get("loop_total", totals)
    me.polygons.foreach_get("material_index", materials)
    loops = np.empty(nloop, np.int32)
    me.loops.foreach_get("vertex_index", loops)
    return MeshArrays(co.reshape(-1, 3), starts, totals, loops, materials, linear)


def object_arrays(context, obj, use_modifiers, same_vertices):
    """(MeshArrays, warning) of a mesh object; the evaluated mesh when use_modifiers.

    same_vertices: the result is written per vertex of obj.data, so an
    evaluated mesh with another vertex count cannot be used; the raw mesh is,
    and `warning` says so.
    """
    if obj is None or obj.type != "MESH":
        raise ValueError("the active object must be a mesh")
    if obj.mode == "EDIT":
        obj.update_from_editmode()
    linear = [list(r)[:3] for r in list(obj.matrix_world)[:3]]
    warning = None
    if use_modifiers:
        evaluated = obj.evaluated_get(context.evaluated_depsgraph_get())
        me = evaluated.to_mesh()
        try:
            if not same_vertices or len(me.vertices) == len(obj.data.vertices):
                return read_mesh(me, linear), None
        finally:
            evaluated.to_mesh_clear()
        warning = (f"the modifiers of '{obj.name}' change its vertex count, so the result cannot be written "
                   "per vertex: used the mesh without modifiers")
    return read_mesh(obj.data, linear), warning


def selected_vertices(me):
    sel = np.empty(len(me.vertices), bool)
    me.vertices.foreach_get("select", sel)
    return np.flatnonzero(sel)
