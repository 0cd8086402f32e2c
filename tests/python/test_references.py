"""Python results equal the CLI's and the C API's for the same input.

The CLI's outputs are read back by a small PLY reader written here (not the
engine's), the C API is called through ctypes on build/liblocus.so. Equality
is bit for bit: the three paths run the same engine code on the same doubles.
"""
import ctypes
import json
import subprocess

import numpy as np
import pytest

import locus
from conftest import BUILD_DIR

PLY_TYPES = {"double": "<f8", "float": "<f4", "int": "<i4", "uint": "<u4", "uchar": "u1", "char": "i1",
             "short": "<i2", "ushort": "<u2"}


def read_ply_vertices(path):
    """The vertex element of a binary little-endian PLY as {property: array}."""
    data = path.read_bytes()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode("ascii").splitlines()
    assert "format binary_little_endian 1.0" in header
    count, fields, in_vertex = 0, [], False
    for line in header:
        words = line.split()
        if words[:2] == ["element", "vertex"]:
            count, in_vertex = int(words[2]), True
        elif words[:1] == ["element"]:
            in_vertex = False
        elif words[:1] == ["property"] and in_vertex:
            fields.append((words[2], PLY_TYPES[words[1]]))
    table = np.frombuffer(data, dtype=np.dtype(fields), count=count, offset=end)
    return {name: table[name] for name, _ in fields}


def run_cli(cli, tmp_path, *args):
    out = subprocess.run([str(cli), *map(str, args), "--json"], cwd=tmp_path, check=True, capture_output=True)
    return json.loads(out.stdout)


def test_geodesic_equals_cli_bit_for_bit(cli, armadillo_path, armadillo, tmp_path):
    run_cli(cli, tmp_path, "geodesic", armadillo_path, "--source", 0, "-o", tmp_path / "g.ply")
    ref = read_ply_vertices(tmp_path / "g.ply")
    V, F = armadillo
    d = locus.geodesic_distance(V, F, 0)
    assert d.dtype == np.float64 and d.shape == (len(V),)
    assert np.all(ref["valid"] == 1)
    assert np.array_equal(d, ref["distance"])  # bit for bit (no NaN: every vertex is reached)
    assert np.array_equal(V, np.stack([ref["x"], ref["y"], ref["z"]], axis=1))  # the same mesh was read


def test_logmap_equals_cli(cli, armadillo_path, armadillo_session, tmp_path):
    run_cli(cli, tmp_path, "logmap", armadillo_path, "--center", 0, "--fraction", 0.05, "-o", tmp_path / "l.ply")
    ref = read_ply_vertices(tmp_path / "l.ply")
    r = armadillo_session.logmap(0, 0.05)
    in_patch = np.flatnonzero(ref["in_patch"] == 1)
    assert np.array_equal(np.sort(r.patch), in_patch)
    for name in ("u", "v", "distance", "angle"):
        assert np.array_equal(getattr(r, name), ref[name][r.patch]), name


def test_heat_values_and_adf_equal_cli(cli, armadillo_path, armadillo_session, tmp_path):
    j = run_cli(cli, tmp_path, "heat", armadillo_path, "--source", "0,1,2", "--target", "100,200,25000")
    # `locus heat`: unit heat at every source, one step; the heat at each target.
    e = armadillo_session.heat_exchange([0, 1, 2], [100, 200, 25000])
    assert np.array_equal(e, np.array(j["values"]))
    h = armadillo_session.heat_values([0, 1, 2], [100, 200, 25000])
    assert h.shape == (3, 3)
    assert np.allclose(h.sum(axis=0), e, rtol=1e-12, atol=0)  # the same heat, source by source
    j = run_cli(cli, tmp_path, "adf", armadillo_path, "--vertices", "0,7,12345")
    a = armadillo_session.auto_diffusion([0, 7, 12345])
    assert np.array_equal(a, np.array(j["adf"]))


class CApi:
    """The handful of locus.h functions the comparison needs, through ctypes."""

    def __init__(self, path):
        self.lib = ctypes.CDLL(str(path))
        c = ctypes
        P, i64 = c.POINTER, c.c_int64
        self.lib.locus_session_create.argtypes = [P(c.c_double), i64, P(c.c_int32), i64, P(c.c_void_p)]
        self.lib.locus_geodesic_distance.argtypes = [c.c_void_p, i64, P(c.c_double)]
        self.lib.locus_logmap.argtypes = [c.c_void_p, i64, c.c_double, P(c.c_double)]
        self.lib.locus_heat_values.argtypes = [c.c_void_p, P(i64), i64, P(i64), i64, P(c.c_double), c.c_void_p]
        self.lib.locus_session_destroy.argtypes = [c.c_void_p]
        self.lib.locus_last_error_message.restype = c.c_char_p

    @staticmethod
    def ptr(a, ctype):
        return a.ctypes.data_as(ctypes.POINTER(ctype))

    def check(self, status):
        assert status == 0, self.lib.locus_last_error_message().decode()

    def session(self, V, F):
        V = np.ascontiguousarray(V, np.float64)
        F = np.ascontiguousarray(F, np.int32)
        s = ctypes.c_void_p()
        self.check(self.lib.locus_session_create(self.ptr(V, ctypes.c_double), len(V), self.ptr(F, ctypes.c_int32),
                                                 len(F), ctypes.byref(s)))
        return s


@pytest.fixture(scope="module")
def capi():
    path = BUILD_DIR / "liblocus.so"
    if not path.exists():
        pytest.skip(f"needs the shared library at {path} (cmake --build build)")
    return CApi(path)


def test_equals_c_api(capi, armadillo, armadillo_session):
    V, F = armadillo
    s = capi.session(V, F)
    try:
        n = len(V)
        d = np.empty(n)
        capi.check(capi.lib.locus_geodesic_distance(s, 123, capi.ptr(d, ctypes.c_double)))
        assert np.array_equal(armadillo_session.geodesic_distance(123), d)

        uv = np.empty(2 * n)
        capi.check(capi.lib.locus_logmap(s, 7, 0.05, capi.ptr(uv, ctypes.c_double)))
        r = armadillo_session.logmap(7, 0.05)
        uv = uv.reshape(n, 2)
        assert np.array_equal(uv[r.patch, 0], r.u) and np.array_equal(uv[r.patch, 1], r.v)
        outside = np.setdiff1d(np.arange(n), r.patch)
        assert np.all(np.isnan(uv[outside]))

        src, tgt = np.array([0, 10, 20], np.int64), np.array([5, 6, 25000, 5], np.int64)
        h = np.empty(len(src) * len(tgt))
        capi.check(capi.lib.locus_heat_values(s, capi.ptr(src, ctypes.c_int64), len(src), capi.ptr(tgt, ctypes.c_int64),
                                              len(tgt), capi.ptr(h, ctypes.c_double), None))
        assert np.array_equal(armadillo_session.heat_values(src, tgt), h.reshape(3, 4))
    finally:
        capi.lib.locus_session_destroy(s)


def test_deform_and_nncoords_equal_cli(cli, armadillo_path, armadillo_session, tmp_path):
    run_cli(cli, tmp_path, "deform", armadillo_path, "--roi-seed", 0, "--roi-fraction", 0.1, "--handle", 0,
            "--offset", "0.5,1,0", "-o", tmp_path / "d.ply")
    ref = read_ply_vertices(tmp_path / "d.ply")
    r = armadillo_session.deform(0, 0, (0.5, 1, 0), roi_fraction=0.1)
    assert np.array_equal(r.V, np.stack([ref["x"], ref["y"], ref["z"]], axis=1))
    sites = [0, 1000, 5000, 9000, 13000, 20000]
    j = run_cli(cli, tmp_path, "nncoords", armadillo_path, "--sites", ",".join(map(str, sites)),
                "--point", "10,0.2,0.3,0.5")
    nn = armadillo_session.natural_neighbor_coordinates(sites, ([10], [[0.2, 0.3, 0.5]]))
    assert np.array_equal(nn.weights, np.array(j["weights"])) and nn.cell_area == j["cell_area"]
