"""The add-on's interface: preferences, the sidebar panel and the Object/Mesh menus.

The panel's settings live on the scene (Scene.locus) and are passed to the
operators it calls; the operators keep their own properties too, so the
redo panel (F9) and scripts set them directly.
"""
import bpy
from bpy.app.handlers import persistent
from bpy.props import BoolProperty, FloatProperty, IntProperty, PointerProperty, StringProperty

from . import engine


class LocusPreferences(bpy.types.AddonPreferences):
    bl_idname = __package__

    module_path: StringProperty(
        name="locus module folder", subtype="DIR_PATH",
        description="Folder holding the locus Python package (e.g. <build>/python), when Blender's Python "
                    "does not find it on its own")

    def draw(self, context):
        self.layout.prop(self, "module_path")
        try:
            m = engine.locus(self.module_path)
            self.layout.label(text=f"locus {m.__version__} from {m.__file__}")
        except engine.NotAvailable as e:
            self.layout.label(text=str(e), icon="ERROR")


class LocusSettings(bpy.types.PropertyGroup):
    use_modifiers: BoolProperty(name="Use Modifiers", default=True,
                                description="Read the evaluated mesh (modifiers applied), else the mesh data")
    points: IntProperty(name="Points", default=2000, min=4, description="Vertices of the remeshed surface")
    iterations: IntProperty(name="Iterations", default=10, min=0, max=500, description="Lloyd steps")
    replace: BoolProperty(name="Replace Mesh", default=False, description="Replace the mesh data (else a new object)")
    falloff: FloatProperty(name="Falloff Radius", default=0.0, min=0.0, subtype="DISTANCE", unit="LENGTH",
                           description="Geodesic weight reaches 0 at this distance (0: the farthest vertex)")
    decal_radius: FloatProperty(name="Decal Radius", default=0.0, min=0.0, subtype="DISTANCE", unit="LENGTH",
                                description="Geodesic radius of the decal (0: 5% of the object's size)")
    decal_rotation: FloatProperty(name="Rotation", default=0.0, subtype="ANGLE")
    heat_time: FloatProperty(name="Heat Time", default=1.0, min=1e-6,
                             description="t = heat time * h^2 (skinning, HKS)")
    scales: IntProperty(name="Scales", default=1, min=1, max=16, description="HKS time scales (1: auto-diffusion)")


def _menu_items(layout):
    layout.operator("locus.remesh", icon="MOD_REMESH")
    layout.operator("locus.geodesic", icon="DRIVER_DISTANCE")
    layout.operator("locus.logmap_decal", icon="UV")
    layout.operator("locus.skinning_weights", icon="ARMATURE_DATA")
    layout.operator("locus.heat_signature", icon="COLOR")


class LOCUS_MT_menu(bpy.types.Menu):
    bl_idname = "LOCUS_MT_menu"
    bl_label = "Locus"

    def draw(self, context):
        _menu_items(self.layout)


class LOCUS_PT_panel(bpy.types.Panel):
    bl_label = "Locus"
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "Locus"

    @classmethod
    def poll(cls, context):
        return context.active_object is not None and context.active_object.type == "MESH"

    def draw(self, context):
        s = context.scene.locus
        col = self.layout.column()
        col.prop(s, "use_modifiers")
        box = col.box()
        box.prop(s, "points")
        box.prop(s, "iterations")
        box.prop(s, "replace")
        op = box.operator("locus.remesh")
        op.points, op.iterations, op.replace, op.use_modifiers = s.points, s.iterations, s.replace, s.use_modifiers
        box = col.box()
        box.prop(s, "falloff")
        op = box.operator("locus.geodesic")
        op.radius, op.use_modifiers = s.falloff, s.use_modifiers
        box = col.box()
        box.prop(s, "decal_radius")
        box.prop(s, "decal_rotation")
        op = box.operator("locus.logmap_decal")
        op.radius, op.rotation, op.use_modifiers = s.decal_radius, s.decal_rotation, s.use_modifiers
        box = col.box()
        box.prop(s, "heat_time")
        box.prop(s, "scales")
        op = box.operator("locus.skinning_weights")
        op.t_factor = s.heat_time
        op = box.operator("locus.heat_signature")
        op.t_factor, op.scales, op.use_modifiers = s.heat_time, s.scales, s.use_modifiers


def _object_menu(self, context):
    self.layout.menu(LOCUS_MT_menu.bl_idname)


@persistent
def _forget_sessions(*_args):
    engine.forget()


_CLASSES = (LocusSettings, LOCUS_MT_menu, LOCUS_PT_panel)


def register_preferences():
    bpy.utils.register_class(LocusPreferences)


def unregister_preferences():
    bpy.utils.unregister_class(LocusPreferences)


def register():
    for c in _CLASSES:
        bpy.utils.register_class(c)
    bpy.types.Scene.locus = PointerProperty(type=LocusSettings)
    bpy.types.VIEW3D_MT_object.append(_object_menu)
    bpy.types.VIEW3D_MT_edit_mesh.append(_object_menu)
    bpy.app.handlers.load_post.append(_forget_sessions)


def unregister():
    bpy.app.handlers.load_post.remove(_forget_sessions)
    bpy.types.VIEW3D_MT_edit_mesh.remove(_object_menu)
    bpy.types.VIEW3D_MT_object.remove(_object_menu)
    del bpy.types.Scene.locus
    for c in reversed(_CLASSES):
        bpy.utils.unregister_class(c)
    engine.forget()
