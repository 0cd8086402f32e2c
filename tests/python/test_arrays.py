"""The dtype and layout matrix, out= arguments and zero-copy results.

Every accepted representation of the same mesh gives bit-identical answers:
float32 positions hold the same values as the float64 ones (the fixture
rounds them to float32), ids are exact in every integer type.
"""
import numpy as np
import pytest

import locus


def layouts(a):
    """The same array as C order, Fortran order, a strided (non-contiguous) view and a list."""
    wide = np.zeros((a.shape[0], 5), a.dtype)
    wide[:, 1:4] = a
    every_other = np.repeat(a, 2, axis=0)[::2]
    return {"C": np.ascontiguousarray(a), "F": np.asfortranarray(a), "columns of a wider array": wide[:, 1:4],
            "every other row": every_other, "reversed columns": a[:, ::-1][:, ::-1], "list": a.tolist()}


@pytest.fixture(scope="module")
def reference(sphere):
    V, F = sphere
    return locus.Session(V, F).geodesic_distance(5)


@pytest.mark.parametrize("vdtype", [np.float32, np.float64])
@pytest.mark.parametrize("fdtype", [np.int32, np.int64, np.uint32, np.uint16])
def test_dtypes(sphere, reference, vdtype, fdtype):
    V, F = sphere
    d = locus.Session(V.astype(vdtype), F.astype(fdtype)).geodesic_distance(5)
    assert np.array_equal(d, reference)


@pytest.mark.parametrize("which", ["V", "F"])
def test_layouts(sphere, reference, which):
    V, F = sphere
    for name, a in layouts(V.astype(np.float32) if which == "V" else F.astype(np.int64)).items():
        s = locus.Session(a, F) if which == "V" else locus.Session(V, a)
        assert np.array_equal(s.geodesic_distance(5), reference), name


def test_positions_read_back(sphere):
    V, F = sphere
    s = locus.Session(np.asfortranarray(V), F.astype(np.uint32))
    assert np.array_equal(s.V, V) and np.array_equal(s.F, F) and s.F.dtype == np.int32


def test_out_argument_and_sources(sphere, reference):
    V, F = sphere
    s = locus.Session(V, F)
    out = np.full(len(V), -1.0)
    assert s.geodesic_distance(5, out=out) is out
    assert np.array_equal(out, reference)
    for bad in (np.empty(len(V), np.float32), np.empty(len(V) + 1), np.empty((len(V), 2))[:, 0]):
        with pytest.raises(ValueError):
            s.geodesic_distance(5, out=bad)
    # A set of one vertex as an array, and the same point as a face corner (weights (1, 0, 0)).
    multi = s.geodesic_distance(np.array([5], np.int64))
    f = int(np.flatnonzero(F[:, 0] == 5)[0])
    face_point = s.geodesic_distance(([f], [[1.0, 0.0, 0.0]]))
    assert np.allclose(multi, reference, atol=1e-9) and np.allclose(face_point, multi, atol=1e-12)


def test_results_own_their_memory(sphere):
    V, F = sphere
    r = locus.Session(V, F).logmap(0, 0.5)
    # The array took over the engine's vector (its base is the owning capsule), and it outlives the Session.
    assert r.u.base is not None and r.u.flags.owndata is False
    assert np.all(np.isfinite(r.u)) and len(r.patch) == round(0.5 * len(V))


def test_polygon_faces(sphere):
    # A quad grid as an (m, 4) array, a list of faces and (offsets, indices) gives the same parameterization.
    n = 6
    i, j = np.meshgrid(np.arange(n), np.arange(n), indexing="xy")
    V = np.stack([i.ravel(), j.ravel(), 0.1 * (i * (n - 1 - i) + j * (n - 1 - j)).ravel()], axis=1).astype(float)
    quads = np.array([[r * n + c, r * n + c + 1, (r + 1) * n + c + 1, (r + 1) * n + c]
                      for r in range(n - 1) for c in range(n - 1)])
    offsets = np.arange(0, 4 * len(quads) + 1, 4)
    forms = [quads, quads.tolist(), (offsets, quads.ravel())]
    uvs = [locus.parameterize_disk(V, f).uv for f in forms]
    assert all(np.array_equal(uvs[0], uv) for uv in uvs[1:])
    assert np.allclose(np.linalg.norm(uvs[0][[0, n - 1, n * n - 1]], axis=1), 1.0)  # corners on the unit circle
