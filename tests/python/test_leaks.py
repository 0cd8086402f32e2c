"""Reference counting: 1000 calls leave the process size bounded.

Resident set size from /proc/self/statm after a warm-up (allocator pools,
caches filled) and after the 1000 calls; a leak of even one mesh copy per
call (about 30 kB here) would add 30 MB.
"""
import numpy as np
import pytest

import locus


def rss_bytes():
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * 4096


def grow(fn, calls=1000, warmup=100):
    for _ in range(warmup):
        fn()
    before = rss_bytes()
    for _ in range(calls):
        fn()
    return rss_bytes() - before, before


@pytest.fixture(scope="module")
def bad_inputs(sphere):
    V, F = sphere
    nan = V.copy()
    nan[5, 0] = np.nan
    wrong = F.copy()
    wrong[0, 0] = len(V)
    return [(locus.InputError, lambda: locus.Session(nan, F)),
            (locus.InputError, lambda: locus.Session(V, wrong)),
            (ValueError, lambda: locus.Session(V.astype(np.int32), F)),
            (ValueError, lambda: locus.Session(V, F[:, :2]))]


def test_bad_input_calls_do_not_leak(bad_inputs):
    k = [0]

    def call():
        expected, fn = bad_inputs[k[0] % len(bad_inputs)]
        k[0] += 1
        with pytest.raises(expected):
            fn()

    growth, before = grow(call)
    assert growth <= 0.05 * before and growth < 4 << 20, f"RSS grew by {growth} bytes from {before}"


def test_queries_do_not_leak(sphere):
    V, F = sphere
    s = locus.Session(V, F)
    out = np.empty(len(V))

    def call():
        s.geodesic_distance(7)
        s.geodesic_distance(7, out=out)
        s.logmap(3, 0.1)
        try:
            s.geodesic_distance(len(V))
        except locus.UsageError:
            pass

    growth, before = grow(call)
    assert growth < 4 << 20, f"RSS grew by {growth} bytes from {before}"


def test_sessions_do_not_leak(sphere):
    V, F = sphere
    growth, _ = grow(lambda: locus.Session(V, F).geodesic_distance(0), calls=200, warmup=20)
    assert growth < 4 << 20, f"RSS grew by {growth} bytes"
