"""The model's functions compiled with numba: the fast path's copy of the one source.

The model (``analytic.geometry``, ``limits``, ``aero``, ``eom``, ``friction``, ``stages``) is
written as plain Python on floats, which the reference path runs as it is.
This module gives the compiled path the same functions, compiled: for each
model module a namespace (``compiled.eom``, ``compiled.stages``, ...) whose
functions are numba dispatchers of the very same code objects, with their
calls to each other rebound to the compiled versions. Importing it imports
numba; ``import analytic`` and the reference path never do.

numba caches machine code on disk keyed on each function's own source file,
not on the files it calls into: after an edit to ``eom.py`` the cached
``kernel.shots`` would still hold the old equations. So the cache is stamped
with a fingerprint of every source the compiled code depends on
(``SOURCES``), and a cache whose stamp differs is dropped before anything is
loaded from it.
"""

from __future__ import annotations

import hashlib
import types
from pathlib import Path

import numba

from analytic import aero, eom, friction, geometry, limits, outcome, parameters, stages

#: The modules whose functions are compiled, each calling only those before it.
MODEL_MODULES = (geometry, limits, aero, eom, friction, stages)
#: Options of every compiled function. ``error_model="numpy"``: a division by
#: zero gives inf/NaN (a rejected step) instead of raising, as in Python's
#: float arithmetic on the reference path; no fastmath, so IEEE arithmetic is
#: kept and the compiled functions round exactly as the Python ones do.
OPTIONS = dict(cache=True, nogil=True, error_model="numpy")
#: Functions numba inlines into their callers at its own IR level (it does not
#: inline across compiled functions otherwise): the right-hand side and the
#: equations it calls on every evaluation. Measured on the benchmark's designs:
#: without this, a shot takes about 1.3x as long.
INLINE = {"eom": ("terms", "slide_constraint", "slide_system", "slide_accelerations", "swing_accelerations"),
          "stages": ("derivative",)}
_HERE = Path(__file__).parent
#: Every source whose change must invalidate the compiled cache: the model,
#: the modules whose constants it reads at import, this module and the kernel.
SOURCES = tuple(Path(module.__file__) for module in (*MODEL_MODULES, outcome, parameters)) + (
    _HERE / "compiled.py", _HERE / "kernel.py")
#: Name of the stamp file beside the cached machine code.
STAMP_NAME = "analytic-model-sources.sha256"


def compile_modules(modules, options, inline=None) -> dict[str, types.ModuleType]:
    """numba twins of every function defined in ``modules``, by module short name.

    Each twin is a new function object on the original's code, with its own
    globals: a copy of its module's, in which every function of ``modules``
    is replaced by its compiled twin. numba reads those globals only when it
    compiles, so the order of definition does not matter.

    ``inline`` maps a short module name to the functions numba should inline
    into their callers.

    Returns
    -------
    dict of short module name (``"eom"``) to a module object whose attributes
    are the compiled functions.
    """
    twins: dict[types.FunctionType, object] = {}
    namespaces = []
    for module in modules:
        namespace = dict(vars(module))
        for name, value in vars(module).items():
            if isinstance(value, types.FunctionType) and value.__module__ == module.__name__:
                twin = types.FunctionType(value.__code__, namespace, name, value.__defaults__, value.__closure__)
                twin.__qualname__, twin.__module__, twin.__doc__ = value.__qualname__, value.__module__, value.__doc__
                short = module.__name__.rsplit(".", 1)[-1]
                hint = {"inline": "always"} if name in (inline or {}).get(short, ()) else {}
                twins[value] = numba.njit(**options, **hint)(twin)
        namespaces.append((module, namespace))
    compiled = {}
    for module, namespace in namespaces:
        for name, value in namespace.items():
            if isinstance(value, types.FunctionType) and value in twins:
                namespace[name] = twins[value]
        short = module.__name__.rsplit(".", 1)[-1]
        twin_module = types.ModuleType(f"{__name__}.{short}", f"{module.__name__}, compiled.")
        for name, value in vars(module).items():
            if isinstance(value, types.FunctionType) and value.__module__ == module.__name__:
                setattr(twin_module, name, twins[value])
        compiled[short] = twin_module
    return compiled


def source_fingerprint(paths) -> str:
    """SHA-256 over the names and contents of ``paths``, in order."""
    digest = hashlib.sha256()
    for path in paths:
        digest.update(Path(path).name.encode())
        digest.update(Path(path).read_bytes())
    return digest.hexdigest()


def cache_directory(dispatcher) -> Path:
    """Where numba keeps ``dispatcher``'s machine code (``__pycache__`` beside its source,
    or under ``NUMBA_CACHE_DIR``). numba exposes no public accessor for it."""
    return Path(dispatcher._cache._cache_path)


def drop_stale_cache(directory: Path, paths, stamp_name: str = STAMP_NAME) -> bool:
    """Delete numba's cached code of ``paths``' modules in ``directory`` unless its stamp
    matches their fingerprint; then stamp it. Returns whether anything was dropped.

    A directory that cannot be written (a read-only install) is left alone:
    numba then keeps its cache elsewhere or compiles in memory.
    """
    fingerprint = source_fingerprint(paths)
    stamp = Path(directory) / stamp_name
    try:
        if stamp.read_text() == fingerprint:
            return False
    except OSError:
        pass
    stems = {Path(path).stem for path in paths}
    try:
        Path(directory).mkdir(parents=True, exist_ok=True)
        for cached in Path(directory).glob("*.nb[ic]"):
            if cached.name.split(".", 1)[0] in stems:
                cached.unlink(missing_ok=True)
        stamp.write_text(fingerprint)
    except OSError:
        return False
    return True


_modules = compile_modules(MODEL_MODULES, OPTIONS, INLINE)
geometry_ = _modules["geometry"]   # trailing underscore: not the Python module of that name
limits_ = _modules["limits"]
aero_ = _modules["aero"]
eom_ = _modules["eom"]
friction_ = _modules["friction"]
stages_ = _modules["stages"]
drop_stale_cache(cache_directory(eom_.terms), SOURCES)
