#!/usr/bin/env python3
"""Remesh a surface by a heat CVT and write the result and its PNG preview.

    PYTHONPATH=build/python python3 python/examples/remesh.py cache/meshes/armadillo.off \
        --sites 2000 -o build/armadillo_remeshed.obj --preview build/armadillo_remeshed.png

The same as `locus cvt MESH --sites N -o OUT --preview PNG`, from Python: the
preview is the engine's software renderer (no matplotlib), the remesh shaded
in one colour with its triangle edges drawn.
"""
import argparse
import sys
import time

import locus


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("mesh", help="input triangle mesh (.obj, .off, .ply)")
    p.add_argument("--sites", type=int, default=2000, help="vertices of the remesh (default 2000)")
    p.add_argument("--iterations", type=int, default=10, help="Lloyd iterations (default 10)")
    p.add_argument("--seed", type=int, default=1, help="seed of the initial sites (default 1)")
    p.add_argument("-o", "--output", default="remeshed.obj", help="remeshed mesh (default remeshed.obj)")
    p.add_argument("--preview", default="remeshed.png", help="PNG preview (default remeshed.png)")
    a = p.parse_args(argv)

    V, F = locus.read_mesh(a.mesh)
    start = time.perf_counter()
    r = locus.Session(V, F).cvt(a.sites, a.iterations, a.seed, remesh=True,
                                progress=lambda f, phase: print(f"\r{100 * f:5.1f}% {phase:<40}", end="",
                                                                file=sys.stderr))
    print(file=sys.stderr)
    if not r.remeshed:
        sys.exit("the remesh is not a manifold with the input's topology; try more sites")
    locus.write_mesh(a.output, r.remesh_V, r.remesh_F)
    title = f"cvt remesh: {len(r.remesh_V)} vertices (the sites), {len(r.remesh_F)} triangles"  # as `locus cvt`
    locus.render_preview(r.remesh_V, r.remesh_F, edges=True, path=a.preview, title=title)
    print(f"{a.output}: {len(r.remesh_V)} vertices, {len(r.remesh_F)} triangles, genus {r.genus}, "
          f"mean smallest angle {r.mean_min_angle_deg:.1f} deg, Hausdorff {r.hausdorff_rel:.4f} of the diagonal "
          f"({time.perf_counter() - start:.1f} s); preview {a.preview}")


if __name__ == "__main__":
    main()
