"""Every option of a migrated CLI command is a keyword argument of the Python
function of that command, with the same name ('-' as '_') and default.

The CLI's options are those `locus <command> --help` lists; the defaults are
the engine's (locus._locus.request_fields, built from the request structs the
CLI binds its options to). The commands not migrated yet are listed as pending.
"""
import ast
import inspect
import re
import subprocess

import numpy as np
import pytest

import locus
from locus import _locus

MIGRATED = {"geodesic": locus.geodesic, "logmap": locus.logmap, "adf": locus.Session.adf, "hks": locus.Session.hks,
            "heat": locus.Session.heat, "deform": locus.Session.deform,
            "nncoords": locus.Session.nncoords, "param": locus.Session.param,
            "perfect-laplacian": locus.Session.perfect_laplacian, "selfsupport": locus.Session.selfsupport,
            "voronoi": locus.Session.voronoi_command, "cvt": locus.Session.cvt_command,
            "skinweights": locus.Session.skinweights_command, "factor": locus.Session.factor_command}
PENDING = []
# info has no options of its own (Session.info() takes none); run drives the
# other commands in child processes, a batch front end with no Python twin.
WITHOUT_OWN_OPTIONS = {"info": locus.Session.info}
FRONT_END_ONLY = ["run"]
# The CommandTable's options: threads is every Python call's keyword, subdivide
# is locus.subdivide, seed is perfect-laplacian's noise seed and unused by the others, operator is the
# Session's (Session(V, F, operator=), checked below; factor's --operator is the older spelling of its --matrix),
# no_weld is read_mesh(weld=), the rest present a result.
COMMON = {"help", "json", "output", "threads", "seed", "subdivide", "max_memory", "preview", "preview_t", "view",
          "operator", "no_weld"}
POSITIONAL = {"geodesic": ["source"], "logmap": ["center"], "adf": [], "hks": ["ts"], "heat": ["source", "target"],
              "deform": ["roi_seed", "handle", "offset"], "nncoords": ["sites", "point"], "param": [], "perfect-laplacian": [],
              "selfsupport": [], "voronoi": [], "cvt": [], "skinweights": [], "factor": []}


def parameters(fn):
    """name -> default (inspect.Parameter.empty when required) of a Python function or a pybind11 method.

    pybind11 methods have no inspectable signature; their docstring opens with
    it ("adf(self: ..., t: str = '1h2', *, vertices: object = None, ...) -> object").
    """
    try:
        return {n: p.default for n, p in inspect.signature(fn).parameters.items()}
    except ValueError:
        pass
    line = fn.__doc__.strip().splitlines()[0]
    args = line[line.index("(") + 1:line.rindex(")")]
    out = {}
    for part in re.split(r",\s*(?![^()\[\]]*[)\]])", args):
        if part in ("*", "") or part.startswith("self"):
            continue
        m = re.match(r"(\w+)(?::\s*[^=]+?)?(?:\s*=\s*(.+))?$", part.strip())
        out[m.group(1)] = ast.literal_eval(m.group(2)) if m.group(2) else inspect.Parameter.empty
    return out


def cli_options(cli, command):
    text = subprocess.run([str(cli), command, "--help"], check=True, capture_output=True, text=True).stdout
    return [m.group(1).replace("-", "_") for m in re.finditer(r"^\s+(?:-[A-Za-z],)?--([a-z][a-z0-9-]*)", text, re.M)]


def python_default(value):
    """A Python default as the engine's text: None = not given."""
    if value is None:
        return ""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return "%.6g" % value
    return str(value)


@pytest.mark.parametrize("command", sorted(MIGRATED))
def test_cli_options_are_python_keywords(cli, command):
    params = parameters(MIGRATED[command])
    fields = dict(_locus.request_fields(command))
    for option in cli_options(cli, command):
        if option in COMMON:
            continue
        assert option in fields, f"{command} --{option} is not a field of the engine's request"
        assert option in params, f"{command} --{option} is not a keyword of locus.{command}"
        if option in POSITIONAL[command]:
            continue  # required, no default
        assert python_default(params[option]) == fields[option], f"{command}: default of {option}"


@pytest.mark.parametrize("command", sorted(MIGRATED))
def test_operator_is_a_keyword_with_the_cli_default(cli, command):
    """--operator is a keyword of the one-shot function, or of the Session the method runs on."""
    assert "operator" in cli_options(cli, command)
    params = parameters(MIGRATED[command])
    if "operator" not in params:
        params = parameters(locus.Session.__init__)
    assert params["operator"] == "auto"


def test_every_command_is_migrated_or_pending(cli):
    text = subprocess.run([str(cli), "--help"], check=True, capture_output=True, text=True).stdout
    listed = re.findall(r"^  ([a-z][a-z-]*)\s{2,}", text.split("Subcommands:")[1], re.M)
    assert sorted(listed) == sorted(list(MIGRATED) + PENDING + list(WITHOUT_OWN_OPTIONS) + FRONT_END_ONLY)


def test_info_takes_no_options():
    assert [p for p in parameters(locus.Session.info) if p != "self"] == []


def test_diagonal_method_takes_the_cli_name(sphere):
    """`locus adf --method selinv`: the same name in Python; selected inversion
    and per-vertex subset solves are two algorithms for the same entries."""
    s = locus.Session(*sphere)
    by_selinv = s.auto_diffusion(method="selinv")
    assert np.allclose(by_selinv, s.auto_diffusion(method="subset"), rtol=1e-9, atol=0)
    assert np.array_equal(s.auto_diffusion(method="selected_inversion"), by_selinv)
    with pytest.raises(locus.UsageError, match="selinv"):
        s.auto_diffusion(method="full-inverse")
