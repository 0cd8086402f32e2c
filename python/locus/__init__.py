"""locus: locally solving the linear systems of geometry processing.

Two tiers, as in potpourri3d:

* one-shot functions on arrays, e.g. ``locus.geodesic_distance(V, F, 0)``,
  ``locus.logmap(V, F, center, fraction)``, ``locus.cvt(V, F, sites)``;
* ``locus.Session(V, F)``, the prepared object: the factorization of each
  operator is kept between calls, any number of threads may query it.

Arrays: V is (nv, 3) float32/float64 positions, F is (nf, 3) int32/int64/
uint32 vertex ids, or a polygon mesh (quads, mixed, n-gons) as an (nf, k)
array, a list of faces or (offsets, indices), taken by the Session and every
one-shot: geodesic distance and log maps run on the polygons as the CLI does,
the other pipelines on a triangulation with the same vertices. Results are NumPy arrays (float64 values, int32
ids) or namespaces of them. Errors raise locus.InputError, locus.NumericalError,
locus.Cancelled, locus.ResourceLimitError or locus.UsageError (a ValueError),
each carrying the engine's message; an argument of the wrong type or out of
range is a UsageError naming it. Every computing call releases the GIL;
Ctrl-C cancels it (KeyboardInterrupt).
"""
import numpy  # noqa: F401  (every array goes through NumPy: fail here, clearly, without it)

from . import _locus
from ._arguments import check_class as _check_class, checked as _checked

# An argument pybind11 cannot convert raises UsageError naming it (_arguments.py).
_check_class(_locus.Session, "Session")
_check_class(_locus.NaturalNeighbors, "NaturalNeighbors")
for _name in ("read_mesh", "write_mesh", "subdivide", "render_preview", "parameterize_disk",
              "perfect_laplacian", "self_supporting"):
    setattr(_locus, _name, _checked(getattr(_locus, _name), _name))
del _name

from ._locus import (  # noqa: F401  (the package's API)
    __version__,
    Error,
    UsageError,
    InputError,
    NumericalError,
    Cancelled,
    ResourceLimitError,
    Session,
    NaturalNeighbors,
    read_mesh,
    write_mesh,
    subdivide,
    render_preview,
    parameterize_disk,
    perfect_laplacian,
    self_supporting,
)
from ._one_shot import (  # noqa: F401
    geodesic_distance,
    geodesic,
    logmap,
    heat_values,
    cvt,
    voronoi,
    natural_neighbor_coordinates,
    skinning_weights,
    adf,
    hks,
    heat_exchange,
    deform,
    param,
)

__all__ = [
    "Error", "UsageError", "InputError", "NumericalError", "Cancelled", "ResourceLimitError",
    "Session", "NaturalNeighbors",
    "read_mesh", "write_mesh", "subdivide", "render_preview",
    "geodesic_distance", "geodesic", "logmap", "heat_values", "cvt", "voronoi", "natural_neighbor_coordinates",
    "skinning_weights", "adf", "hks", "heat_exchange", "deform", "param",
    "parameterize_disk", "perfect_laplacian", "self_supporting",
]
