"""One Session queried from four Python threads gives the answers of one thread (issue 25 item 3)."""
import threading

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
