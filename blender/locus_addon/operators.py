"""The locus operators: remesh, geodesic distance, log-map decal, skinning weights, HKS.

Each reads the active mesh object (operator_base.LocusOperator runs it) and
uses the Session cached for that object (engine.session). Lengths (radii)
are in scene units, measured on the object with its scale applied.
"""
import bmesh
import bpy
import numpy as np
from bpy.props import BoolProperty, FloatProperty, IntProperty, StringProperty

from . import bone_handles, colormap, engine, mesh_arrays, mesh_write
from .operator_base import LocusOperator, Task

_MODIFIERS = "Use the evaluated mesh (modifiers applied); off: the mesh data without modifiers"
_T_FACTOR = "Heat time t = t_factor * h^2, h the mean edge length (0: locus' default)"


def _session(task, use_modifiers, arrays):
    """The object's cached Session (worker thread: only names and arrays, no bpy data)."""
    s, task.session_how = engine.session((task.object_name, bool(use_modifiers)), arrays)
    return s


def _prepare_arrays(op, context, task_warnings, same_vertices):
    arrays, warning = mesh_arrays.object_arrays(context, context.active_object, op.use_modifiers, same_vertices)
    if warning:
        task_warnings.append(warning)
    return arrays


def _polygon_of_vertex(arrays):
    """One polygon (of the faces as given) holding each vertex of arrays.V."""
    F = arrays.F
    indices = F.ravel() if isinstance(F, np.ndarray) else F[1]
    poly = np.repeat(np.arange(len(arrays.totals), dtype=np.int32), arrays.totals)
    out = np.zeros(len(arrays.V), np.int32)
    out[indices] = poly
    return out


def _optional(t_factor):
    return None if t_factor <= 0 else float(t_factor)


class LOCUS_OT_remesh(LocusOperator, bpy.types.Operator):
    """Remesh the active object by a heat-diffusion centroidal Voronoi tessellation (isotropic)"""
    bl_idname = "locus.remesh"
    bl_label = "Remesh (heat CVT)"
    bl_options = {"REGISTER", "UNDO"}

    points: IntProperty(name="Points", description="Vertices of the new mesh (CVT sites)", default=2000, min=4)
    iterations: IntProperty(name="Iterations", description="Lloyd steps", default=10, min=0, max=500)
    seed: IntProperty(name="Seed", description="Seed of the random initial sites", default=1, min=0)
    replace: BoolProperty(name="Replace Mesh", description="Replace the object's mesh data (else a new object)",
                          default=False)
    use_modifiers: BoolProperty(name="Use Modifiers", description=_MODIFIERS, default=True)

    def prepare(self, context):
        obj = context.active_object
        task = Task(obj, None, None)
        arrays = _prepare_arrays(self, context, task.warnings, same_vertices=False)
        smooth = np.empty(len(obj.data.polygons), bool)
        obj.data.polygons.foreach_get("use_smooth", smooth)
        points, iterations, seed, use_modifiers, replace = self.points, self.iterations, self.seed, \
            self.use_modifiers, self.replace
        if replace and use_modifiers and len(obj.modifiers):
            task.warnings.append("the new mesh data has the modifiers applied, and the object's modifiers "
                                 "apply again on top of it")

        def compute(progress):
            s = _session(task, use_modifiers, arrays)
            return s.cvt(points, iterations, seed, remesh=True, progress=progress), s.triangle_polygon

        def apply(context, obj, result):
            r, triangle_polygon = result
            site_poly = np.where(r.site_face >= 0, triangle_polygon[np.maximum(r.site_face, 0)],
                                 _polygon_of_vertex(arrays)[np.maximum(r.site_vertex, 0)])
            first_site = np.asarray(r.remesh_site)[r.remesh_F[:, 0]]
            material = arrays.materials[site_poly[np.clip(first_site, 0, len(site_poly) - 1)]]
            me = mesh_write.new_mesh(obj.data.name + "_remesh", arrays.to_local(r.remesh_V), r.remesh_F,
                                     material, list(obj.data.materials), smooth.mean() > 0.5 if len(smooth) else False)
            if replace:
                with mesh_write.object_mode(context, obj):
                    obj.data = me
            else:
                new = bpy.data.objects.new(obj.name + "_remesh", me)
                new.matrix_world = obj.matrix_world.copy()
                for c in obj.users_collection or [context.scene.collection]:
                    c.objects.link(new)
                if obj.mode == "OBJECT":
                    obj.select_set(False)
                    new.select_set(True)
                    context.view_layer.objects.active = new
            return (f"{len(r.remesh_V)} vertices, {len(r.remesh_F)} triangles, min angle "
                    f"{r.min_angle_deg:.1f} deg, Hausdorff {r.hausdorff_rel:.2e} of the diagonal")

        task.compute, task.apply = compute, apply
        return task


class LOCUS_OT_geodesic(LocusOperator, bpy.types.Operator):
    """Geodesic distance from the selected vertices: a vertex group (falloff) and colour attribute"""
    bl_idname = "locus.geodesic"
    bl_label = "Geodesic Distance"
    bl_options = {"REGISTER", "UNDO"}

    radius: FloatProperty(name="Falloff Radius", description="Weight 1 at the sources, 0 at this distance "
                          "(0: the farthest vertex)", default=0.0, min=0.0, subtype="DISTANCE", unit="LENGTH")
    t_factor: FloatProperty(name="Heat Time", description=_T_FACTOR, default=0.0, min=0.0)
    name: StringProperty(name="Name", description="Vertex group; attributes NAME_distance and NAME_color",
                         default="locus_geodesic")
    use_modifiers: BoolProperty(name="Use Modifiers", description=_MODIFIERS, default=True)

    def prepare(self, context):
        obj = context.active_object
        task = Task(obj, None, None, num_vertices=len(obj.data.vertices))
        arrays = _prepare_arrays(self, context, task.warnings, same_vertices=True)
        sources = arrays.session_ids(mesh_arrays.selected_vertices(obj.data))
        if len(sources) == 0:
            raise ValueError("select the source vertices first (Edit Mode)")
        t_factor, radius, name, use_modifiers = _optional(self.t_factor), self.radius, self.name, self.use_modifiers

        def compute(progress):
            s = _session(task, use_modifiers, arrays)
            return s.geodesic_distance(sources, t_factor=t_factor, progress=progress)

        def apply(context, obj, d):
            d = arrays.to_mesh(d, np.nan)
            far = float(np.nanmax(d)) if np.isfinite(d).any() else 0.0
            r = radius if radius > 0 else (far or 1.0)
            with mesh_write.object_mode(context, obj):
                mesh_write.vertex_group(obj, name, np.clip(1.0 - d / r, 0.0, 1.0))
                mesh_write.float_attribute(obj.data, name + "_distance", d)
                mesh_write.color_attribute(obj.data, name + "_color", colormap.ramp(d / r))
            return f"{len(sources)} sources, farthest vertex at {far:.4g}, falloff radius {r:.4g}"

        task.compute, task.apply = compute, apply
        return task


def active_vertex(obj):
    """The only selected vertex, else the active one (Edit Mode's last selected)."""
    selected = mesh_arrays.selected_vertices(obj.data)
    if len(selected) == 1:
        return int(selected[0])
    if obj.mode == "EDIT":
        bm = bmesh.from_edit_mesh(obj.data)
        active = bm.select_history.active
        if isinstance(active, bmesh.types.BMVert):
            return active.index
    else:
        bm = bmesh.new()
        try:
            bm.from_mesh(obj.data)
            active = bm.select_history.active
            if isinstance(active, bmesh.types.BMVert):
                return active.index
        finally:
            bm.free()
    raise ValueError("select the decal's centre vertex (the active vertex in Edit Mode)")


class LOCUS_OT_logmap_decal(LocusOperator, bpy.types.Operator):
    """A UV map for a decal around the active vertex (the logarithmic map of the geodesic disk)"""
    bl_idname = "locus.logmap_decal"
    bl_label = "Log-Map Decal"
    bl_options = {"REGISTER", "UNDO"}

    radius: FloatProperty(name="Radius", description="Geodesic radius the decal's unit square spans (0: 5% "
                          "of the object's size)", default=0.0, min=0.0, subtype="DISTANCE", unit="LENGTH")
    rotation: FloatProperty(name="Rotation", description="Rotation of the decal about its centre",
                            default=0.0, subtype="ANGLE")
    t_factor: FloatProperty(name="Heat Time", description=_T_FACTOR, default=0.0, min=0.0)
    name: StringProperty(name="UV Map", default="locus_decal")
    use_modifiers: BoolProperty(name="Use Modifiers", description=_MODIFIERS, default=True)

    def prepare(self, context):
        obj = context.active_object
        task = Task(obj, None, None, num_vertices=len(obj.data.vertices))
        arrays = _prepare_arrays(self, context, task.warnings, same_vertices=True)
        center = arrays.session_ids([active_vertex(obj)])
        if len(center) == 0:
            raise ValueError("the centre vertex is in no face")
        center = int(center[0])
        extent = float(np.linalg.norm(arrays.V.max(0) - arrays.V.min(0)))
        radius = self.radius if self.radius > 0 else 0.05 * extent
        t_factor, rotation, name, use_modifiers = _optional(self.t_factor), self.rotation, self.name, \
            self.use_modifiers

        def compute(progress):
            s = _session(task, use_modifiers, arrays)
            d = s.geodesic_distance(center, t_factor=t_factor)
            # The patch reaches 1.5 radii: the unit square's corners (sqrt(2) radii) lie inside it.
            inside = int(np.count_nonzero(d <= 1.5 * radius))
            fraction = min(1.0, max(inside, 8) / len(d))
            return s.logmap(center, fraction, t_factor=t_factor, progress=progress)

        def apply(context, obj, r):
            c, s_ = np.cos(rotation), np.sin(rotation)
            uv = np.full((len(arrays.V), 2), -1.0)
            uv[r.patch, 0] = 0.5 + (c * r.u - s_ * r.v) / (2 * radius)
            uv[r.patch, 1] = 0.5 + (s_ * r.u + c * r.v) / (2 * radius)
            with mesh_write.object_mode(context, obj):
                mesh_write.uv_map(obj.data, name, arrays.to_mesh(uv, -1.0))
            inj = r.injectivity_radius
            if inj is not None and inj < radius:
                task.warnings.append(f"the log map folds over at distance {inj:.4g}, inside the decal radius "
                                     f"{radius:.4g}: the decal will be distorted there")
            inj_text = "none flipped in the patch" if inj is None else f"{inj:.4g}"
            return (f"UV map '{name}' around vertex {center}: radius {radius:.4g}, {len(r.patch)} vertices, "
                    f"injectivity radius {inj_text}")

        task.compute, task.apply = compute, apply
        return task


def armature_of(context, obj):
    arm = obj.find_armature()
    if arm is None:
        arm = next((o for o in context.selected_objects if o.type == "ARMATURE"), None)
    if arm is None and obj.parent is not None and obj.parent.type == "ARMATURE":
        arm = obj.parent
    if arm is None:
        raise ValueError("select an armature together with the mesh (or give the mesh an Armature modifier)")
    return arm


class LOCUS_OT_skinning_weights(LocusOperator, bpy.types.Operator):
    """Vertex groups per deforming bone from heat-diffusion natural-neighbour skinning weights"""
    bl_idname = "locus.skinning_weights"
    bl_label = "Skinning Weights"
    bl_options = {"REGISTER", "UNDO"}

    t_factor: FloatProperty(name="Heat Time", description="t = t_factor * h^2", default=1.0, min=1e-6)
    threshold: FloatProperty(name="Threshold", description="Weights at or below this are left out",
                             default=1e-3, min=0.0, max=0.5)
    add_modifier: BoolProperty(name="Add Armature Modifier", default=True)
    use_modifiers: BoolProperty(name="Use Modifiers", description=_MODIFIERS + " (rest pose)", default=False)

    def prepare(self, context):
        obj = context.active_object
        task = Task(obj, None, None, num_vertices=len(obj.data.vertices))
        arm = armature_of(context, obj)
        bones = [b for b in arm.data.bones if b.use_deform]
        if not bones:
            raise ValueError(f"armature '{arm.name}' has no deforming bones")
        arrays = _prepare_arrays(self, context, task.warnings, same_vertices=True)
        to_local = np.linalg.inv(np.array(obj.matrix_world)) @ np.array(arm.matrix_world)

        def metric(p):
            return arrays.stretch @ (to_local @ np.append(np.array(p), 1.0))[:3]

        heads = [metric(b.head_local) for b in bones]
        tails = [metric(b.tail_local) for b in bones]
        names = [b.name for b in bones]
        t_factor, threshold, add_modifier, use_modifiers = self.t_factor, self.threshold, self.add_modifier, \
            self.use_modifiers

        def compute(progress):
            s = _session(task, use_modifiers, arrays)
            if hasattr(s, "skinweights_command"):  # bones as handles (the vertices nearest each), sampled method
                bones = [np.stack([h, t]) for h, t in zip(heads, tails)]
                r = s.skinweights_command(bone=bones, t="%.17gh2" % t_factor, progress=progress)
                return None, r.weights
            handles = bone_handles.nearest_vertices(arrays.V, heads, tails)  # an older locus module
            return handles, s.skinning_weights(handles, t_factor=t_factor, progress=progress).weights

        def apply(context, obj, result):
            handles, w = result
            with mesh_write.object_mode(context, obj):
                for j, name in enumerate(names):
                    mesh_write.vertex_group(obj, name, arrays.to_mesh(w[:, j], 0.0), threshold)
            if add_modifier and not any(m.type == "ARMATURE" and m.object == arm for m in obj.modifiers):
                obj.modifiers.new("Armature", "ARMATURE").object = arm
            return f"{len(names)} vertex groups from '{arm.name}'"

        task.compute, task.apply = compute, apply
        return task


def diagonal_method(m):
    """The name of selected inversion in this locus module (the CLI's 'selinv', or the older spelling)."""
    doc = m.Session.heat_kernel_signature.__doc__ or ""
    return "selinv" if "selinv" in doc else "selected_inversion"


class LOCUS_OT_heat_signature(LocusOperator, bpy.types.Operator):
    """Auto-diffusion function / heat kernel signature as vertex attributes and a colour attribute"""
    bl_idname = "locus.heat_signature"
    bl_label = "Heat Kernel Signature"
    bl_options = {"REGISTER", "UNDO"}

    t_factor: FloatProperty(name="Heat Time", description="t = t_factor * h^2 of the first scale",
                            default=1.0, min=1e-6)
    scales: IntProperty(name="Scales", description="Times t, t*ratio, t*ratio^2, ... (1: the auto-diffusion "
                        "function)", default=1, min=1, max=16)
    ratio: FloatProperty(name="Ratio", description="Between successive times", default=4.0, min=1.0001)
    name: StringProperty(name="Name", description="Attributes NAME_0, NAME_1, ... and NAME_color",
                         default="locus_hks")
    use_modifiers: BoolProperty(name="Use Modifiers", description=_MODIFIERS, default=True)

    def prepare(self, context):
        obj = context.active_object
        task = Task(obj, None, None, num_vertices=len(obj.data.vertices))
        arrays = _prepare_arrays(self, context, task.warnings, same_vertices=True)
        t_factors = self.t_factor * self.ratio ** np.arange(self.scales)
        name, use_modifiers = self.name, self.use_modifiers
        method = diagonal_method(engine.locus())

        def compute(progress):
            s = _session(task, use_modifiers, arrays)
            return s.heat_kernel_signature(t_factors, method=method, progress=progress)

        def apply(context, obj, h):
            h = arrays.to_mesh(h, np.nan)
            with mesh_write.object_mode(context, obj):
                for j in range(h.shape[1]):
                    mesh_write.float_attribute(obj.data, f"{name}_{j}", h[:, j])
                with np.errstate(divide="ignore", invalid="ignore"):
                    shade = colormap.normalized(np.log(h[:, 0]))
                mesh_write.color_attribute(obj.data, name + "_color", colormap.ramp(shade))
            return f"{h.shape[1]} scale(s) from t_factor {t_factors[0]:.4g}"

        task.compute, task.apply = compute, apply
        return task


CLASSES = (LOCUS_OT_remesh, LOCUS_OT_geodesic, LOCUS_OT_logmap_decal, LOCUS_OT_skinning_weights,
           LOCUS_OT_heat_signature)


def register():
    for c in CLASSES:
        bpy.utils.register_class(c)


def unregister():
    for c in reversed(CLASSES):
        bpy.utils.unregister_class(c)
