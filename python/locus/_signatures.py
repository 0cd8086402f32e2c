"""Introspectable signatures for the bound functions, and progress= adapters.

The extension's docstrings open with the Python signature, defaults
included (module.cpp turns off pybind11's own, which spells C++ types), e.g.
"logmap(center, fraction=0.05, *, t=None, method='heat', ...) -> namespace".
inspect.signature cannot read a builtin without __text_signature__, so each
wrapper made by _arguments.checked gets an inspect.Signature parsed from that
line: help(), IDEs and inspect then show the real parameters and defaults.

progress= takes a callable(fraction, phase) (a true return value cancels) or
a tqdm-like bar (an object with update() and n, e.g. tqdm.tqdm(total=100)):
the bar is advanced to fraction * total and its description set to the phase.
"""
import ast
import inspect
import re

_EMPTY = inspect.Parameter.empty
# The return types the docstrings name, as the objects they are.
_RETURNS = {"ndarray": "numpy.ndarray", "namespace": "types.SimpleNamespace", "dict": "dict"}
_NAME = re.compile(r"^[\w.]+\(")


def _default(node):
    try:
        return ast.literal_eval(node)
    except ValueError:
        return _Text(ast.unparse(node))


class _Text:
    """A default the signature shows as written (not a Python literal)."""

    def __init__(self, text):
        self.text = text

    def __repr__(self):
        return self.text


def _split_first_line(line):
    """("params", "ret" or None) of "name(params) -> ret", the parentheses matched; None if not that form."""
    head = _NAME.match(line)
    if not head:
        return None
    depth = 0
    for i in range(head.end() - 1, len(line)):
        depth += {"(": 1, "[": 1, "{": 1, ")": -1, "]": -1, "}": -1}.get(line[i], 0)
        if depth == 0:
            rest = line[i + 1:].strip()
            if rest and not rest.startswith("->"):
                return None
            return line[head.end():i], (rest[2:].strip() or None) if rest else None
    return None


def parse(doc, method=False):
    """The inspect.Signature of a docstring's first line "name(params) -> ret", or None."""
    if not doc:
        return None
    split = _split_first_line(doc.split("\n", 1)[0].strip())
    if split is None:
        return None
    params, ret = split
    try:
        args = ast.parse(f"def f({'self, ' if method else ''}{params}): pass").body[0].args
    except SyntaxError:
        return None
    P = inspect.Parameter
    out = []
    positional = args.posonlyargs + args.args
    defaults = [_EMPTY] * (len(positional) - len(args.defaults)) + [_default(d) for d in args.defaults]
    for a, d in zip(positional, defaults):
        out.append(P(a.arg, P.POSITIONAL_OR_KEYWORD, default=d))
    if args.vararg:
        out.append(P(args.vararg.arg, P.VAR_POSITIONAL))
    for a, d in zip(args.kwonlyargs, args.kw_defaults):
        out.append(P(a.arg, P.KEYWORD_ONLY, default=_EMPTY if d is None else _default(d)))
    if args.kwarg:
        out.append(P(args.kwarg.arg, P.VAR_KEYWORD))
    annotation = _RETURNS.get(ret.strip(), ret.strip()) if ret else _EMPTY
    return inspect.Signature(out, return_annotation=annotation)


def progress_callable(progress, usage_error):
    """progress as the callable the bindings take (None, a callable, or a tqdm-like bar)."""
    if progress is None or callable(progress):
        return progress
    if not (hasattr(progress, "update") and hasattr(progress, "n")):
        raise usage_error(f"progress must be None, a callable(fraction, phase) or a tqdm bar, "
                          f"got {type(progress).__name__}")
    bar = progress
    if getattr(bar, "total", None) is None:
        bar.total = 100
    total = float(bar.total)

    def relay(fraction, phase):
        step = float(fraction) * total - bar.n
        if phase and hasattr(bar, "set_description_str"):
            bar.set_description_str(str(phase), refresh=False)
        if step > 0:
            bar.update(step)
        return False

    return relay
