"""Skinning handles from an armature's bones for a locus module without
Session.skinweights_command (which takes the bones themselves: each bone's
handle is the set of vertices nearest its segment): one mesh vertex per bone.

locus.Session.skinning_weights interpolates between handle points on the
surface (natural-neighbour coordinates, thesis §3.7.2): weight 1 at a bone's
own handle. The handle of a bone is the mesh vertex nearest its segment
(head to tail), the surface point the bone most directly drives; bones whose
nearest vertex another bone already took get their next nearest one, so the
handles are distinct. Pure NumPy (no bpy): the Blender tests check the choice.
"""
import numpy as np


def segment_distances(V, head, tail):
    """Distance of every row of V (n, 3) to the segment head-tail."""
    d = np.asarray(tail, np.float64) - np.asarray(head, np.float64)
    rel = V - np.asarray(head, np.float64)
    length2 = float(d @ d)
    s = np.clip(rel @ d / length2, 0.0, 1.0) if length2 > 0 else np.zeros(len(V))
    return np.linalg.norm(rel - s[:, None] * d, axis=1)


def nearest_vertices(V, heads, tails):
    """Distinct vertex ids, one per segment (heads[i], tails[i]), in segment order."""
    taken = set()
    handles = []
    for head, tail in zip(heads, tails):
        order = np.argsort(segment_distances(V, head, tail), kind="stable")
        for v in order:
            if int(v) not in taken:
                taken.add(int(v))
                handles.append(int(v))
                break
    return np.asarray(handles, np.int32)
