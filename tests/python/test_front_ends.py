"""Python's `geodesic` and `logmap` with the CLI's options equal the CLI's answers bit for bit.

The CLI writes PLY files read back by the independent reader of
test_references.py; Python runs Session.geodesic / Session.logmap (the engine's
one orchestration of these commands) with the same options.
"""
import numpy as np

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
