"""The model compiled with numba: how the fast path runs the very source the reference path runs.

The model (``analytic.geometry``, ``limits``, ``peaks``, ``aero``, ``eom``,
``friction``, ``stages``, ``sequence``) is plain Python on floats and tuples,
which the reference path runs as it is. This module gives the compiled path
the same functions, compiled (``compile_modules``): for each model module a
namespace whose functions are compiled twins of the very same code objects,
with their calls to each other rebound to the compiled versions.
``kernel_scope(scope)`` compiles the model and the kernel for compiled callers
only (emitted as machine code only inside the scope's one cached entry point,
its ``kernel.shots``), with the scope's switches in the model's globals
(``analytic.scope``: what a smaller copy leaves out is pruned before it is
typed); ``kernel_twins`` are the whole model's, for ``callable_twins``
(``compiled.eom_``, ``compiled.stages_``, ...), which Python calls (the
tests compare them with the Python functions).

Two mechanisms compile it, to the same machine arithmetic and the same
numbers (``mechanism()`` says which one this process uses):

* ``"linked"`` (``analytic.fast.numba_linking``): numba's internals, each function
  compiled once per argument type and linked once, into its entry point; the
  shorter cold compile, used wherever every internal it touches is there
  with the signature and body it was written against;
* ``"public"``: numba's public API only, each function the kernel calls
  registered with ``numba.extending.overload`` (what ``register_jitable``
  does) and each entry point a ``numba.njit(cache=True)``; numba then
  compiles and emits each function as an entry point of its own (a longer
  cold compile), and it serves where the linked one does not fit the numba
  installed, or where ``TREBUCHET_NUMBA=public`` asks for it.

Importing this module imports numba and builds nothing: every twin is made
on first use. ``import analytic`` and the reference path never import it.
Only the entry points are cached on disk, each under a name that says its
mechanism (``shots_ideal``, ``shots_ideal_public``); a cold compile takes
tens of seconds of CPU (``python -m benchmarks --cold`` measures each scope's).

numba caches machine code on disk keyed on each function's own source file,
not on the files it calls into: after an edit to ``eom.py`` the cached
``kernel.shots`` would still hold the old equations. So each mechanism's
cache is stamped with a fingerprint of every source the compiled code
depends on (``SOURCES``), and a cache whose stamp differs is dropped before
anything is loaded from it.
"""

from __future__ import annotations

import functools
import hashlib
import os
import threading
import types
from pathlib import Path

import numba
from numba.extending import overload

from analytic import (aero, eom, floating_arm, friction, geometry, limits, outcome, parameters, peaks, sequence, stages,
                      states)
from analytic.fast import dop853, kernel, kernel_loads
from analytic import scope as switches   # (the scopes' switches; a parameter below is named scope)
from analytic.scope import EVERYTHING, Scope

#: The modules whose functions are compiled, each calling only those before it.
MODEL_MODULES = (geometry, limits, peaks, aero, floating_arm, eom, friction, states, stages, sequence)
#: Options of every compiled function. ``error_model="numpy"``: a division by
#: zero gives inf/NaN (a rejected step) instead of raising, as in Python's
#: float arithmetic on the reference path; no fastmath, so IEEE arithmetic is
#: kept and the compiled functions round exactly as the Python ones do.
OPTIONS = dict(nogil=True, error_model="numpy")
#: Options of the functions only compiled code calls (the kernel's parts and
#: the model's functions as the kernel calls them), which have no disk cache
#: of their own: the kernel's one entry point (``kernel.shots``) holds all
#: their machine code and is cached. (The linked mechanism also leaves out
#: their wrappers to and from Python objects: ``numba_linking.WITHOUT_WRAPPERS``.)
#:
#: ``_nrt=False`` (an option ``numba.extending.register_jitable``'s own
#: documentation shows): no reference counting of the arrays they are handed.
#: numba counts a reference to every array argument a function keeps in a
#: variable, and to every view (``K[s]``), with an atomic add and subtract
#: per call that LLVM cannot prove away; in the right-hand side's callers that
#: would be a quarter of a shot's time (perf: ``NRT_incref``/``NRT_decref``).
#: These functions allocate nothing and return no array, and their callers
#: hold every array they are given for the whole call, so the counts are not
#: needed. A function that allocates is declared with
#: ``analytic.fast.marks.internal(allocates=True)`` and counts as usual; numba
#: refuses to compile an allocation in one that is not. Every option is given
#: explicitly (``forceinline`` too): numba lets a callee inherit an option it
#: does not set from whichever caller compiles it first.
INTERNAL = dict(OPTIONS, _nrt=False)
#: Options of a function Python calls: with its wrappers, and cached.
CALLABLE = dict(OPTIONS, cache=True)
#: Functions LLVM inlines into every caller (numba's ``forceinline``: LLVM's
#: ``alwaysinline``): the right-hand side and the equations it calls on every
#: evaluation: without it, every shot is slower (``python -m benchmarks``, keys
#: ``fast_median_shot_s`` and ``batch_one_thread_shots_per_s``). With friction, the
#: joint forces are taken three times per evaluation at the same angles; inlined,
#: LLVM computes their sines and cosines once (faster with friction, key
#: ``friction_fast_time_ratio``; the same bits and cold compile). The sites a shot
#: passes only a few times call ``dop853.derivative_call`` instead: one copy of the
#: model for them all (a shorter compile). numba's own inlining (``inline="always"``,
#: at its IR level) gives shots a little faster but copies and re-types each callee at
#: every call site, for a far longer cold compile (``--cold``, key ``compile_s``).
INLINE = {"floating_arm": ("terms",),
          "eom": ("sines", "terms", "swing_terms", "frame_eliminated", "machine_terms", "slide_constraint",
                  "slide_system", "slide_accelerations", "swing_accelerations", "joint_forces", "joint_forces_sliding",
                  "joint_forces_in_gravity", "frame_acceleration", "frame_coupling", "total_mass", "solve_symmetric",
                  "symmetric_cofactors"),
          "friction": ("_force_response", "_joints", "swing_friction", "slide_friction", "_linearisation_error",
                       "_cofactors3"),
          "stages": ("derivative",)}
_HERE = Path(__file__).parent
#: Every source whose change must invalidate the compiled cache: the model,
#: the modules whose constants it reads at import, this module, the linking
#: machinery and the kernel.
SOURCES = tuple(Path(module.__file__) for module in (*MODEL_MODULES, outcome, parameters, switches)) + tuple(
    _HERE / name for name in ("compiled.py", "numba_linking.py", "marks.py", "dop853.py", "kernel_loads.py",
                              "kernel.py"))
#: The mechanisms that compile the model, the preferred first.
MECHANISMS = ("linked", "public")
#: The environment variable that chooses one: ``public``, ``linked``, or unset (``auto``: the
#: linked one where it fits the numba installed, else the public one).
MECHANISM_VARIABLE = "TREBUCHET_NUMBA"
#: What ends the name of each function the public mechanism compiles (and so its symbol in the
#: machine code and its files in the disk cache): the two mechanisms' caches never meet.
PUBLIC_LABEL = "_public"


# --------------------------------------------------------------------------- #
# The mechanism
# --------------------------------------------------------------------------- #

@functools.cache
def _linking():
    """``analytic.fast.numba_linking`` where it imports and fits the numba installed; else why not (a str)."""
    try:
        from analytic.fast import numba_linking
    except (ImportError, AttributeError) as error:
        return f"analytic.fast.numba_linking does not import: {type(error).__name__}: {error}"
    problem = numba_linking.problem()
    return numba_linking if problem is None else problem


def select(asked: str, linking) -> tuple[str, str]:
    """The mechanism for ``TREBUCHET_NUMBA=asked`` given ``linking`` (the module, or why it does not
    fit), and why: ``("linked" | "public", reason)``.

    Raises ``ValueError`` for a value that names no mechanism, and ``RuntimeError`` where
    ``linked`` is asked for and does not fit.
    """
    asked = asked.strip().lower()
    if asked not in ("", "auto", *MECHANISMS):
        raise ValueError(f"{MECHANISM_VARIABLE}={asked!r}: expected one of auto, {', '.join(MECHANISMS)}")
    fits = not isinstance(linking, str)
    if asked == "public":
        return "public", f"{MECHANISM_VARIABLE}=public"
    if fits:
        return "linked", f"numba {numba.__version__}'s internals fit analytic.fast.numba_linking"
    if asked == "linked":
        raise RuntimeError(f"{MECHANISM_VARIABLE}=linked, but {linking}")
    return "public", linking


@functools.cache
def _selected() -> tuple[str, str]:
    return select(os.environ.get(MECHANISM_VARIABLE, ""), _linking())


def mechanism() -> str:
    """``"linked"`` or ``"public"``: how this process compiles the model (chosen on first use, from
    ``TREBUCHET_NUMBA`` and whether ``analytic.fast.numba_linking`` fits the numba installed)."""
    return _selected()[0]


def mechanism_reason() -> str:
    """Why ``mechanism()`` is what it is: the variable that asked, or what of numba did not fit."""
    return _selected()[1]


def callee(function, inline: bool = False, **options):
    """``function`` compiled for compiled callers only, once per argument type (by the public
    mechanism, once per argument type and set of its callers' options), by ``mechanism()``:
    ``INTERNAL``'s options, then those its ``analytic.fast.marks.internal`` mark gives, then ``options``;
    ``inline``: LLVM inlines it into every caller (``INLINE``). Calling it from Python is a
    ``TypeError`` that says what to call instead."""
    options = {**INTERNAL, "forceinline": inline, **getattr(function, "compile_options", {}), **options}
    if mechanism() == "linked":
        return _linking().dispatcher(function, **options)
    return _public_callee(function, **options)


def entry(function):
    """``function`` compiled for Python callers, with its wrappers and disk cache (``CALLABLE``), by
    ``mechanism()``: with its whole call tree of ``callee`` functions in its machine code."""
    if mechanism() == "linked":
        return _linking().entry(function, **CALLABLE)
    return numba.njit(**CALLABLE)(function)


def _public_callee(function, **options):
    """``function`` for compiled callers through ``numba.extending.overload``, as ``register_jitable``
    registers one, but under a stand-in that Python cannot call by mistake.

    numba compiles it when a caller is typed (for the argument types without their constant
    values: an overload prefers them), with ``options``, once for each set of options its
    callers are compiled with. The stand-in's ``typed_for`` lists the argument types it was
    compiled for (``is_compiled``).

    A mark's ``inline="always"`` (numba's inlining at its IR level: ``kernel.shot``, so that
    the whole shot is optimised once, inside its entry point) is left out: an overload to be
    inlined is first compiled whole on its own, and its callees again after inlining, which
    lengthens the cold compile it is meant to shorten. LLVM still inlines what ``INLINE`` names.
    """
    options.pop("inline", None)

    def kernel_only(*args, **kwargs):
        raise TypeError(f"{function.__qualname__} is compiled for compiled callers only; "
                        "call analytic.fast.compiled's Python-callable twin instead")

    kernel_only.__name__, kernel_only.__qualname__ = function.__name__, function.__qualname__
    kernel_only.__doc__, kernel_only.py_func, kernel_only.typed_for = function.__doc__, function, []

    def implementation(*args, **kwargs):
        kernel_only.typed_for.append(args)
        return function

    overload(kernel_only, jit_options=options, strict=False)(implementation)
    return kernel_only


def is_compiled(function) -> bool:
    """Whether numba has compiled ``function`` (a twin of either mechanism) for some argument types."""
    return bool(getattr(function, "overloads", None) or getattr(function, "typed_for", None))


# --------------------------------------------------------------------------- #
# The twins
# --------------------------------------------------------------------------- #

def compile_modules(modules, compile_function, inline=None, callees=None,
                    constants=None) -> dict[str, types.ModuleType]:
    """numba twins of every function defined in ``modules``, by module short name.

    Each twin is a new function object on the original's code, with its own
    globals: a copy of its module's, in which every function of ``modules``
    is replaced by its compiled twin, or by its twin in ``callees`` (a result
    of this function) if given. numba reads those globals only when it
    compiles, so the order of definition does not matter.

    ``compile_function(function, inline)`` compiles one (a ``callee`` or an
    ``entry``; ``inline``: whether it is to be inlined into its callers); ``inline`` maps a short
    module name to the functions to inline. ``constants`` replaces those of
    the modules' globals it names (a scope's switches: ``analytic.scope``).

    Returns
    -------
    dict of short module name (``"eom"``) to a module object whose attributes
    are the compiled functions.
    """
    twins: dict[types.FunctionType, object] = {}
    namespaces = []
    for module in modules:
        namespace = dict(vars(module))
        namespace.update({name: value for name, value in (constants or {}).items() if name in namespace})
        short = module.__name__.rsplit(".", 1)[-1]
        for name, value in vars(module).items():
            if isinstance(value, types.FunctionType) and value.__module__ == module.__name__:
                twin = types.FunctionType(value.__code__, namespace, name, value.__defaults__, value.__closure__)
                twin.__qualname__, twin.__module__, twin.__doc__ = value.__qualname__, value.__module__, value.__doc__
                twin.__dict__.update(value.__dict__)   # (``internal``'s and ``entry``'s marks)
                twins[value] = compile_function(twin, name in (inline or {}).get(short, ()))
        namespaces.append((module, namespace))
    compiled = {}
    for module, namespace in namespaces:
        short = module.__name__.rsplit(".", 1)[-1]
        for name, value in namespace.items():
            if isinstance(value, types.FunctionType) and value in twins:
                namespace[name] = (getattr(callees[value.__module__.rsplit(".", 1)[-1]], value.__name__)
                                   if callees is not None else twins[value])
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


def cache_directory(dispatcher) -> Path | None:
    """Where numba keeps ``dispatcher``'s machine code (``__pycache__`` beside its source, or under
    ``NUMBA_CACHE_DIR``), from its public ``stats``; None where it caches nothing."""
    path = dispatcher.stats.cache_path
    return None if path is None else Path(path)


def stamp_name(mechanism: str) -> str:
    """The name of ``mechanism``'s stamp file beside the cached machine code."""
    return f"analytic-model-sources.{mechanism}.sha256"


def cache_mechanism(file_name: str) -> str:
    """The mechanism whose cache file ``file_name`` is (numba names one
    ``<module>.<qualified name>-<line>.py<version>...``): ``"public"`` where the function's
    name ends in ``PUBLIC_LABEL``, else ``"linked"`` (older files too)."""
    qualname = file_name.split(".", 1)[-1].rsplit("-", 1)[0]
    return "public" if qualname.endswith(PUBLIC_LABEL) else "linked"


def drop_stale_cache(directory: Path, paths, stamp_name: str = stamp_name("linked"),
                     mechanism: str | None = None) -> bool:
    """Delete numba's cached code of ``paths``' modules in ``directory`` (only ``mechanism``'s, if
    given: ``cache_mechanism``) unless the stamp ``stamp_name`` matches their fingerprint; then
    stamp it. Returns whether anything was dropped.

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
            if cached.name.split(".", 1)[0] in stems and mechanism in (None, cache_mechanism(cached.name)):
                cached.unlink(missing_ok=True)
        stamp.write_text(fingerprint)
    except OSError:
        return False
    return True


def _check_cache(dispatcher) -> None:
    """Drop this mechanism's stale cache (``drop_stale_cache``) where ``dispatcher`` keeps its machine
    code: once a process, before anything is loaded from it (an entry point loads on its first call)."""
    directory = cache_directory(dispatcher)
    if directory is not None:
        _drop_stale_once(directory, mechanism())


@functools.cache
def _drop_stale_once(directory: Path, mechanism: str) -> bool:
    return drop_stale_cache(directory, SOURCES, stamp_name(mechanism), mechanism)


def _label(function, suffix: str = "") -> None:
    """End ``function``'s name with ``suffix`` and, under the public mechanism, ``PUBLIC_LABEL``."""
    function.__qualname__ += suffix + (PUBLIC_LABEL if mechanism() == "public" else "")


def _scope_function(scope: Scope, label: bool = True):
    """``compile_modules``' ``compile_function`` for ``scope``: its entry point an ``entry``, every
    other function a ``callee`` with its ``internal`` options.

    With ``label``, each function's name ends in the scope's (``integrate_ideal``), and so
    does its symbol in the machine code. numba names a symbol by the function's module, name
    and a count of the functions its process has compiled, and assumes one definition per
    symbol. Two scopes' kernels, compiled in different processes and loaded into one, would
    otherwise hold different machine code under one symbol, and one kernel would call the
    other's copy (the ideal scope with its loads would run the loads-free scope's
    ``integrate``). The entry point's name also keys its disk cache (``shots_ideal``). The
    public mechanism's names end in ``PUBLIC_LABEL`` too, for the same reasons.
    """
    def compile_function(function, inline):
        _label(function, f"_{scope.name}" if label else "")
        if getattr(function, "entry_point", False):
            return entry(function)
        return callee(function, inline)
    return compile_function


_scopes: dict[str, dict[str, types.ModuleType]] = {}
#: Held while a scope's or the callable twins' modules are built: threads that first shoot at once
#: (a server's requests) share one build, as they must (two builds' twins, with the same names,
#: would each drop and load the same cache files).
_BUILDING = threading.RLock()


def kernel_scope(scope: Scope) -> dict[str, types.ModuleType]:
    """The model and the kernel (``analytic.fast.dop853``, ``kernel_loads``, ``kernel``) compiled in
    ``scope``, by module short name: ``kernel_scope(scope)["kernel"].shots`` is its entry point.

    Each scope has its own twins, built on first use (compiled when first called, or loaded
    from the disk cache, whose stale files are dropped first); the model's globals hold the
    scope's switches, so numba prunes what the scope leaves out before it types anything
    (``analytic.scope``).
    """
    with _BUILDING:
        if scope.name not in _scopes:
            modules = compile_modules((*MODEL_MODULES, dop853, kernel_loads, kernel), _scope_function(scope), INLINE,
                                      constants=scope.globals())
            _check_cache(modules["kernel"].shots)
            _scopes[scope.name] = modules
        return _scopes[scope.name]


def _model_twins() -> tuple[dict[str, types.ModuleType], dict[str, types.ModuleType]]:
    """``(kernel_twins, callable_twins)``, built on first use."""
    with _BUILDING:
        return _built_model_twins()


@functools.cache
def _built_model_twins() -> tuple[dict[str, types.ModuleType], dict[str, types.ModuleType]]:
    kernel_twins = compile_modules(MODEL_MODULES, _scope_function(EVERYTHING, label=False), INLINE,
                                   constants=EVERYTHING.globals())

    def callable_twin(function, inline):
        _label(function)
        return entry(function)

    callable_twins = compile_modules(MODEL_MODULES, callable_twin, callees=kernel_twins)
    _check_cache(callable_twins["eom"].terms)
    return kernel_twins, callable_twins


#: The lazy attributes (``__getattr__``), each by what it is in ``_model_twins()``: ``kernel_twins``,
#: the model compiled as the kernel calls it in the scope that handles everything, by module short
#: name (the callees of ``callable_twins``; ``kernel_scope`` builds each scope's own);
#: ``callable_twins``, the model compiled for Python callers (tests, the benchmark), each function
#: with its wrappers and disk cache; and one module of them each, named with a trailing underscore
#: (``eom_``: not the Python module of that name).
_LAZY = {"kernel_twins": (0, None), "callable_twins": (1, None),
         **{f"{module.__name__.rsplit('.', 1)[-1]}_": (1, module.__name__.rsplit(".", 1)[-1])
            for module in MODEL_MODULES}}


def __getattr__(name: str):
    """``kernel_twins``, ``callable_twins`` and ``eom_`` etc., built on first use (PEP 562)."""
    if name not in _LAZY:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    which, module = _LAZY[name]
    twins = _model_twins()[which]
    return twins if module is None else twins[module]
