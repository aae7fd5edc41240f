"""The model compiled with numba: how the fast path runs the very source the reference path runs.

The model (``analytic.geometry``, ``limits``, ``peaks``, ``aero``, ``eom``,
``friction``, ``stages``, ``sequence``) is plain Python on floats and tuples,
which the reference path runs as it is. This module gives the compiled path
the same functions, compiled (``compile_modules``): for each model module a
namespace whose functions are numba dispatchers of the very same code
objects, with their calls to each other rebound to the compiled versions.
``kernel_scope(scope)`` compiles the model and the kernel for compiled callers
only (``Internal`` dispatchers, compiled once per argument type and emitted as
machine code only inside the scope's one cached entry point, its
``kernel.shots``), with the scope's switches in the model's globals
(``analytic.scope``: what a smaller copy leaves out is pruned before it is
typed); ``kernel_twins`` are the whole model's, for ``callable_twins``
(``compiled.eom_``, ``compiled.stages_``, ...) are for Python callers (the
tests compare them with the Python functions). numba's public
``register_jitable`` does the same job with less machinery, and was measured
against this (the same model, paired cold compiles): shots as fast and
bit-identical, but a cold compile 1.37x as long (30.8 against 22.5 s of CPU,
median of three pairs), because each registered function is compiled and
emitted as an entry point of its own; so the model is compiled here. Importing
this module imports numba; ``import analytic`` and the reference path never
do. Only each scope's ``kernel.shots`` is cached on disk; a cold compile takes
tens of seconds of CPU (``python -m benchmarks --cold`` measures each scope's).

numba caches machine code on disk keyed on each function's own source file,
not on the files it calls into: after an edit to ``eom.py`` the cached
``kernel.shots`` would still hold the old equations. So the cache is stamped
with a fingerprint of every source the compiled code depends on
(``SOURCES``), and a cache whose stamp differs is dropped before anything is
loaded from it.
"""

from __future__ import annotations

import functools
import hashlib
import types
from pathlib import Path

import numba
from numba.core import compiler as nbcompiler
from numba.core import types as nbtypes
from numba.core.codegen import JITCodeLibrary
from numba.core.dispatcher import _FunctionCompiler
from numba.core.registry import CPUDispatcher

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
#: the model's functions as the kernel calls them): no wrappers to and from
#: Python objects, and no disk cache of their own. The kernel's one entry
#: point (``kernel.shots``) holds all their machine code and is cached;
#: a wrapper unboxing the 31-number ``Params`` and a cache file for each of
#: some 80 functions made a cold compile take 1.5x as long (measured).
#:
#: ``_nrt=False``: no reference counting of the arrays they are handed. numba
#: counts a reference to every array argument a function keeps in a variable,
#: and to every view (``K[s]``), with an atomic add and subtract per call that
#: LLVM cannot prove away; in the right-hand side's callers that would be a
#: quarter of a shot's time (perf: ``NRT_incref``/``NRT_decref`` 26 % of the
#: samples of a batch with them). These functions allocate nothing and return
#: no array, and their callers hold every array they are given for the whole
#: call, so the counts are not needed. A function that allocates is declared with
#: ``analytic.fast.marks.internal(allocates=True)`` and counts as usual; numba refuses to compile
#: an allocation in one that is not.
INTERNAL = dict(OPTIONS, no_cpython_wrapper=True, no_cfunc_wrapper=True, _nrt=False)
#: Options of a function Python calls: with its wrappers, and cached.
CALLABLE = dict(OPTIONS, cache=True)
#: Functions LLVM inlines into every caller (numba's ``forceinline``: LLVM's
#: ``alwaysinline``): the right-hand side and the equations it calls on every
#: evaluation. Measured on the benchmark's designs: without it, a batch of
#: shots takes about 1.2x as long. With friction, the joint forces are taken
#: three times per evaluation at the same angles; inlined, LLVM computes
#: their sines and cosines once (a batch with friction 1.26-1.35x as fast,
#: the same bits, the same cold compile). The sites a shot passes only a few
#: times call ``dop853.derivative_call`` instead: one copy of the model for
#: them all (a shorter compile). numba's own inlining (``inline="always"``,
#: at its IR level) gives shots a few per cent faster but copies and re-types
#: each callee at every call site: it made a cold compile 1.2x-1.6x as long.
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
#: the modules whose constants it reads at import, this module and the kernel.
SOURCES = tuple(Path(module.__file__) for module in (*MODEL_MODULES, outcome, parameters, switches)) + tuple(
    _HERE / name for name in ("compiled.py", "marks.py", "dop853.py", "kernel_loads.py", "kernel.py"))
#: Name of the stamp file beside the cached machine code.
STAMP_NAME = "analytic-model-sources.sha256"


class LinkOnlyLibrary(JITCodeLibrary):
    """The machine code library of a function only compiled code calls: linked into its callers, never run alone.

    numba finalises every function's library as if it were an entry point:
    it links in the whole call tree below it, optimises that module again and
    emits it as machine code. Along a chain of callees that repeats the same
    work at every level, and the machine code is never run: only the entry
    point's (``kernel.shots``) is. This library holds its own function,
    optimised on its own as it is added (numba's per-function passes); an
    ``EntryLibrary`` links every library of its call tree once and optimises
    and emits the whole tree once. Measured (three cold compiles each,
    interleaved): 26 s of CPU instead of 35 s, and the shots as fast. Each
    library is linked once, at the entry point: linking a callee's whole tree
    into every caller along the way costs a cold compile of the ``everything``
    scope about a second of LLVM's linking and cloning (measured: 1.0 s
    against 0.1 s).

    A caller numba compiles on its own (a plain ``numba.njit`` function) links
    ``_get_module_for_linking``: this function with its whole call tree.

    numba gives each compiled function an environment and points a global of
    the machine code at it (``set_env``); nothing reads a callee's at run time
    (a kernel loaded from the disk cache never sets its callees' either), so
    this library's codegen leaves it alone and no global of it is emitted.
    """

    #: numba's internals (0.68) this library relies on, checked before it is used.
    NUMBA_INTERNALS = ("_linking_libraries", "_final_module", "_reload_init", "_codegen", "_shared_module",
                       "_get_module_for_linking", "_raise_if_finalized", "_finalized")

    def __init__(self, codegen, name):
        super().__init__(codegen, name)
        self._tree_module = None
        self._codegen_without_env = _CodegenWithoutEnv(codegen)

    def fits_this_numba(self) -> bool:
        return all(hasattr(self, name) for name in self.NUMBA_INTERNALS) and hasattr(self._codegen, "set_env")

    @property
    def codegen(self):
        return self._codegen_without_env

    def finalize(self):
        self._raise_if_finalized()
        for library in self._linking_libraries:
            self._reload_init.update(library._reload_init)
        self._finalized = True

    def own_module(self):
        """This library's own functions, fit for linking (exported ones made ``linkonce_odr``)."""
        return super()._get_module_for_linking()

    def _get_module_for_linking(self):
        if self._tree_module is None:
            self._tree_module = self.own_module().clone()
            for library in call_tree(self._linking_libraries):
                self._tree_module.link_in(module_for_linking(library), preserve=True)
        return self._tree_module


class _CodegenWithoutEnv:
    """A codegen whose ``set_env`` keeps nothing (``LinkOnlyLibrary``): everything else is the codegen's."""

    def __init__(self, codegen):
        self._wrapped = codegen

    def __getattr__(self, name):
        return getattr(self._wrapped, name)

    def set_env(self, env_name, env):
        pass


def call_tree(libraries) -> list:
    """``libraries`` and every library a ``LinkOnlyLibrary`` among them links, each once, callers first."""
    tree, seen, pending = [], set(), list(reversed(libraries))
    while pending:
        library = pending.pop()
        if library in seen:
            continue
        seen.add(library)
        tree.append(library)
        if isinstance(library, LinkOnlyLibrary):
            pending.extend(reversed(library._linking_libraries))
    return tree


def module_for_linking(library):
    """What a caller links of ``library``: a ``LinkOnlyLibrary``'s own functions (the caller links the
    rest of its tree), any other library's module with its tree."""
    return library.own_module() if isinstance(library, LinkOnlyLibrary) else library._get_module_for_linking()


class EntryLibrary(JITCodeLibrary):
    """The machine code library of an entry point: its whole call tree linked once, then numba's finalising
    (the optimisation and machine code of the whole module)."""

    def finalize(self):
        self._raise_if_finalized()
        for library in call_tree(self._linking_libraries):
            self._reload_init.update(library._reload_init)
            self._final_module.link_in(module_for_linking(library), preserve=True)
        self._linking_libraries = []   # (linked above)
        super().finalize()


@functools.cache
def _fits_this_numba() -> bool:
    """Whether the numba installed has the internals ``LinkOnlyLibrary`` relies on."""
    from numba.core.registry import cpu_target
    return LinkOnlyLibrary(cpu_target.target_context.codegen(), "probe").fits_this_numba()


class _LibraryCompiler(_FunctionCompiler):
    """numba's function compiler, giving each compiled function a library of the class ``library_class``."""

    def __init__(self, py_func, targetdescr, targetoptions, locals, pipeline_class, library_class):
        super().__init__(py_func, targetdescr, targetoptions, locals, pipeline_class)
        self.library_class = library_class

    def _compile_core(self, args, return_type):
        flags = nbcompiler.Flags()
        self.targetdescr.options.parse_as_flags(flags, self.targetoptions)
        flags = self._customize_flags(flags)
        context = self.targetdescr.target_context
        library = None   # numba's own library: a slower cold compile, the same machine code
        if _fits_this_numba():
            library = self.library_class(context.codegen(), self.py_func.__qualname__)
            library.enable_object_caching()   # (numba makes its own so, for the disk cache)
        return nbcompiler.compile_extra(self.targetdescr.typing_context, context, self._get_implementation(args, {}),
                                        args=args, return_type=return_type, flags=flags, locals=self.locals,
                                        library=library, pipeline_class=self.pipeline_class)


class Internal(CPUDispatcher):
    """A function compiled for other compiled code only: once per argument *type*.

    numba otherwise compiles a function again for every constant value a
    caller passes (a stage, a joint's index, a flag), as if asked to
    specialise on it; the kernel's stages and the model's joints share one
    copy each (measured: the copies cost a quarter of a cold compile, and
    sharing them costs the shots nothing measurable). It has no wrapper for
    Python: calling it from Python is an error (``callable_twins`` gives
    functions Python can call).
    """

    def __init__(self, py_func, locals=None, targetoptions=None, pipeline_class=nbcompiler.Compiler):
        super().__init__(py_func, locals=locals, targetoptions=targetoptions, pipeline_class=pipeline_class)
        self._compiler = _LibraryCompiler(py_func, self.targetdescr, self.targetoptions, self.locals, pipeline_class,
                                          LinkOnlyLibrary)

    def get_call_template(self, args, kws):
        return super().get_call_template(tuple(nbtypes.unliteral(a) for a in args),
                                         {k: nbtypes.unliteral(v) for k, v in kws.items()})

    def __call__(self, *args, **kwargs):
        raise TypeError(f"{self.py_func.__qualname__} is compiled for compiled callers only; "
                        "call analytic.fast.compiled's Python-callable twin instead")


def dispatcher(function, **options) -> Internal:
    """``function`` as an ``Internal`` dispatcher: ``INTERNAL``'s options, then those its
    ``analytic.fast.marks.internal`` mark gives, then ``options``."""
    return Internal(py_func=function, locals={},
                    targetoptions={**INTERNAL, **getattr(function, "compile_options", {}), **options})


def entry(function):
    """``function`` as a dispatcher Python calls, with its wrappers and disk cache (``CALLABLE``), whose
    machine code links its call tree of ``Internal`` functions once (``EntryLibrary``)."""
    compiled = numba.njit(**CALLABLE)(function)
    compiled._compiler = _LibraryCompiler(function, compiled.targetdescr, compiled.targetoptions, compiled.locals,
                                          compiled._compiler.pipeline_class, EntryLibrary)
    return compiled


def compile_modules(modules, compile_function, inline=None, callees=None,
                    constants=None) -> dict[str, types.ModuleType]:
    """numba twins of every function defined in ``modules``, by module short name.

    Each twin is a new function object on the original's code, with its own
    globals: a copy of its module's, in which every function of ``modules``
    is replaced by its compiled twin, or by its twin in ``callees`` (a result
    of this function) if given. numba reads those globals only when it
    compiles, so the order of definition does not matter.

    ``compile_function(function, inline)`` makes a dispatcher (``inline``:
    whether it is to be inlined into its callers); ``inline`` maps a short
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


def _scope_function(scope: Scope, label: bool = True):
    """``compile_modules``' ``compile_function`` for ``scope``: its entry point as a cached
    ``CALLABLE``, every other function an ``Internal`` dispatcher with its ``internal`` options.

    With ``label``, each function's name ends in the scope's (``integrate_ideal``), and so
    does its symbol in the machine code. numba names a symbol by the function's module, name
    and a count of the functions its process has compiled, and assumes one definition per
    symbol. Two scopes' kernels, compiled in different processes and loaded into one, would
    otherwise hold different machine code under one symbol, and one kernel would call the
    other's copy (the ideal scope with its loads would run the loads-free scope's
    ``integrate``). The entry point's name also keys its disk cache (``shots_ideal``).
    """
    def compile_function(function, inline):
        if label:
            function.__qualname__ = f"{function.__qualname__}_{scope.name}"
        if getattr(function, "entry_point", False):
            return entry(function)
        return dispatcher(function, forceinline=inline)
    return compile_function


_scopes: dict[str, dict[str, types.ModuleType]] = {}


def kernel_scope(scope: Scope) -> dict[str, types.ModuleType]:
    """The model and the kernel (``analytic.fast.dop853``, ``kernel_loads``, ``kernel``) compiled in
    ``scope``, by module short name: ``kernel_scope(scope)["kernel"].shots`` is its entry point.

    Each scope has its own dispatchers, built on first use (compiled when first called, or
    loaded from the disk cache); the model's globals hold the scope's switches, so numba
    prunes what the scope leaves out before it types anything (``analytic.scope``).
    """
    if scope.name not in _scopes:
        _scopes[scope.name] = compile_modules((*MODEL_MODULES, dop853, kernel_loads, kernel), _scope_function(scope),
                                              INLINE, constants=scope.globals())
    return _scopes[scope.name]


#: The model compiled as the kernel calls it, in the scope that handles everything
#: (``Internal`` dispatchers), by module short name: the callees of ``callable_twins``.
#: (``kernel_scope`` builds each scope's own.)
kernel_twins = compile_modules(MODEL_MODULES, _scope_function(EVERYTHING, label=False), INLINE,
                               constants=EVERYTHING.globals())
#: The model compiled for Python callers (tests, the benchmark): each function
#: with its wrappers and disk cache, calling the kernel's twins.
callable_twins = compile_modules(MODEL_MODULES, lambda f, inline: entry(f),
                                 callees=kernel_twins)
geometry_ = callable_twins["geometry"]   # trailing underscore: not the Python module of that name
limits_ = callable_twins["limits"]
aero_ = callable_twins["aero"]
floating_arm_ = callable_twins["floating_arm"]
eom_ = callable_twins["eom"]
friction_ = callable_twins["friction"]
states_ = callable_twins["states"]
stages_ = callable_twins["stages"]
sequence_ = callable_twins["sequence"]
peaks_ = callable_twins["peaks"]
drop_stale_cache(cache_directory(eom_.terms), SOURCES)
