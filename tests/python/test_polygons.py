"""Polygon meshes through locus.Session and the one-shots.

F as an (m, k) array, a list of faces or (offsets, indices) gives the same
Session; its results equal the `locus` CLI's on the same file bit for bit
(geodesic distance and log map on the polygons themselves, CVT on the
triangulation); bad polygons raise locus.InputError naming the face. The quad
torus is written here as OFF text (17 significant digits: the CLI reads the
same doubles) and read back for the CLI by the CLI only.
"""
import numpy as np
import pytest

import locus
from test_references import read_ply_vertices, run_cli


def quad_torus(n=16, m=8):
    """n x m quads on a torus (radii 2 and 0.7), slightly twisted so that the quads are not planar."""
    u = 2 * np.pi * np.repeat(np.arange(n), m) / n
    v = 2 * np.pi * np.tile(np.arange(m), n) / m + 0.05 * np.sin(3 * u)
    V = np.stack([(2 + 0.7 * np.cos(v)) * np.cos(u), (2 + 0.7 * np.cos(v)) * np.sin(u), 0.7 * np.sin(v)], axis=1)
    i, j = np.repeat(np.arange(n), m), np.tile(np.arange(m), n)
    F = np.stack([i * m + j, (i + 1) % n * m + j, (i + 1) % n * m + (j + 1) % m, i * m + (j + 1) % m], axis=1)
    return V, F.astype(np.int32)


def write_off(path, V, faces):
    lines = ["OFF", f"{len(V)} {len(faces)} 0"]
    lines += [" ".join(repr(float(c)) for c in p) for p in V]
    lines += [" ".join(map(str, [len(f), *f])) for f in faces]
    path.write_text("\n".join(lines) + "\n")


@pytest.fixture(scope="module")
def torus():
    return quad_torus()


def forms(F):
    """The same faces as an (m, k) array, a list of faces and (offsets, indices)."""
    offsets = np.arange(0, F.size + 1, F.shape[1])
    return {"array": F, "list": F.tolist(), "csr": (offsets, F.ravel())}


def test_every_form_is_the_same_session(torus):
    V, F = torus
    ref = locus.Session(V, F)
    assert ref.has_polygons and ref.num_polygons == len(F) and ref.num_faces == 2 * len(F)
    assert np.array_equal(np.bincount(ref.triangle_polygon), np.full(len(F), 2))
    assert [f.tolist() for f in ref.polygons] == F.tolist()
    d = ref.geodesic_distance(5)
    for name, f in forms(F).items():
        s = locus.Session(V, f)
        assert np.array_equal(s.F, ref.F), name
        assert np.array_equal(s.geodesic_distance(5), d), name
        assert np.array_equal(locus.geodesic_distance(V, f, 5), d), name


def test_geodesic_and_logmap_equal_cli(cli, torus, tmp_path):
    V, F = torus
    path = tmp_path / "torus.off"
    write_off(path, V, F)
    s = locus.Session(V, F.tolist())
    for t in (None, 3.0):
        extra = [] if t is None else ["--t", f"{t:g}h2"]
        j = run_cli(cli, tmp_path, "geodesic", path, "--source", 5, "-o", tmp_path / "g.ply", *extra)
        assert j["method"] == "heat-full-polygon"
        ref = read_ply_vertices(tmp_path / "g.ply")
        assert np.array_equal(np.stack([ref["x"], ref["y"], ref["z"]], axis=1), V)  # the same mesh was read
        assert np.array_equal(s.geodesic_distance(5, t_factor=t), ref["distance"])
        assert np.array_equal(locus.geodesic_distance(V, F, 5, t_factor=t), ref["distance"])

        j = run_cli(cli, tmp_path, "logmap", path, "--center", 5, "--fraction", 0.3, "-o", tmp_path / "l.ply", *extra)
        assert j["method"] == "heat-full-polygon"
        ref = read_ply_vertices(tmp_path / "l.ply")
        r = locus.logmap(V, F, 5, 0.3, t_factor=t)
        assert np.array_equal(np.sort(r.patch), np.flatnonzero(ref["in_patch"] == 1))
        for name in ("u", "v", "distance", "angle"):
            assert np.array_equal(getattr(r, name), ref[name][r.patch]), name


def test_cvt_equals_cli_on_a_mixed_mesh(cli, torus, tmp_path):
    # Quads with one quad split into two triangles: a mixed mesh, given as a list of faces.
    V, F = torus
    faces = [list(f) for f in F[1:]] + [[F[0][0], F[0][1], F[0][2]], [F[0][0], F[0][2], F[0][3]]]
    path = tmp_path / "mixed.off"
    write_off(path, V, faces)
    run_cli(cli, tmp_path, "cvt", path, "--sites", 12, "--iters", 3, "--seed", 4, "--labels", tmp_path / "c.ply",
            "-o", tmp_path / "remesh.obj")
    ref = read_ply_vertices(tmp_path / "c.ply")
    sites, rV, rF, labels = locus.cvt(V, faces, 12, 3, seed=4)
    assert np.array_equal(labels, ref["label"])
    # The remesh the CLI wrote, read back: its vertices are Python's (collapses may leave fewer than the sites).
    cli_vertices = [line.split()[1:4] for line in (tmp_path / "remesh.obj").read_text().splitlines() if line.startswith("v ")]
    assert len(rV) == len(cli_vertices) <= len(sites) and rF.shape[1] == 3
    assert np.allclose(rV, np.array(cli_vertices, dtype=float), rtol=1e-6, atol=1e-12)


def test_bad_polygons_raise_input_error(torus):
    V, F = torus
    crossed = F.copy()
    crossed[6, [1, 2]] = crossed[6, [2, 1]]  # face 6's boundary crosses itself
    for name, f in forms(crossed).items():
        with pytest.raises(locus.InputError, match="face 6"):
            locus.Session(V, f)
    with pytest.raises(locus.InputError, match="face 3 has 2 vertices"):
        locus.Session(V, F[:3].tolist() + [[0, 1]] + F[4:].tolist())
    out_of_range = F.tolist()
    out_of_range[9][2] = len(V) + 1
    with pytest.raises(locus.InputError, match="face 9 references vertex"):
        locus.geodesic_distance(V, out_of_range, 0)
    with pytest.raises(ValueError, match="offsets"):
        locus.Session(V, (np.arange(1, F.size + 1, 4), F.ravel()))


def test_uniform_polygons_come_back_as_arrays(torus, tmp_path):
    """Quads read or returned are an (m, 4) int32 array; mixed faces a list."""
    V, F = torus
    path = tmp_path / "quads.off"
    write_off(path, V, F)
    V2, F2 = locus.read_mesh(str(path))
    assert isinstance(F2, np.ndarray) and F2.shape == F.shape and F2.dtype == np.int32
    assert np.array_equal(F2, F)
    s = locus.Session(V, F)
    assert isinstance(s.polygons, np.ndarray) and np.array_equal(s.polygons, F)
    mixed = [list(f) for f in F[1:]] + [[F[0][0], F[0][1], F[0][2]], [F[0][0], F[0][2], F[0][3]]]
    p = locus.Session(V, mixed).polygons
    assert isinstance(p, list) and [list(f) for f in p] == mixed
