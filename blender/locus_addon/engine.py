"""The locus module inside Blender, and the Session kept per object.

Blender's Python is the system interpreter on Debian, so `pip install .` or
`cmake --install` of locus makes it importable; else the add-on's preference
"locus module folder" (the folder holding the `locus` package, e.g.
build/python), or the environment variable LOCUS_MODULE_DIR (Blender ignores
PYTHONPATH unless started with --python-use-system-env; an add-on enabled by
`blender --addons` has no preferences), is put on sys.path.

The cache: one Session per (object, evaluated or raw), keyed by a digest of
the faces and one of the positions. Same faces, other positions: the
Session keeps its symbolic factors and takes the new positions
(Session.set_positions); other faces: a new Session. A few objects at most
are kept (least recently used dropped), so a scene of many meshes does not
hold every factor in memory.
"""
import collections
import hashlib
import os
import sys
import threading

_MAX_SESSIONS = 4
_lock = threading.Lock()
_sessions = collections.OrderedDict()  # key -> _Entry
_module = None


class NotAvailable(RuntimeError):
    """The locus module cannot be imported."""


def locus(extra_path=""):
    """The locus module, importing it on first use (extra_path: the preference folder)."""
    global _module
    if _module is not None:
        return _module
    extra_path = extra_path or os.environ.get("LOCUS_MODULE_DIR", "")
    try:
        import locus as m
    except ImportError as first:
        if not extra_path:
            raise NotAvailable(f"the locus Python module is not importable by Blender's Python ({first}); "
                               "install it (pip install . in the locus checkout) or set its folder in "
                               "the add-on's preferences or in LOCUS_MODULE_DIR") from None
        if extra_path not in sys.path:
            sys.path.append(extra_path)
        try:
            import locus as m
        except ImportError as second:
            raise NotAvailable(f"no usable locus module in '{extra_path}' ({second})") from None
    _module = m
    return m


def digest(*arrays):
    h = hashlib.blake2b(digest_size=16)
    for a in arrays:
        h.update(str(a.dtype).encode())
        h.update(str(a.shape).encode())
        h.update(memoryview(a).cast("B") if a.flags.c_contiguous else a.tobytes())
    return h.hexdigest()


class _Entry:
    def __init__(self, session, faces_key, positions_key):
        self.session, self.faces_key, self.positions_key = session, faces_key, positions_key


def session(key, arrays, progress=None):
    """(Session, how) for MeshArrays `arrays` under cache `key`; how is 'cached', 'moved' or 'new'.

    Runs on the worker thread: building a Session checks and triangulates
    the mesh (the GIL is released meanwhile).
    """
    m = locus()
    with _lock:
        entry = _sessions.get(key)
        if entry is not None:
            _sessions.move_to_end(key)
    if entry is not None and entry.faces_key == arrays.faces_key:
        if entry.positions_key == arrays.positions_key:
            return entry.session, "cached"
        entry.session.set_positions(arrays.V)
        entry.positions_key = arrays.positions_key
        return entry.session, "moved"
    s = m.Session(arrays.V, arrays.F)
    with _lock:
        _sessions[key] = _Entry(s, arrays.faces_key, arrays.positions_key)
        _sessions.move_to_end(key)
        while len(_sessions) > _MAX_SESSIONS:
            _sessions.popitem(last=False)
    return s, "new"


def forget(keep=None):
    """Drops the Sessions of objects not in `keep` (a set of names), or all of them."""
    with _lock:
        for key in list(_sessions):
            if keep is None or key[0] not in keep:
                del _sessions[key]


def cached_keys():
    with _lock:
        return list(_sessions)
