"""progress= takes a tqdm bar as well as a callable.

The bar ends at its total when the call ends (the engine reports fraction 1
last), its description shows the engine's phase, and an object that is
neither callable nor a bar is a UsageError naming progress.
"""
import io

import numpy as np
import pytest

import locus


def test_tqdm_bar_follows_the_call(sphere):
    tqdm = pytest.importorskip("tqdm", reason="needs python3-tqdm").tqdm
    phases = []
    locus.Session(*sphere).geodesic_distance(0, progress=lambda f, phase: phases.append((f, phase)))
    with tqdm(total=100, file=io.StringIO()) as bar:
        d = locus.Session(*sphere).geodesic_distance(0, progress=bar)
        assert bar.n == pytest.approx(100 * phases[-1][0])
        assert bar.desc == phases[-1][1]
    assert d[0] == 0 and np.isfinite(d).all()


def test_tqdm_bar_without_total(sphere):
    tqdm = pytest.importorskip("tqdm", reason="needs python3-tqdm").tqdm
    with tqdm(file=io.StringIO()) as bar:
        locus.Session(*sphere).prepare_diffusion(progress=bar)
        assert bar.total == 100 and 0 < bar.n <= 100


def test_progress_of_another_type_is_a_usage_error(sphere):
    with pytest.raises(locus.UsageError, match="progress"):
        locus.Session(*sphere).prepare_heat(progress=42)
