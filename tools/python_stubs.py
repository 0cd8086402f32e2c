#!/usr/bin/env python3
"""Writes python/locus/__init__.pyi, the type stubs of the locus package, from the module itself.

The parameters (names, kinds, defaults) come from inspect.signature of the
built module (the bindings' docstrings, python/locus/_signatures.py), the
types from the parameter names and defaults below, so the stubs follow every
binding that is added; tests/python/test_stubs.py fails when the committed
stubs and the module differ. Run after changing a binding:

    PYTHONPATH=build/python python3 tools/python_stubs.py [--check]
"""
import inspect
import pathlib
import sys

import locus

OUT = pathlib.Path(__file__).resolve().parents[1] / "python" / "locus" / "__init__.pyi"

HEADER = '''\
# Type stubs of the locus package, written by tools/python_stubs.py from the
# module's own signatures (tests/python/test_stubs.py keeps them in step).
from types import SimpleNamespace
from typing import Any, Callable, Dict, List, Optional, Sequence, Tuple, Union

import numpy as np
from numpy.typing import ArrayLike, NDArray

__version__: str

# progress=: a callable(fraction, phase) (a true return cancels) or a tqdm bar.
Progress = Optional[Union[Callable[[float, str], Optional[bool]], Any]]
# F: triangles (nf, 3), an (nf, k) polygon array, a list of faces, or (offsets, indices).
Faces = Union[ArrayLike, Sequence[Sequence[int]], Tuple[ArrayLike, ArrayLike]]
# Surface points: a vertex id, an array of ids, or (faces, bary).
Points = Union[int, ArrayLike, Tuple[ArrayLike, ArrayLike]]

class Error(Exception):
    code: int
    vertex: int
    column: int

class UsageError(Error, ValueError): ...
class InputError(Error): ...
class NumericalError(Error): ...
class Cancelled(Error): ...
class ResourceLimitError(Error, MemoryError): ...
'''

# Parameter types by name (else from the default's type).
BY_NAME = {
    "V": "ArrayLike", "F": "Faces", "progress": "Progress", "threads": "int", "path": "str",
    "sources": "Points", "generators": "Points", "sites": "Points", "handles": "Points", "point": "Points",
    "vertices": "ArrayLike", "targets": "ArrayLike", "t_factors": "ArrayLike", "values": "ArrayLike",
    "offset": "ArrayLike", "out": "NDArray[np.float64]", "t_factor": "float", "save": "str", "load": "str",
    "markers": "ArrayLike", "view": "ArrayLike", "properties": "Dict[str, ArrayLike]", "center": "int",
    "source": "int", "roi_seed": "int", "handle": "int", "count": "int", "seed": "int", "times": "int",
    "iterations": "int", "fraction": "float", "call": "Any", "kwargs": "Any",
}
# Return types: by the docstring's "-> X", else by function name.
RETURNS = {"ndarray": "NDArray[Any]", "namespace": "SimpleNamespace", "dict": "Dict[str, Any]",
           "(V, F)": "Tuple[NDArray[np.float64], Any]", "(faces, bary)": "Tuple[NDArray[np.int32], NDArray[np.float64]]",
           "NaturalNeighbors": "NaturalNeighbors"}
RETURNS_BY_NAME = {
    "geodesic_distance": "NDArray[np.float64]", "geodesic": "SimpleNamespace", "logmap": "SimpleNamespace",
    "heat_values": "NDArray[np.float64]", "voronoi": "SimpleNamespace", "natural_neighbor_coordinates": "SimpleNamespace",
    "skinning_weights": "NDArray[np.float64]", "adf": "NDArray[np.float64]", "hks": "NDArray[np.float64]",
    "heat_exchange": "NDArray[np.float64]", "deform": "NDArray[np.float64]", "param": "SimpleNamespace",
    "cvt": "Tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.int32], NDArray[np.int32]]",
    "write_mesh": "None", "set_positions": "None", "render_preview": "Any", "parameterize_disk": "SimpleNamespace",
    "perfect_laplacian": "SimpleNamespace", "self_supporting": "SimpleNamespace", "parameterize_patch": "SimpleNamespace",
    "prepare_heat": "None", "prepare_diffusion": "None", "prepare_patch_parameterization": "None",
}
PROPERTIES = {"num_vertices": "int", "num_faces": "int", "num_polygons": "int", "num_edges": "int", "num_sites": "int",
              "has_polygons": "bool", "mean_edge_length": "float", "V": "NDArray[np.float64]", "F": "NDArray[np.int32]",
              "triangle_polygon": "NDArray[np.int32]", "polygons": "Union[NDArray[np.int32], List[NDArray[np.int32]]]"}


# Where a name means something else in one function.
BY_FUNCTION = {("cvt", "sites"): "int", ("Session.cvt", "sites"): "int", ("Session.cvt_command", "sites"): "int",
               ("Session.cvt_command", "centroid_t"): "str", ("Session.cvt_command", "t_centroid"): "str",
               ("Session.cvt_command", "labels"): "str", ("Session.cvt_command", "sites_out"): "str"}


def annotation(function_name, p):
    """The type of parameter p: by name, else by its default's type; Optional when the default is None."""
    d = p.default
    if (function_name, p.name) in BY_FUNCTION:
        kind = BY_FUNCTION[(function_name, p.name)]
    elif p.name == "t":  # the heat method's t: '4h2' or a number; the diffusion pipelines' t: a number
        kind = "Union[str, float]" if d is None or isinstance(d, str) else "float"
    elif p.name in BY_NAME:
        kind = BY_NAME[p.name]
    else:
        kind = next((k.__name__ for k in (bool, int, float, str) if isinstance(d, k)), "Any")
    if d is None and kind not in ("Any", "Progress"):
        return f"Optional[{kind}]"
    return kind


def parameter(function_name, p):
    text = p.name if p.name == "self" else f"{p.name}: {annotation(function_name, p)}"
    if p.kind == p.VAR_POSITIONAL:
        return "*" + text
    if p.kind == p.VAR_KEYWORD:
        return "**" + text
    if p.default is not p.empty:
        text += f" = {p.default!r}"
    return text


def returns(name, sig):
    r = sig.return_annotation
    if r is not sig.empty and str(r) in RETURNS:
        return RETURNS[str(r)]
    if r is not sig.empty and str(r) in ("numpy.ndarray", "types.SimpleNamespace", "dict"):
        return {"numpy.ndarray": "NDArray[Any]", "types.SimpleNamespace": "SimpleNamespace", "dict": "Dict[str, Any]"}[str(r)]
    return RETURNS_BY_NAME.get(name, "Any")


def function(name, f, indent="", owner=""):
    sig = inspect.signature(f)
    parts, keyword_only = [], False
    for p in sig.parameters.values():
        if p.kind == p.KEYWORD_ONLY and not keyword_only:
            parts.append("*")
            keyword_only = True
        if p.kind == p.VAR_POSITIONAL:
            keyword_only = True
        parts.append(parameter(owner + name, p))
    ret = "None" if name == "__init__" else returns(name, sig)
    return f"{indent}def {name}({', '.join(parts)}) -> {ret}: ..."


def cls_stub(name, cls):
    lines = [f"class {name}:"]
    for attr, value in vars(cls).items():
        if attr == "__init__" and any(p.kind is p.VAR_POSITIONAL for p in inspect.signature(value).parameters.values()):
            continue  # no constructor of its own (NaturalNeighbors: made by Session.prepare_natural_neighbors)
        if attr.startswith("_") and attr != "__init__":
            continue
        if isinstance(value, property):
            lines += ["    @property", f"    def {attr}(self) -> {PROPERTIES.get(attr, 'Any')}: ..."]
        elif isinstance(value, staticmethod):
            f = function(attr, value.__func__, "    ", name + ".").replace("-> Any:", f"-> {name}:")
            lines += ["    @staticmethod", f]
        elif callable(value):
            lines.append(function(attr, value, "    ", name + "."))
    return lines


def stubs():
    lines = HEADER.splitlines()
    for name in ("Session", "NaturalNeighbors"):
        lines += ["", *cls_stub(name, getattr(locus, name))]
    lines.append("")
    for name in locus.__all__:
        obj = getattr(locus, name)
        if callable(obj) and not isinstance(obj, type):
            lines.append(function(name, obj))
    lines += ["", "__all__: List[str]"]
    return "\n".join(lines) + "\n"


def main():
    text = stubs()
    if "--check" in sys.argv[1:]:
        if OUT.read_text() != text:
            sys.exit(f"{OUT} is out of date: run PYTHONPATH=build/python python3 tools/python_stubs.py")
        return
    OUT.write_text(text)
    print(f"wrote {OUT}")


if __name__ == "__main__":
    main()
