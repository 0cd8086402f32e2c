"""Bad input raises the right exception with the engine's message, never crashes."""
import numpy as np
import pytest

import locus


def test_exception_hierarchy():
    assert issubclass(locus.UsageError, locus.Error) and issubclass(locus.UsageError, ValueError)
    for cls in (locus.InputError, locus.NumericalError, locus.Cancelled, locus.ResourceLimitError):
        assert issubclass(cls, locus.Error) and not issubclass(cls, ValueError)


def test_bad_meshes_raise_input_error(sphere):
    V, F = sphere
    nan = V.copy()
    nan[17, 1] = np.nan
    with pytest.raises(locus.InputError, match="17"):
        locus.Session(nan, F)
    out_of_range = F.copy()
    out_of_range[40, 2] = len(V) + 5
    with pytest.raises(locus.InputError, match=str(len(V) + 5)):
        locus.Session(V, out_of_range)
    with pytest.raises(locus.InputError, match="int32"):
        locus.Session(V, np.where(F == 3, 2 ** 40, F).astype(np.int64))
    with pytest.raises(locus.InputError):  # a face used twice: not manifold (the cotan operator refuses it)
        locus.Session(V, np.vstack([F, F[:1]]), operator="cotan")
    with pytest.raises(locus.InputError):
        locus.Session(np.zeros((0, 3)), np.zeros((0, 3), np.int32))
    with pytest.raises(locus.InputError, match="no_such_file"):
        locus.read_mesh("no_such_file.off")


def test_bad_arguments_raise_value_error(sphere):
    V, F = sphere
    for bad_v in (V.astype(np.int64), V[:, :2], V.ravel(), "mesh", None):
        with pytest.raises(ValueError):
            locus.Session(bad_v, F)
    for bad_f in (F.astype(np.float64), F[:, :2], F.ravel()):
        with pytest.raises(ValueError):
            locus.Session(V, bad_f)
    s = locus.Session(V, F)
    with pytest.raises(locus.UsageError, match="source 9999 is not a vertex"):
        s.geodesic_distance(9999)
    with pytest.raises(ValueError, match="fraction"):
        s.logmap(0, 2.0)
    with pytest.raises(ValueError, match="method"):
        s.auto_diffusion([0], method="nonsense")
    with pytest.raises(ValueError):
        s.heat_values([0], [len(V)])
    with pytest.raises(ValueError):
        s.set_positions(V[:-1])
    e = pytest.raises(locus.UsageError, s.geodesic_distance, -1).value
    assert e.code == 2 and e.vertex == -1
    assert np.isfinite(s.geodesic_distance(0)).all()  # still usable


def test_numerical_error_names_vertex_and_column(sphere):
    s = locus.Session(*sphere)
    with pytest.raises(locus.NumericalError, match="not positive definite") as info:
        # t = 1e100 h^2: M is lost in rounding against tL, whose Laplacian is singular.
        s.heat_values([0], [1], t_factor=1e100)
    assert info.value.code == 4 and info.value.vertex >= 0 and info.value.column >= 0
    assert np.isfinite(s.geodesic_distance(0)).all()


def test_absurd_heat_time_is_refused_naming_the_limit(sphere):
    V, F = sphere
    s = locus.Session(V, F)
    for tf in (1e300, 1e100, 1e7):
        with pytest.raises(locus.UsageError, match="at most 1e\\+06 h\\^2"):
            s.geodesic_distance(0, t_factor=tf)
        with pytest.raises(locus.UsageError, match="at most 1e\\+06 h\\^2"):
            locus.geodesic_distance(V, F, 0, t_factor=tf)
    d = s.geodesic_distance(0, t_factor=1e6)
    assert (d >= 0).all()


@pytest.mark.parametrize("call, name", [
    (lambda s, V, F: locus.geodesic_distance(V, F, 2 ** 64), "source"),
    (lambda s, V, F: s.geodesic_distance(2 ** 64), "source"),
    (lambda s, V, F: s.geodesic_distance(-2 ** 70), "source"),
    (lambda s, V, F: s.geodesic_distance(0, threads=2 ** 63), "threads"),
    (lambda s, V, F: s.geodesic_distance(0, threads=-1), "threads"),
    (lambda s, V, F: s.geodesic_distance(0, threads=5000), "threads"),
    (lambda s, V, F: s.geodesic_distance(0, threads="2"), "threads"),
    (lambda s, V, F: s.cvt(10, 1, -1), "seed"),
    (lambda s, V, F: locus.cvt(V, F, 10, seed=-1), "seed"),
    (lambda s, V, F: locus.cvt(V, F, 2 ** 63), "sites"),
    (lambda s, V, F: s.random_points(2 ** 40), "count"),
    (lambda s, V, F: s.geodesic_distance(0, t_factor=0), "t_factor"),
    (lambda s, V, F: s.geodesic_distance(0, t_factor=-1.0), "t_factor"),
    (lambda s, V, F: s.voronoi([0, 5], t_factor=0), "t_factor"),
    (lambda s, V, F: s.logmap(0, 0.1, t_factor=float("nan")), "t_factor"),
    (lambda s, V, F: s.logmap(0, 2 ** 2000), "fraction"),
])
def test_every_bad_argument_is_a_locus_error_naming_it(sphere, call, name):
    V, F = sphere
    s = locus.Session(V, F)
    with pytest.raises(locus.UsageError, match=name) as info:
        call(s, V, F)
    assert isinstance(info.value, ValueError) and info.value.code == 2
    assert np.isfinite(s.geodesic_distance(0, threads=1)).all()  # still usable


def test_set_positions_rejects_nan_and_keeps_old(sphere):
    V, F = sphere
    s = locus.Session(V, F)
    before = s.geodesic_distance(0)
    bad = V.copy()
    bad[3] = np.inf
    with pytest.raises(locus.InputError):
        s.set_positions(bad)
    assert np.array_equal(s.geodesic_distance(0), before)
    s.set_positions(2 * V)
    assert s.stats()["positions_version"] == 1
    assert np.allclose(s.geodesic_distance(0), 2 * before, rtol=1e-9)  # distances scale with the mesh


def test_meshes_beyond_double_precision_name_the_cause(sphere):
    V, F = sphere
    for s, cause in ((1e160, "overflow"), (1e155, "overflow"), (1e-155, "underflow"), (1e-300, "underflow")):
        with pytest.raises(locus.InputError, match=cause) as info:
            locus.geodesic_distance(V * s, F, 0)
        assert "between 1e-150 and 1e+150" in str(info.value) and "zero area" not in str(info.value)
    d1 = locus.geodesic_distance(V, F, 0)
    for s in (1e149, 1e-149):
        assert np.allclose(locus.geodesic_distance(V * s, F, 0) / s, d1, rtol=1e-9, atol=0)
