"""Fixtures of the locus Python tests.

Run from the build tree: ``PYTHONPATH=build/python python3 -m pytest tests/python``
(ctest entry ``python`` does this). The CLI (build/locus) and the shared
library (build/liblocus.so) are the references the results are compared with;
tests that need them, or the sample meshes of tools/fetch_meshes.sh, skip
themselves when they are absent.
"""
import os
import pathlib

import numpy as np
import pytest

import locus

SOURCE_DIR = pathlib.Path(os.environ.get("LOCUS_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))
# locus/__init__.py lives in <build>/python/locus/ (or an installed site-packages).
BUILD_DIR = pathlib.Path(os.environ.get("LOCUS_BUILD_DIR", pathlib.Path(locus.__file__).resolve().parents[2]))


def icosphere(level):
    """The unit icosphere: the icosahedron subdivided `level` times, projected onto the sphere."""
    t = (1 + 5 ** 0.5) / 2
    V = np.array([[-1, t, 0], [1, t, 0], [-1, -t, 0], [1, -t, 0], [0, -1, t], [0, 1, t],
                  [0, -1, -t], [0, 1, -t], [t, 0, -1], [t, 0, 1], [-t, 0, -1], [-t, 0, 1]], float)
    F = np.array([[0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11], [1, 5, 9], [5, 11, 4],
                  [11, 10, 2], [10, 7, 6], [7, 1, 8], [3, 9, 4], [3, 4, 2], [3, 2, 6], [3, 6, 8],
                  [3, 8, 9], [4, 9, 5], [2, 4, 11], [6, 2, 10], [8, 6, 7], [9, 8, 1]])
    V, F = locus.subdivide(V, F, level)
    return V / np.linalg.norm(V, axis=1)[:, None], F


@pytest.fixture(scope="session")
def sphere():
    """642 vertices; positions rounded to float32 so that float32 and float64 inputs hold the same values."""
    V, F = icosphere(3)
    return V.astype(np.float32).astype(np.float64), F


@pytest.fixture(scope="session")
def armadillo_path():
    path = SOURCE_DIR / "cache" / "meshes" / "armadillo.off"
    if not path.exists():
        pytest.skip("needs cache/meshes/armadillo.off (bash tools/fetch_meshes.sh)")
    return path


@pytest.fixture(scope="session")
def armadillo(armadillo_path):
    return locus.read_mesh(str(armadillo_path))


@pytest.fixture(scope="session")
def armadillo_session(armadillo):
    return locus.Session(*armadillo)


@pytest.fixture(scope="session")
def cli():
    path = BUILD_DIR / "locus"
    if not path.exists():
        pytest.skip(f"needs the CLI at {path} (cmake --build build --target locus-cli)")
    return path
