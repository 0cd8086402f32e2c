"""The operator choice in Python (Session(V, F, operator=...), the one-shot
functions' operator=, Session.operator) and asset files (read_mesh weld=).
Oracles: the great-circle distance on the unit sphere, the defect counts of the
mesh built here, and the file's own vertex count."""
import math
import pathlib

import numpy as np
import pytest

import locus

from conftest import icosphere


def with_fin(V, F):
    """A fin: a triangle on edge (F[0][0], F[0][1]), its apex off the surface: one non-manifold edge."""
    a, b = F[0][0], F[0][1]
    apex = (V[a] + V[b]) / 2 * 1.2
    return np.vstack([V, apex]), np.vstack([F, [[a, b, len(V)]]]).astype(np.int32)


def test_auto_takes_a_non_manifold_mesh_and_says_why():
    V, F = icosphere(3)
    Vf, Ff = with_fin(V, F)
    with pytest.raises(locus.InputError):
        locus.Session(Vf, Ff, operator="cotan")
    s = locus.Session(Vf, Ff)
    op = s.operator
    assert op["used"] == "robust" and op["asked"] == "auto"
    assert op["non_manifold_edges"] == 1
    assert "non-manifold edge" in op["reason"]
    d = locus.geodesic_distance(Vf, Ff, 0)
    great = np.arccos(np.clip(V @ V[0], -1, 1))
    assert np.mean(np.abs(d[:len(V)] - great)) < 0.02
    with pytest.raises(ValueError):
        locus.Session(V, F, operator="fancy")


def test_auto_on_a_clean_mesh_is_the_cotan_operator():
    V, F = icosphere(2)
    assert locus.Session(V, F).operator["used"] == "cotan"
    assert np.array_equal(locus.geodesic_distance(V, F, 3), locus.geodesic_distance(V, F, 3, operator="cotan"))


def test_unreferenced_vertices_get_nan():
    V, F = icosphere(2)
    V2 = np.vstack([V, [[5.0, 5.0, 5.0]]])
    d = locus.geodesic_distance(V2, F, 0)
    assert math.isnan(d[-1]) and np.all(np.isfinite(d[:-1]))


def test_read_mesh_of_a_glb_welds_its_seams():
    path = pathlib.Path("/usr/share/assimp/models/glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb")
    if not path.exists():
        pytest.skip("needs Debian's assimp-testmodels")
    V, F = locus.read_mesh(str(path))
    Vf, _ = locus.read_mesh(str(path), weld=False)
    assert len(V) < len(Vf)
    d = locus.Session(V, F).geodesic_distance(0)
    assert d[0] == 0 and np.nanmax(d) > 0
