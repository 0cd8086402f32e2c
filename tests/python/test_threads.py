"""One Session queried from four Python threads gives the answers of one thread."""
import threading
import time

import numpy as np

import locus


def test_four_threads_one_session(armadillo):
    s = locus.Session(*armadillo)
    s.prepare_heat()
    sources = list(range(0, 26000, 1000))
    expected = [s.geodesic_distance(v, threads=1) for v in sources]
    logmaps = s.logmap(3, 0.02).u
    results, errors = {}, []

    def worker(k):
        try:
            out = np.empty(s.num_vertices)
            for i, v in enumerate(sources):
                if (i + k) % 4 == 0:
                    results[(k, v)] = s.geodesic_distance(v, out=out).copy()
            results[(k, "logmap")] = s.logmap(3, 0.02).u
        except BaseException as e:  # noqa: B902 (reported below)
            errors.append(e)

    threads = [threading.Thread(target=worker, args=(k,)) for k in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert not errors
    for (k, v), d in results.items():
        if v == "logmap":
            assert np.array_equal(d, logmaps)
        else:
            assert np.array_equal(d, expected[sources.index(v)]), (k, v)
    assert len(results) == len(sources) + 4
    assert s.stats()["heat_engines"] == 1  # one factorization served every thread


def test_other_threads_run_while_the_engine_computes(armadillo):
    # If the GIL were held during the factorization, the ticker could not run inside the call.
    # 104k vertices: the 26k precompute (~25 ms) is too short to see ticks inside it.
    s = locus.Session(*locus.subdivide(*armadillo, 1))
    ticks, stop = [], threading.Event()

    def ticker():
        while not stop.is_set():
            ticks.append(time.perf_counter())
            time.sleep(0.002)

    t = threading.Thread(target=ticker)
    t.start()
    time.sleep(0.01)
    start = time.perf_counter()
    s.prepare_heat()
    end = time.perf_counter()
    stop.set()
    t.join()
    inside = [x for x in ticks if start + 0.01 < x < end - 0.01]
    assert end - start > 0.05 and len(inside) >= 2, (end - start, len(inside))
