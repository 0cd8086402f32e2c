"""locus for Blender: heat-method geometry processing on the active mesh.

A thin layer over the `locus` Python module (python/, DESIGN.md "blender/"):
operators under Object > Locus and Mesh > Locus and a sidebar panel
(View3D > Sidebar > Locus) for CVT remeshing (thesis §3.7), geodesic
distance (§6.4), log-map decals (§6.5-6.6), skinning weights from an
armature (§3.7.2) and the auto-diffusion function / heat kernel signature
(§4.6). Each operator reads the evaluated mesh (modifiers applied) or the raw
mesh, computes off Blender's main thread with progress in the status bar
(Esc cancels; nothing is written then), and writes its result in one undo
step. The Session of each object is kept between calls (the second geodesic
on the same mesh only solves) and rebuilt when the mesh changes.

Install: zip the `locus_addon` folder (`python3 -m zipfile -c
locus_addon.zip blender/locus_addon`) and use Preferences > Add-ons > Install, or start Blender with `--addons locus_addon` and this folder's
parent in BLENDER_USER_SCRIPTS/addons. The locus module itself must be
importable by Blender's Python (see docs/blender.md).
"""
bl_info = {
    "name": "locus",
    "author": "locus authors",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "View3D > Sidebar > Locus; Object/Mesh menu > Locus",
    "description": "Heat-method remeshing, geodesic distance, log-map decals, skinning weights, HKS",
    "category": "Mesh",
}

from . import operators, ui  # noqa: E402  (bl_info must come first for Blender's add-on scanner)


def register():
    ui.register_preferences()
    operators.register()
    ui.register()


def unregister():
    ui.unregister()
    operators.unregister()
    ui.unregister_preferences()
