# Blender's Automatic Weights (bone heat) on an OFF mesh, for the comparison in
# docs/skinning.md (locus-bench skinning): one short bone per handle vertex,
# pointing into the mesh along the vertex normal, then
# parent_set(type='ARMATURE_AUTO'); prints the wall time of that call alone.
#   blender -b --factory-startup --python tools/bench/blender_auto_weights.py -- MESH.off 4530,7448,3233,17208 [SUBDIVIDE]
import sys
import time

import bpy
import bmesh


def read_off(path):
    words = open(path).read().split()
    if words[0] != "OFF":
        raise SystemExit(path + ": not an OFF file")
    nv, nf = int(words[1]), int(words[2])
    p = 4
    verts = []
    for _ in range(nv):
        verts.append((float(words[p]), float(words[p + 1]), float(words[p + 2])))
        p += 3
    faces = []
    for _ in range(nf):
        k = int(words[p])
        faces.append(tuple(int(w) for w in words[p + 1:p + 1 + k]))
        p += 1 + k
    return verts, faces


def main():
    args = sys.argv[sys.argv.index("--") + 1:]
    verts, faces = read_off(args[0])
    handles = [int(v) for v in args[1].split(",")]
    subdivide = int(args[2]) if len(args) > 2 else 0
    bpy.ops.wm.read_factory_settings(use_empty=True)
    me = bpy.data.meshes.new("m")
    me.from_pydata(verts, [], faces)
    if subdivide:  # 1:4 midpoint subdivision keeps the vertex ids, as locus --subdivide
        bm = bmesh.new()
        bm.from_mesh(me)
        for _ in range(subdivide):
            bmesh.ops.subdivide_edges(bm, edges=bm.edges[:], cuts=1, use_grid_fill=True)
        bm.to_mesh(me)
        bm.free()
    me.update()
    obj = bpy.data.objects.new("m", me)
    bpy.context.scene.collection.objects.link(obj)
    xs = [v.co for v in me.vertices]
    diag = (max(c.x for c in xs) - min(c.x for c in xs)) ** 2 + (max(c.y for c in xs) - min(c.y for c in xs)) ** 2
    length = 0.02 * diag ** 0.5
    arm = bpy.data.armatures.new("a")
    rig = bpy.data.objects.new("a", arm)
    bpy.context.scene.collection.objects.link(rig)
    bpy.context.view_layer.objects.active = rig
    bpy.ops.object.mode_set(mode="EDIT")
    for i, h in enumerate(handles):
        b = arm.edit_bones.new("h%d" % i)
        co, n = me.vertices[h].co, me.vertices[h].normal
        b.head = co - n * (0.1 * length)
        b.tail = co - n * length
    bpy.ops.object.mode_set(mode="OBJECT")
    bpy.ops.object.select_all(action="DESELECT")
    obj.select_set(True)
    rig.select_set(True)
    bpy.context.view_layer.objects.active = rig
    t0 = time.perf_counter()
    bpy.ops.object.parent_set(type="ARMATURE_AUTO")
    t = time.perf_counter() - t0
    print("blender_auto_weights n=%d handles=%d wall_s=%.3f groups=%d" % (len(me.vertices), len(handles), t, len(obj.vertex_groups)))


main()
