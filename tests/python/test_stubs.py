"""The type stubs (python/locus/__init__.pyi) list every public function,
method and property of the module with the parameters inspect.signature
reports, and inspect.signature works on every one of them.

The stubs are read with ast (not imported), the module through inspect, so a
binding added without regenerating the stubs (tools/python_stubs.py) fails
here; mypy --strict checks the stubs themselves when Debian's mypy is there.
"""
import ast
import inspect
import shutil
import subprocess

import pytest

import locus

from conftest import SOURCE_DIR

STUB = SOURCE_DIR / "python" / "locus" / "__init__.pyi"


def stub_tree():
    return ast.parse(STUB.read_text())


def stub_functions(body):
    return {n.name: n for n in body if isinstance(n, ast.FunctionDef)}


def stub_classes():
    return {n.name: n for n in stub_tree().body if isinstance(n, ast.ClassDef)}


def stub_parameters(node):
    """[(name, kind, default)] of a stub function, kinds as inspect names them."""
    a = node.args
    out = []
    positional = a.posonlyargs + a.args
    defaults = [inspect.Parameter.empty] * (len(positional) - len(a.defaults)) + [ast.literal_eval(d) for d in a.defaults]
    kinds = ["POSITIONAL_ONLY"] * len(a.posonlyargs) + ["POSITIONAL_OR_KEYWORD"] * len(a.args)
    out += [(p.arg, k, d) for p, k, d in zip(positional, kinds, defaults)]
    if a.vararg:
        out.append((a.vararg.arg, "VAR_POSITIONAL", inspect.Parameter.empty))
    out += [(p.arg, "KEYWORD_ONLY", inspect.Parameter.empty if d is None else ast.literal_eval(d))
            for p, d in zip(a.kwonlyargs, a.kw_defaults)]
    if a.kwarg:
        out.append((a.kwarg.arg, "VAR_KEYWORD", inspect.Parameter.empty))
    return out


def module_parameters(f):
    return [(p.name, p.kind.name, p.default) for p in inspect.signature(f).parameters.values()]


def constructible(cls):
    """Whether cls has a constructor of its own (NaturalNeighbors comes from Session.prepare_natural_neighbors)."""
    params = inspect.signature(cls.__init__).parameters.values()
    return not any(p.kind is p.VAR_POSITIONAL for p in params)


def public_functions():
    return [n for n in locus.__all__ if callable(getattr(locus, n)) and not isinstance(getattr(locus, n), type)]


@pytest.mark.parametrize("name", public_functions())
def test_module_function_in_stub(name):
    functions = stub_functions(stub_tree().body)
    assert name in functions, f"locus.{name} is missing from {STUB.name} (tools/python_stubs.py)"
    assert stub_parameters(functions[name]) == module_parameters(getattr(locus, name)), name


@pytest.mark.parametrize("cls", ["Session", "NaturalNeighbors"])
def test_class_members_in_stub(cls):
    members = stub_functions(stub_classes()[cls].body)
    for attr, value in vars(getattr(locus, cls)).items():
        if attr.startswith("_") and (attr != "__init__" or not constructible(getattr(locus, cls))):
            continue
        assert attr in members, f"locus.{cls}.{attr} is missing from {STUB.name} (tools/python_stubs.py)"
        if isinstance(value, property):
            continue
        f = value.__func__ if isinstance(value, staticmethod) else value
        assert stub_parameters(members[attr]) == module_parameters(f), f"{cls}.{attr}"
    extra = set(members) - set(vars(getattr(locus, cls)))
    assert not extra, f"{STUB.name} lists {cls} members the module lacks: {sorted(extra)}"


def test_every_name_of_all_is_in_stub():
    tree = stub_tree()
    names = set(stub_functions(tree.body)) | set(stub_classes())
    assert set(locus.__all__) <= names


def test_signatures_of_session_methods(sphere):
    sig = inspect.signature(locus.Session.logmap)
    assert list(sig.parameters)[:3] == ["self", "center", "fraction"]
    assert sig.parameters["method"].default == "heat" and sig.parameters["fraction"].default == 0.05
    assert sig.parameters["method"].kind is inspect.Parameter.KEYWORD_ONLY
    assert list(inspect.signature(locus.Session).parameters) == ["V", "F", "operator"]
    # A bound method: inspect drops self.
    assert list(inspect.signature(locus.Session(*sphere).cvt).parameters)[0] == "sites"


def test_py_typed_marker():
    assert (STUB.parent / "py.typed").exists()


def test_mypy_strict_accepts_the_stubs(tmp_path):
    mypy = shutil.which("mypy")
    if mypy is None:
        pytest.skip("needs mypy (apt-get install mypy)")
    example = tmp_path / "typed_example.py"
    example.write_text(
        "import numpy as np\nimport locus\n\n\n"
        "from numpy.typing import NDArray\n\n\n"
        "def distance(V: NDArray[np.float64], F: NDArray[np.int32]) -> float:\n"
        "    s = locus.Session(V, F)\n"
        "    d = s.geodesic_distance([0, 1], t_factor=None, progress=lambda f, p: None)\n"
        "    r = locus.logmap(V, F, 0, 0.1, method='heat')\n"
        "    return float(d.max()) + float(r.u[0]) + s.mean_edge_length\n")
    r = subprocess.run([mypy, "--strict", "--no-incremental", "--cache-dir", str(tmp_path / "cache"), str(example)],
                       capture_output=True, text=True, env={"MYPYPATH": str(STUB.parent.parent), "PATH": "/usr/bin:/bin"})
    assert r.returncode == 0, r.stdout + r.stderr
