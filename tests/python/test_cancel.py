"""Ctrl-C and the progress callback cancel a long call.

The factorization of armadillo subdivided once (104k vertices) takes about a
second; SIGINT arrives while it runs. The latency is measured by
tools/bench_python.py (at 416k); here only that the call stops with the
right exception and the Session stays usable.
"""
import os
import signal
import threading
import time

import numpy as np
import pytest

import locus


@pytest.fixture(scope="module")
def big(armadillo):
    return locus.subdivide(*armadillo, 1)


def test_sigint_during_numeric_factorization(big):
    s = locus.Session(*big)
    sent = []

    def progress(fraction, phase):
        if phase == "numeric factorization" and not sent:
            sent.append(time.perf_counter())
            os.kill(os.getpid(), signal.SIGINT)  # from an engine thread, as a terminal's Ctrl-C

    with pytest.raises(KeyboardInterrupt):
        s.geodesic_distance(0, progress=progress)
    assert sent and time.perf_counter() - sent[0] < 5.0
    assert s.stats()["heat_engines"] == 0  # nothing cached from the cancelled call
    d = s.geodesic_distance(0)
    assert d[0] == 0 and np.isfinite(d).all()


def test_sigint_from_a_timer_during_ordering(big):
    s = locus.Session(*big)
    timer = threading.Timer(0.05, os.kill, (os.getpid(), signal.SIGINT))
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        s.prepare_heat()
    timer.join()
    assert s.stats()["heat_engines"] == 0  # cancelled, not finished and interrupted afterwards


def test_ignored_sigint_is_left_alone(sphere):
    s = locus.Session(*sphere)
    old = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        s.prepare_heat(progress=lambda f, phase: os.kill(os.getpid(), signal.SIGINT))
    finally:
        signal.signal(signal.SIGINT, old)
    assert s.stats()["heat_engines"] == 1
    assert signal.getsignal(signal.SIGINT) is old


def test_progress_callback_cancels_and_raises(sphere):
    s = locus.Session(*sphere)
    seen = []
    s.prepare_heat(progress=lambda f, phase: seen.append((f, phase)))
    assert seen and all(0.0 <= f <= 1.0 for f, _ in seen) and all(isinstance(p, str) for _, p in seen)
    assert [f for f, _ in seen] == sorted(f for f, _ in seen)
    with pytest.raises(locus.Cancelled):
        s.prepare_diffusion(progress=lambda f, phase: True)
    with pytest.raises(ZeroDivisionError):
        s.prepare_diffusion(progress=lambda f, phase: 1 / 0)
    assert s.stats()["numeric_factorizations"] == 0
    s.prepare_diffusion()
    assert s.stats()["numeric_factorizations"] == 1


def test_sigint_under_a_host_handler_raises_keyboard_interrupt(big):
    """A host whose SIGINT handler is not Python's (Blender, an embedding
    application): Ctrl-C still raises KeyboardInterrupt, the host's handler is
    still called, and Cancelled stays the progress callback's. The host
    handler here is libc's abs(), a C function that does nothing harmful."""
    import ctypes

    libc = ctypes.CDLL(None)
    libc.signal.restype = ctypes.c_void_p
    libc.signal.argtypes = [ctypes.c_int, ctypes.c_void_p]
    host = ctypes.cast(libc.abs, ctypes.c_void_p).value
    old = signal.getsignal(signal.SIGINT)
    libc.signal(signal.SIGINT, host)
    try:
        s = locus.Session(*big)
        timer = threading.Timer(0.05, os.kill, (os.getpid(), signal.SIGINT))
        timer.start()
        with pytest.raises(KeyboardInterrupt) as raised:
            s.prepare_heat()
        timer.join()
        assert not isinstance(raised.value, locus.Cancelled)
        assert libc.signal(signal.SIGINT, host) == host  # the host's handler is back in place
    finally:
        signal.signal(signal.SIGINT, old)
    assert s.stats()["heat_engines"] == 0
