"""One-shot functions: a Session for one call (the first tier).

Each builds ``Session(V, F)``, runs one query and drops it, so every call
factors its operator again; for repeated queries on one mesh keep a Session.
F may be a polygon mesh wherever a Session takes one ((nf, k) array, list of
faces, or (offsets, indices)): the Session triangulates it, keeping V.
``operator`` ('auto' default, 'cotan', 'robust') is the Session's: the Laplacian the
call runs on (the robust one takes non-manifold and degenerate meshes; see Session).
Keyword arguments ``threads`` (default 0: all cores) and ``progress``
(callable(fraction, phase); True cancels) are passed through.
"""
from ._locus import Session, parameterize_disk as _parameterize_disk


def geodesic_distance(V, F, sources, *, t_factor=None, operator="auto", **call):
    """Heat geodesic distance to every vertex, in the units of V: (nv,) float64.

    F: triangles (nf, 3), or a polygon mesh as an (nf, k) array, a list of faces
    or (offsets, indices); on polygons the distance runs on the polygon operators,
    as `locus geodesic` (see Session).
    sources: a vertex id, a 1-D array of ids, or (faces, bary) points in faces.
    t_factor: diffusion time t = t_factor * h^2, h the mean edge length (None: the
    CLI's default, 4 on triangle meshes, 8 on polygon meshes).
    NaN (no value) in connected components without a source. See Session.geodesic_distance.
    """
    return Session(V, F, operator=operator).geodesic_distance(sources, t_factor=t_factor, **call)


def geodesic(V, F, source, *, fraction=1.0, t=None, t_factor=None, save=None, load=None, operator="auto", **call):
    """`locus geodesic` with every option: distance from vertex `source` and the CLI's statistics.

    fraction: 1 (default) the whole mesh, else the geodesic disk of
    round(fraction * nv) vertices (exact subset solves). t: the diffusion time
    as the CLI's --t, a str ('4h2', '0.001') or a number (absolute); None: 4h2
    (8h2 on polygon meshes). t_factor: t = t_factor * h^2 (not with t).
    save / load: a factor cache file. Returns a namespace: .distance (NaN
    without a value), .valid and the statistics. See Session.geodesic.
    """
    return Session(V, F, operator=operator).geodesic(source, fraction=fraction, t=t, t_factor=t_factor, save=save, load=load, **call)


def logmap(V, F, center, fraction=0.05, *, t=None, t_factor=None, method="heat", angle="auto",
           lattice="default", recenter="default", clip_injective=False, save=None, load=None, operator="auto", **call):
    """`locus logmap` with every option: the log map of the geodesic disk of round(fraction * nv) vertices.

    F: triangles or a polygon mesh (as geodesic_distance; on polygons the
    polygon log map with full solves, as `locus logmap`).
    fraction: in (0, 1] (default 0.05). t, t_factor, save, load: as geodesic.
    method: 'heat' (localized), 'heat-full' or 'dem'; angle: 'auto', 'log',
    'two-ring' or 'average'; lattice: 'default', 'none', 'star', 'ring' or
    'path'; recenter: 'default', 'on' or 'off'; clip_injective: keep only the
    vertices inside the injectivity radius.
    Returns a namespace: .patch (vertex ids, center first), .distance (units of V),
    .angle (radians), .u, .v (Cartesian coordinates) and the CLI's statistics.
    See Session.logmap.
    """
    return Session(V, F, operator=operator).logmap(center, fraction, t=t, t_factor=t_factor, method=method, angle=angle,
                                lattice=lattice, recenter=recenter, clip_injective=clip_injective, save=save,
                                load=load, **call)


def heat_values(V, F, sources, targets, *, t_factor=1.0, t=0.0, operator="auto", **call):
    """(M - tL)^{-1}[target, source] by exact subset solves: (len(sources), len(targets)) float64.

    t: absolute time (length^2); 0 (default) = t_factor * h^2.
    """
    return Session(V, F, operator=operator).heat_values(sources, targets, t_factor=t_factor, t=t, **call)


def cvt(V, F, sites, iterations=10, seed=1, *, operator="auto", **options):
    """Heat CVT with remeshing: (sites, remesh_V, remesh_F, labels).

    F: triangles or polygons (triangulated, as `locus cvt`; labels index V).
    sites: number of sites (seeded random start, `seed`, default 1); iterations:
    Lloyd steps (default 10; `locus cvt --iters`); t = 4 h^2, as `locus cvt`.
    options: every other option of `locus cvt` under its name (t, solver,
    anisotropy, fit_sigma, optimize, ...; see Session.cvt_command), and threads,
    progress. Returns the final site positions (k, 3), the remeshed surface
    (n, 3) float64 and (m, 3) int32 (empty when the cells still break the
    closed-ball property), and each input vertex's cell (nv,) int32.
    Session.cvt_command gives every statistic.
    """
    r = Session(V, F, operator=operator).cvt_command(sites, iterations, seed=seed, **options)
    return r.sites, r.remesh_V, r.remesh_F, r.labels


def voronoi(V, F, generators, *, t_factor=1.0, t=0.0, operator="auto", **call):
    """Heat-diffusion Voronoi diagram of generators (ids or (faces, bary)); see Session.voronoi."""
    return Session(V, F, operator=operator).voronoi(generators, t_factor=t_factor, t=t, **call)


def natural_neighbor_coordinates(V, F, sites, point, *, t_factor=1.0, t=0.0, operator="auto", **call):
    """Natural-neighbor coordinates of point with respect to sites; see Session.natural_neighbor_coordinates."""
    return Session(V, F, operator=operator).natural_neighbor_coordinates(sites, point, t_factor=t_factor, t=t, **call)


def skinning_weights(V, F, handles, *, t_factor=1.0, t=0.0, operator="auto", **call):
    """Skinning weights, (nv, len(handles)) float64, rows summing to 1; see Session.skinning_weights."""
    return Session(V, F, operator=operator).skinning_weights(handles, t_factor=t_factor, t=t, **call).weights


def adf(V, F, vertices=None, *, t_factor=1.0, method="subset", operator="auto", **call):
    """Auto-diffusion function (M - tL)^{-1}[v, v] at vertices (None: all), t = t_factor * h^2."""
    return Session(V, F, operator=operator).auto_diffusion(vertices, t_factor=t_factor, method=method, **call)


def hks(V, F, t_factors, vertices=None, *, method="subset", operator="auto", **call):
    """Heat kernel signature: (len(vertices) or nv, len(t_factors)) float64, t_j = t_factors[j] * h^2."""
    return Session(V, F, operator=operator).heat_kernel_signature(t_factors, vertices, method=method, **call)


def heat_exchange(V, F, sources, targets, *, t_factor=1.0, t=0.0, operator="auto", **call):
    """Pairwise heat exchange: heat at each target after one step from unit heat at the sources."""
    return Session(V, F, operator=operator).heat_exchange(sources, targets, t_factor=t_factor, t=t, **call)


def deform(V, F, roi_seed, handle, offset, *, operator="auto", **kwargs):
    """Region-of-interest deformation; the deformed positions (nv, 3). See Session.deform for the options."""
    return Session(V, F, operator=operator).deform(roi_seed, handle, offset, **kwargs).V


def param(V, F, center=None, fraction=0.1, *, boundary="neumann", method="perfect", operator="auto", **call):
    """Parameterization, as `locus param`.

    center None: the whole mesh, a disk, flip-free (method 'perfect', 'cotan'
    or 'uniform'; polygon meshes allowed); returns a namespace with .uv (nv, 2).
    center given: the patch of round(fraction * nv) vertices around it
    (boundary 'neumann' or 'circle'); returns .vertices, .F, .uv.
    """
    if center is None:
        return _parameterize_disk(V, F, method=method, **call)
    return Session(V, F, operator=operator).parameterize_patch(center, fraction, boundary=boundary, **call)
