#!/usr/bin/env python3
"""Benchmarks of the Python binding (docs/python.md); not a test.

    PYTHONPATH=build/python /usr/bin/python3 tools/bench_python.py [--mesh cache/meshes/armadillo.off] [--json]
        [--skip-cancel] [--cancel-repeats 3] [--only overhead|factorization|threads|rss|cancel]

1. overhead: Python's locus.Session.geodesic_distance(v, out=...) against the
   same Session::geodesic_distance in a C++ loop in this process
   (locus._locus._bench), on the same prepared Session at 26k vertices;
   medians, interleaved query by query, and the ratio; and the binding's
   own cost per call on an octahedron (where the query is nearly free) as a
   fraction of the 26k query (robust against machine load).
2. one factorization: 100 queries on one Session; stats() before and after.
3. threads: the same 64 queries from 1 and from 4 Python threads on one
   Session (threads=1 per query, and the default all-cores); wall-clock
   speedup, and the process CPU time over wall time of each run (one thread:
   > 1 would mean a single query already uses more than one core; four
   threads: > 1 means queries ran in parallel, the GIL released; on a loaded
   machine it also shows how many cores the process got), and the fraction
   of the four-thread run's wall time during which two or more queries were
   in flight (0 if the GIL serialized them, whatever the machine's load).
4. Ctrl-C: SIGINT at 416k vertices (the mesh subdivided twice) during the
   ordering (0.3 s after the call starts) and during the numeric
   factorization (0.1 s after it reports its phase); latency from os.kill to
   the KeyboardInterrupt reaching the caller; medians.
5. bad input: RSS after 1000 failing Session() calls, relative to before.
"""
import argparse
import json
import os
import signal
import statistics
import threading
import time

import numpy as np

import locus
from locus._locus import _bench


def overhead(s, rounds=7, per_round=40):
    sources = list(range(0, s.num_vertices, s.num_vertices // per_round))[:per_round]
    out = np.empty(s.num_vertices)
    s.geodesic_distance(0, out=out)  # the factorization, outside the timing
    py, cpp = [], []
    for _ in range(rounds):
        for v in sources:  # interleaved query by query, so that machine load hits both alike
            t0 = time.perf_counter()
            s.geodesic_distance(v, out=out)
            py.append(time.perf_counter() - t0)
            cpp += _bench.geodesic_seconds(s, [v], 1)
    mp, mc = statistics.median(py), statistics.median(cpp)
    paired = statistics.median(p - c for p, c in zip(py, cpp))
    return {"python_median_s": mp, "cpp_median_s": mc, "overhead_pct": 100 * (mp - mc) / mc,
            "paired_median_difference_s": paired, "paired_overhead_pct": 100 * paired / mc, "queries_each": len(py)}


def overhead_tiny(rounds=2000):
    """The binding's own cost per call, where the query itself is nearly free: an octahedron."""
    V = np.array([[0, 0, 1], [1, 0, 0], [0, 1, 0], [-1, 0, 0], [0, -1, 0], [0, 0, -1]], float)
    F = np.array([[0, 1, 2], [0, 2, 3], [0, 3, 4], [0, 4, 1], [5, 2, 1], [5, 3, 2], [5, 4, 3], [5, 1, 4]])
    s = locus.Session(V, F)
    out = np.empty(6)
    s.geodesic_distance(0, out=out)
    py, cpp = [], []
    for k in range(rounds):
        t0 = time.perf_counter()
        s.geodesic_distance(k % 6, out=out)
        py.append(time.perf_counter() - t0)
        cpp += _bench.geodesic_seconds(s, [k % 6], 1)
    return {"python_median_s": statistics.median(py), "cpp_median_s": statistics.median(cpp),
            "binding_overhead_s": statistics.median(py) - statistics.median(cpp)}


def one_factorization(V, F):
    s = locus.Session(V, F)
    before = s.stats()
    out = np.empty(s.num_vertices)
    t0 = time.perf_counter()
    for v in range(100):
        s.geodesic_distance(v * 97 % s.num_vertices, out=out)
    return {"stats_before": before, "stats_after": s.stats(), "seconds_100_queries": time.perf_counter() - t0}


def run_threads(s, sources, nthreads, query_threads):
    chunks = [sources[k::nthreads] for k in range(nthreads)]
    results, spans = {}, []

    def work(chunk):
        out = np.empty(s.num_vertices)
        for v in chunk:
            t0 = time.perf_counter()
            s.geodesic_distance(v, out=out, threads=query_threads)
            spans.append((t0, time.perf_counter()))
            results[v] = out.copy()

    workers = [threading.Thread(target=work, args=(c,)) for c in chunks]
    w0, c0 = time.perf_counter(), time.process_time()
    for t in workers:
        t.start()
    for t in workers:
        t.join()
    wall = time.perf_counter() - w0
    return wall, (time.process_time() - c0) / wall, results, overlap(spans) / wall


def overlap(spans):
    """Time during which at least two queries were in flight (0 if the GIL serialized them)."""
    events = sorted([(a, 1) for a, _ in spans] + [(b, -1) for _, b in spans])
    depth, last, both = 0, 0.0, 0.0
    for t, d in events:
        if depth >= 2:
            both += t - last
        depth, last = depth + d, t
    return both


def threads(s, queries=64, rounds=3):
    sources = list(range(0, s.num_vertices, s.num_vertices // queries))[:queries]
    s.prepare_heat()
    report = {}
    for query_threads in (1, 0):
        one, four, cpu1, cpu4, ov4 = [], [], [], [], []
        for _ in range(rounds):
            w1, c1, r1, _ = run_threads(s, sources, 1, query_threads)
            w4, c4, r4, o4 = run_threads(s, sources, 4, query_threads)
            ov4.append(o4)
            assert all(np.array_equal(r1[v], r4[v]) for v in sources), "4 threads gave other answers"
            one.append(w1)
            four.append(w4)
            cpu1.append(c1)
            cpu4.append(c4)
        key = "threads=1 per query" if query_threads == 1 else "threads=0 (all cores) per query"
        report[key] = {"one_thread_s": statistics.median(one), "four_threads_s": statistics.median(four),
                       "speedup": statistics.median(one) / statistics.median(four),
                       "one_thread_cpu_over_wall": statistics.median(cpu1),
                       "four_threads_cpu_over_wall": statistics.median(cpu4),
                       "four_threads_overlap_fraction": statistics.median(ov4), "identical": True}
    return report


def cancel_once(V, F, phase):
    s = locus.Session(V, F)
    sent = []

    def fire():
        sent.append(time.perf_counter())
        os.kill(os.getpid(), signal.SIGINT)

    def progress(fraction, name):
        if phase == "numeric" and name == "numeric factorization" and not timers:
            timers.append(threading.Timer(0.1, fire))
            timers[0].start()

    timers = []
    if phase == "ordering":
        timers.append(threading.Timer(0.3, fire))
        timers[0].start()
    t0 = time.perf_counter()
    try:
        s.geodesic_distance(0, progress=progress)
        return {"phase": phase, "completed_s": time.perf_counter() - t0}
    except KeyboardInterrupt:
        done = time.perf_counter()
        return {"phase": phase, "latency_s": done - sent[0], "started_after_s": sent[0] - t0}
    finally:
        for t in timers:
            t.join()


def cancel(V, F, repeats):
    V2, F2 = locus.subdivide(V, F, 2)
    s = locus.Session(V2, F2)
    t0 = time.perf_counter()
    phases = []
    s.geodesic_distance(0, progress=lambda f, name: phases.append((time.perf_counter() - t0, name)) if not phases or
                        phases[-1][1] != name else None)
    full = time.perf_counter() - t0
    report = {"vertices": len(V2), "uncancelled_first_query_s": full, "phases": phases}
    for phase in ("ordering", "numeric"):
        runs = [cancel_once(V2, F2, phase) for _ in range(repeats)]
        lat = [r["latency_s"] for r in runs if "latency_s" in r]
        report[phase] = {"runs": runs, "median_latency_s": statistics.median(lat) if lat else None}
    return report


def bad_input_rss(V, F, calls=1000):
    bad = V.copy()
    bad[len(V) // 2, 1] = np.nan

    def rss():
        with open("/proc/self/statm") as f:
            return int(f.read().split()[1]) * 4096

    for _ in range(50):
        try:
            locus.Session(bad, F)
        except locus.InputError:
            pass
    before = rss()
    raised = 0
    for _ in range(calls):
        try:
            locus.Session(bad, F)
        except locus.InputError:
            raised += 1
    after = rss()
    return {"calls": calls, "raised_input_error": raised, "rss_before": before, "rss_after": after,
            "growth_pct": 100 * (after - before) / before}


def main():
    p = argparse.ArgumentParser(description="locus Python binding benchmarks")
    p.add_argument("--mesh", default="cache/meshes/armadillo.off")
    p.add_argument("--json", action="store_true")
    p.add_argument("--skip-cancel", action="store_true")
    p.add_argument("--cancel-repeats", type=int, default=3)
    p.add_argument("--only", choices=["overhead", "factorization", "threads", "rss", "cancel"],
                   help="run one part only")
    a = p.parse_args()
    V, F = locus.read_mesh(a.mesh)
    s = locus.Session(V, F)
    report = {"mesh": a.mesh, "vertices": len(V), "cpus": os.cpu_count(), "load_average": os.getloadavg(),
              "nice": os.nice(0)}
    want = (lambda part: a.only in (None, part))
    if want("overhead"):
        report["overhead"] = overhead(s)
        report["overhead_tiny_mesh"] = overhead_tiny()
        report["overhead"]["tiny_mesh_overhead_over_query_pct"] = (
            100 * report["overhead_tiny_mesh"]["binding_overhead_s"] / report["overhead"]["cpp_median_s"])
    if want("factorization"):
        report["one_factorization"] = one_factorization(V, F)
    if want("threads"):
        report["threads"] = threads(s)
    if want("rss"):
        report["bad_input_rss"] = bad_input_rss(V, F)
    if want("cancel") and not a.skip_cancel:
        report["cancel"] = cancel(V, F, a.cancel_repeats)
    print(json.dumps(report, indent=2))


if __name__ == "__main__":
    main()
