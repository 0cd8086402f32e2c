"""Arguments the bindings cannot convert, raised as locus.UsageError naming the argument.

pybind11 converts each argument to its C++ parameter type before a binding
runs. A Python int beyond that type's range (``threads=2**63``, ``cvt(V, F,
2**63)``) or of another type (``seed=-1`` for the unsigned seed,
``threads="2"``) fails that conversion, and pybind11 raises a TypeError that
lists the C++ signatures instead of saying which argument is wrong. A caller
of locus gets a locus exception for every wrong argument (UsageError, also a
ValueError), so each binding is wrapped: on pybind11's conversion failure the
call's arguments are matched against the signature pybind11 reports, and the
first one its parameter type cannot hold is named with the range or type the
parameter takes.

``t_factor``: the engine reads 0 as "the method's default"; in Python the
default is spelled None (or the argument left out), so an explicit
``t_factor`` that is not a finite positive number is refused here, before the
engine would silently use its default.
"""
import functools
import math
import operator
import re

from ._locus import UsageError
from ._signatures import parse as _parse_signature, progress_callable as _progress_callable

# The C++ type of an `int` parameter is int32 (ids, counts, threads) unless named here.
_INT_RANGES = {
    "seed": (0, 2 ** 64 - 1),  # uint64
    "threads": (0, 4096),      # as the CLI's --threads; 0 = all cores
}
_INT32 = (-(2 ** 31), 2 ** 31 - 1)

# pybind11's message: "NAME(): incompatible function arguments. The following
# argument types are supported:\n    1. (self: T, a: int, *, b: float = 1.0) -> R\n\nInvoked with: ..."
_MARKERS = ("incompatible function arguments", "incompatible constructor arguments")
_OVERLOAD = re.compile(r"^\s*\d+\.\s*\((.*)\)\s*->", re.M)


def _usage_error(message):
    e = UsageError(message)
    e.code, e.vertex, e.column = 2, -1, -1
    return e


def _split_top_level(text):
    """Splits "a: int, b: List[int] = [1, 2]" at the commas outside brackets and quotes."""
    parts, depth, quote, start = [], 0, None, 0
    for i, c in enumerate(text):
        if quote:
            quote = None if c == quote else quote
        elif c in "'\"":
            quote = c
        elif c in "([{":
            depth += 1
        elif c in ")]}":
            depth -= 1
        elif c == "," and depth == 0:
            parts.append(text[start:i].strip())
            start = i + 1
    if text[start:].strip():
        parts.append(text[start:].strip())
    return parts


def _parameters(signature):
    """[(name, type, keyword_only)] of one pybind11 signature's parameter list."""
    params, keyword_only = [], False
    for p in _split_top_level(signature):
        if p == "*":
            keyword_only = True
            continue
        if p.startswith("*"):  # *args / **kwargs: nothing to check
            continue
        head = p.split("=", 1)[0]
        name, _, kind = head.partition(":")
        params.append((name.strip(), kind.strip(), keyword_only))
    return params


def _bind(params, args, kwargs):
    """{name: value} of the call's arguments for one signature, or None if they do not fit it."""
    positional = [p for p in params if not p[2]]
    if len(args) > len(positional):
        return None
    bound = {p[0]: a for p, a in zip(positional, args)}
    names = {p[0] for p in params}
    for k, v in kwargs.items():
        if k not in names or k in bound:
            return None
        bound[k] = v
    return bound


def _is_integer(value):
    if isinstance(value, bool):
        return True  # pybind11 takes a bool for an int
    try:
        operator.index(value)
        return True
    except TypeError:
        return False


def _problem(name, kind, value):
    """Why `value` cannot be the C++ parameter `name: kind`, or None if it can."""
    if kind == "int":
        if not _is_integer(value):
            return f"{name} must be an integer, got {type(value).__name__} {value!r}"
        lo, hi = _INT_RANGES.get(name, _INT32)
        v = operator.index(value)
        if not lo <= v <= hi:
            return f"{name} = {v} is outside {lo}..{hi}"
        return None
    if kind == "float":
        try:
            float(value)
        except (TypeError, ValueError, OverflowError):
            return f"{name} must be a number that fits a double, got {type(value).__name__} {value!r}"
        return None
    if kind == "bool" and not isinstance(value, bool):
        return f"{name} must be True or False, got {type(value).__name__} {value!r}"
    if kind == "str" and not isinstance(value, str):
        return f"{name} must be a string, got {type(value).__name__} {value!r}"
    return None


def _conversion_error(qualname, message, args, kwargs):
    """The UsageError for pybind11's TypeError `message` about the call (args, kwargs)."""
    found = []
    for signature in _OVERLOAD.findall(message):
        params = _parameters(signature)
        bound = _bind(params, args, kwargs)
        if bound is None:
            continue
        kinds = {p[0]: p[1] for p in params}
        for name, value in bound.items():
            why = _problem(name, kinds[name], value)
            if why:
                found.append(why)
                break
    if found:
        return _usage_error(f"{qualname}: {found[0]}")
    first = message.split("\n", 1)[0]
    return _usage_error(f"{qualname}: wrong arguments ({first}); see help({qualname})")


def _check_t_factor(qualname, kwargs):
    if "t_factor" not in kwargs or kwargs["t_factor"] is None:
        return
    t = kwargs["t_factor"]
    try:
        ok = math.isfinite(float(t)) and float(t) > 0
    except (TypeError, ValueError, OverflowError):
        return  # not a number: the conversion reports it
    if not ok:
        raise _usage_error(f"{qualname}: t_factor must be a finite positive number (got {t!r}); "
                           "leave it out (or None) for the default")


def checked(function, qualname, method=False, doc=None):
    """`function` with pybind11's argument-conversion TypeError raised as UsageError.

    The wrapper also carries the signature of the docstring's first line
    (inspect.signature works on it) and takes a tqdm bar as progress=.
    """

    @functools.wraps(function)
    def call(*args, **kwargs):
        _check_t_factor(qualname, kwargs)
        if kwargs.get("progress") is not None:
            kwargs["progress"] = _progress_callable(kwargs["progress"], _usage_error)
        try:
            return function(*args, **kwargs)
        except TypeError as e:
            message = str(e)
            if not any(m in message for m in _MARKERS):
                raise
            # The signatures list `self` first; a method's call has it in args too.
            raise _conversion_error(qualname, message, args, kwargs) from None

    signature = _parse_signature(doc or function.__doc__, method)
    if signature is not None:
        call.__signature__ = signature
    return call


def check_class(cls, name):
    """Wraps the public methods, static methods and the constructor of a bound class in place."""
    for attr, value in list(vars(cls).items()):
        if attr != "__init__" and attr.startswith("_"):
            continue
        if isinstance(value, staticmethod):
            setattr(cls, attr, staticmethod(checked(value.__func__, f"{name}.{attr}")))
        elif callable(value) and not isinstance(value, (classmethod, type, property)):
            if attr == "__init__":
                setattr(cls, attr, checked(value, name, method=True, doc=cls.__doc__))
            else:
                setattr(cls, attr, checked(value, f"{name}.{attr}", method=True))
    return cls
