"""Python's `geodesic` and `logmap` with the CLI's options equal the CLI's answers bit for bit.

The CLI writes PLY files read back by the independent reader of
test_references.py; Python runs Session.geodesic / Session.logmap (the engine's
one orchestration of these commands) with the same options.
"""
import pathlib

import numpy as np
import pytest

import locus
from test_references import read_ply_vertices, run_cli


def same(a, b):
    """Bit for bit, NaN (no value) equal to NaN."""
    a, b = np.asarray(a, np.float64), np.asarray(b, np.float64)
    return a.shape == b.shape and np.array_equal(a.view(np.int64)[~np.isnan(a)], b.view(np.int64)[~np.isnan(b)]) \
        and np.array_equal(np.isnan(a), np.isnan(b))


def test_geodesic_whole_and_fraction_equal_cli(cli, armadillo_path, armadillo_session, tmp_path):
    for source, fraction in ((0, 1.0), (100, 0.1)):
        report = run_cli(cli, tmp_path, "geodesic", armadillo_path, "--source", source, "--fraction", fraction,
                         "-o", tmp_path / "g.ply")
        ref = read_ply_vertices(tmp_path / "g.ply")
        r = armadillo_session.geodesic(source, fraction=fraction)
        assert same(r.distance, ref["distance"])
        assert np.array_equal(r.valid, ref["valid"])
        assert r.method == report["method"] and r.patch_size == report["patch_size"]
        assert r.max_distance == report["max_distance"] and r.t_spec == report["t_spec"]


def test_geodesic_time_spellings(armadillo_session):
    s = armadillo_session
    d4 = s.geodesic(0).distance
    assert same(s.geodesic(0, t="4h2").distance, d4)
    assert same(s.geodesic(0, t_factor=4).distance, d4)
    h = s.mean_edge_length
    r = s.geodesic(0, t=4 * h * h)  # a number is an absolute time
    assert abs(r.t - 4 * h * h) <= 1e-15 * r.t
    for bad in (dict(t="4h2", t_factor=4), dict(t_factor=0), dict(t="-1"), dict(fraction=0)):
        try:
            s.geodesic(0, **bad)
        except locus.UsageError:
            continue
        raise AssertionError(f"{bad} was accepted")


def test_logmap_options_equal_cli(cli, armadillo_path, armadillo_session, tmp_path):
    n = armadillo_session.num_vertices
    for args, kw in ((["--method", "dem"], dict(method="dem")),
                     (["--angle", "log", "--lattice", "none", "--recenter", "off", "--clip-injective"],
                      dict(angle="log", lattice="none", recenter="off", clip_injective=True))):
        report = run_cli(cli, tmp_path, "logmap", armadillo_path, "--center", 0, "--fraction", 0.06, *args,
                         "-o", tmp_path / "l.ply")
        ref = read_ply_vertices(tmp_path / "l.ply")
        r = armadillo_session.logmap(0, 0.06, **kw)
        for name in ("distance", "angle", "u", "v"):
            full = np.full(n, np.nan)
            full[r.patch] = getattr(r, name)
            assert same(full, ref[name]), name
        assert r.flipped == report["flipped_triangles"]
        assert r.clipped_vertices == report["clipped_vertices"]
        assert r.injectivity_radius == report["injectivity_radius"]


def test_adf_hks_heat_equal_cli(cli, armadillo_path, armadillo_session, tmp_path):
    s = armadillo_session
    run_cli(cli, tmp_path, "adf", armadillo_path, "--all", "--t", "2h2", "-o", tmp_path / "a.ply")
    r = s.adf("2h2", all=True)
    assert same(r.values, read_ply_vertices(tmp_path / "a.ply")["adf"])
    report = run_cli(cli, tmp_path, "hks", armadillo_path, "--ts", "1h2,10h2", "--vertices", "3,7")
    r = s.hks(["1h2", "10h2"], vertices=[3, 7])
    assert r.values.shape == (2, 2)
    assert same(r.values, np.array(report["hks"]))  # JSON numbers read back to the same doubles
    assert r.t == report["t"] and r.etree_height == report["etree_height"]
    report = run_cli(cli, tmp_path, "heat", armadillo_path, "--source", "0,1,2", "--target", "100,200")
    r = s.heat([0, 1, 2], [100, 200])
    assert same(r.values, np.array(report["values"])) and r.total == report["total"]
    for bad in (dict(), dict(vertices=[1], all=True)):
        try:
            s.adf(**bad)
        except locus.UsageError:
            continue
        raise AssertionError(f"{bad} was accepted")


def test_deform_nncoords_equal_cli(cli, armadillo_path, armadillo_session, tmp_path):
    s = armadillo_session
    run_cli(cli, tmp_path, "deform", armadillo_path, "--roi-seed", 0, "--handle", 0, "--offset", "0.01,0.02,0",
            "-o", tmp_path / "d.ply")
    ref = read_ply_vertices(tmp_path / "d.ply")
    r = s.deform(0, 0, (0.01, 0.02, 0))
    assert same(r.V[:, 0], ref["x"]) and same(r.V[:, 1], ref["y"]) and same(r.V[:, 2], ref["z"])
    report = run_cli(cli, tmp_path, "nncoords", armadillo_path, "--sites", "0,100,200,300,400,500", "--point",
                     "10,0.2,0.3,0.5")
    r = s.nncoords([0, 100, 200, 300, 400, 500], (10, 0.2, 0.3, 0.5))
    assert same(r.weights, np.array(report["weights"])) and r.cell_area == report["cell_area"]


def test_param_patch_equal_cli(cli, armadillo_path, armadillo_session, tmp_path):
    for boundary in ("neumann", "circle"):
        report = run_cli(cli, tmp_path, "param", armadillo_path, "--center", 0, "--boundary", boundary,
                         "-o", tmp_path / "p.ply")
        ref = read_ply_vertices(tmp_path / "p.ply")
        r = armadillo_session.param(center=0, boundary=boundary)
        assert same(r.uv[:, 0], ref["u"]) and same(r.uv[:, 1], ref["v"])
        assert len(r.vertices) == report["patch_vertices"] and r.flipped_faces == report["flipped_faces"]


def test_voronoi_equal_cli(cli, armadillo_path, armadillo_session, tmp_path):
    report = run_cli(cli, tmp_path, "voronoi", armadillo_path, "--random", 20, "--seed", 3)
    r = armadillo_session.voronoi_command(random=20, seed=3)
    assert r.corners == report["corners"] and r.empty_cells == report["empty_cells"]
    assert len(r.points) == report["diagram_points"] and r.t == report["t"]


def test_info_equals_cli(cli, armadillo_path, armadillo_session, tmp_path):
    """Session.info() has the keys and numbers of `locus info --json` (the engine's one mesh report)."""
    report = run_cli(cli, tmp_path, "info", armadillo_path)
    info = armadillo_session.info()
    keys = set(report) - {"command", "input", "timings", "output", "preview", "threads", "version"}  # the envelope
    assert keys == set(info)
    for k in keys:
        want = report[k]
        got = info[k]
        if k == "bbox":
            got = {side: list(v) for side, v in got.items()}
        assert got == want, k


def test_cvt_equal_cli(cli, armadillo_path, armadillo_session, tmp_path):
    """The remesh (vertices, faces), the labels and the sites of `locus cvt`, bit for bit."""
    for args, kw in (([], {}), (["--t", "2h2", "--fit-rings", "1", "--optimize", "2"],
                                dict(t="2h2", fit_rings=1, optimize=2))):
        report = run_cli(cli, tmp_path, "cvt", armadillo_path, "--sites", 150, "--iters", 3, "--seed", 5, *args,
                         "-o", tmp_path / "r.ply", "--labels", tmp_path / "l.ply", "--sites-out", tmp_path / "s.ply")
        V, F = locus.read_mesh(str(tmp_path / "r.ply"))
        r = armadillo_session.cvt_command(150, 3, seed=5, **kw)
        assert r.complete and same(r.remesh_V, V) and np.array_equal(r.remesh_F, F)
        assert np.array_equal(r.labels, read_ply_vertices(tmp_path / "l.ply")["label"])
        sites = read_ply_vertices(tmp_path / "s.ply")
        assert same(r.sites, np.stack([sites["x"], sites["y"], sites["z"]], axis=1))
        assert r.remesh["vertices"] == report["remesh"]["vertices"] and r.energy == report["energy"]


def test_cvt_features_equal_cli(cli, tmp_path):
    """--features DEG: the remesh and the feature counts of `locus cvt`, bit for bit; a bad angle is a ValueError."""
    path = pathlib.Path(__file__).resolve().parents[2] / "cache" / "meshes" / "fandisk.off"
    if not path.exists():
        pytest.skip("needs cache/meshes/fandisk.off")
    report = run_cli(cli, tmp_path, "cvt", path, "--sites", 300, "--iters", 3, "--features", 30, "-o", tmp_path / "r.ply")
    V, F = locus.read_mesh(str(tmp_path / "r.ply"))
    s = locus.Session(*locus.read_mesh(str(path)))
    r = s.cvt_command(300, 3, features=30)
    assert r.complete and same(r.remesh_V, V) and np.array_equal(r.remesh_F, F)
    assert r.remesh["features"] == report["remesh"]["features"]
    assert report["remesh"]["features"]["corners"] > 0 and report["remesh"]["features"]["curves"] > 0
    assert "features" not in s.cvt_command(300, 3).remesh
    for bad in (-1.0, 180.0, float("nan")):
        with pytest.raises(ValueError, match="--features"):
            s.cvt_command(300, 3, features=bad)


def test_skinweights_equal_cli(cli, armadillo_path, armadillo_session, tmp_path):
    """`locus skinweights` (a vertex-set handle among vertex handles, the sampled method): Python's weights bit for bit."""
    report = run_cli(cli, tmp_path, "skinweights", armadillo_path, "--handles", "4530+4531,7448,3233", "-o",
                     tmp_path / "w.ply")
    ref = read_ply_vertices(tmp_path / "w.ply")
    r = armadillo_session.skinweights_command([[4530, 4531], 7448, 3233])
    assert r.weights.shape == (armadillo_session.num_vertices, 3)
    for j in range(3):
        assert same(r.weights[:, j], ref["w%d" % j])
    assert r.method == report["method"] == "sampled" and r.samples == report["samples"]
    assert [list(h) for h in r.handle_vertices] == report["handle_vertices"]
    assert np.allclose(r.weights.sum(axis=1), 1.0, rtol=0, atol=1e-12) and r.weights.min() >= 0


def test_factor_equal_cli(cli, armadillo_path, armadillo_session, tmp_path):
    """`locus factor` (the heat matrix at 2h2, the regularized Laplacian): the factor's sizes and the residuals of
    its solves, bit for bit (the JSON's doubles round-trip)."""
    for args, kw in ((["--t", "2h2", "--seed", 3], dict(t="2h2", seed=3)), (["--matrix", "laplacian"],
                                                                            dict(matrix="laplacian"))):
        report = run_cli(cli, tmp_path, "factor", armadillo_path, *args)
        r = armadillo_session.factor_command(**kw)
        for k in ("n", "nnz_A", "nnz_L", "nnz_L_exact", "supernodes", "etree_height", "super_etree_height", "flops",
                  "t", "h", "residual", "residual8", "solve8_lane0_vs_solve"):
            assert getattr(r, k) == report[k], k
        assert r.matrix == report["operator"] and r.x.shape == (armadillo_session.num_vertices,)
        assert r.residual < 1e-9
