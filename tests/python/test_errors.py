"""Bad input raises the right exception with the engine's message, never crashes (issue 25 item 4)."""
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
    with pytest.raises(locus.InputError):  # a face used twice: not manifold
        locus.Session(V, np.vstack([F, F[:1]]))
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
        s.geodesic_distance(0, t_factor=1e100)
    assert info.value.code == 4 and info.value.vertex >= 0 and info.value.column >= 0
    assert np.isfinite(s.geodesic_distance(0)).all()


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
