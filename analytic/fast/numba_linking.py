"""The linked mechanism: the compiled model built on numba's internals, each function linked once.

numba's public API (``analytic.fast.compiled``'s public mechanism) compiles every
function called from compiled code as an entry point of its own: it links
the function's whole call tree into it, optimises that module and emits it
as machine code, at every level of the tree, although only the scope's entry
point (``kernel.shots``) is ever run; and it compiles a function again for
each caller whose flags differ. This module does the same job with numba's
internals, for a shorter cold compile and the same machine code:

* ``Internal``, a dispatcher compiled once per argument *type* (numba makes
  one copy per constant a caller passes), with no wrapper for Python;
* ``LinkOnlyLibrary``, the machine-code library of such a function: its own
  function, optimised on its own, never finalised alone;
* ``EntryLibrary``, an entry point's library, which links every library of its
  call tree once and optimises and emits the whole tree once.

It touches names numba does not promise to keep (``_FunctionCompiler`` and
its ``_compile_core``, ``JITCodeLibrary``'s private attributes and methods,
a dispatcher's ``_compiler``), and overrides ``_compile_core`` with a copy of
numba 0.68's body. So it is used only where ``problem()`` finds every one of
those names, with the signatures and bodies it was written against; where
any is missing or changed, or this module does not even import,
``analytic.fast.compiled`` compiles the same model with the public API instead
(the same numbers, a longer cold compile). Nothing here runs at import but
the imports.
"""

from __future__ import annotations

import hashlib
import inspect
import textwrap

import numba
from numba.core import compiler as nbcompiler
from numba.core import types as nbtypes
from numba.core.codegen import CPUCodeLibrary, JITCodeLibrary
from numba.core.dispatcher import Dispatcher, _FunctionCompiler
from numba.core.registry import CPUDispatcher

#: The numba release this module was written against and tested with.
TESTED_NUMBA = "0.68"
#: numba's private attributes and methods a ``LinkOnlyLibrary`` relies on.
LIBRARY_INTERNALS = ("_linking_libraries", "_final_module", "_reload_init", "_codegen", "_shared_module",
                     "_get_module_for_linking", "_raise_if_finalized", "_finalized", "enable_object_caching")
#: numba's functions whose parameters this module calls or overrides with, by what it expects.
SIGNATURES = {
    "_FunctionCompiler.__init__": (_FunctionCompiler.__init__,
                                   ("self", "py_func", "targetdescr", "targetoptions", "locals", "pipeline_class")),
    "_FunctionCompiler._compile_core": (_FunctionCompiler._compile_core, ("self", "args", "return_type")),
    "_FunctionCompiler._customize_flags": (_FunctionCompiler._customize_flags, ("self", "flags")),
    "_FunctionCompiler._get_implementation": (_FunctionCompiler._get_implementation, ("self", "args", "kws")),
    "Dispatcher.__init__": (Dispatcher.__init__, ("self", "py_func", "locals", "targetoptions", "pipeline_class")),
    "Dispatcher.get_call_template": (Dispatcher.get_call_template, ("self", "args", "kws")),
    "JITCodeLibrary.__init__": (JITCodeLibrary.__init__, ("self", "codegen", "name")),
    "compile_extra": (nbcompiler.compile_extra, ("typingctx", "targetctx", "func", "args", "return_type", "flags",
                                                 "locals", "library", "pipeline_class")),
}
#: numba's method bodies this module replaces (``_LibraryCompiler._compile_core`` is a copy of the
#: first; ``LinkOnlyLibrary.finalize`` does only the part of the second a library linked elsewhere
#: needs), by the SHA-256 of their source in numba 0.68: a changed body may do something the
#: copy does not, so it is a misfit however small the change.
BODIES = {
    "_FunctionCompiler._compile_core": (_FunctionCompiler._compile_core, "570bc4ef0be9565c"),
    "CPUCodeLibrary.finalize": (CPUCodeLibrary.finalize, "751235266d09e807"),
}


def problem() -> str | None:
    """Why this module does not fit the numba installed, or None where it fits.

    Checks, without compiling anything, every private name the module touches: the
    parameters of the functions it calls or overrides (``SIGNATURES``), the bodies it
    copies or replaces (``BODIES``) and the attributes of a library (``LIBRARY_INTERNALS``).
    """
    try:
        for name, (function, expected) in SIGNATURES.items():
            found = tuple(inspect.signature(function).parameters)
            if found != expected:
                return f"numba {numba.__version__}'s {name} takes {found}, not {expected}"
        for name, (function, digest) in BODIES.items():
            source = textwrap.dedent(inspect.getsource(function))
            if hashlib.sha256(source.encode()).hexdigest()[:16] != digest:
                return f"numba {numba.__version__}'s {name} is not numba {TESTED_NUMBA}'s"
        from numba.core.registry import cpu_target
        codegen = cpu_target.target_context.codegen()
        library = LinkOnlyLibrary(codegen, "probe")
        missing = [name for name in LIBRARY_INTERNALS if not hasattr(library, name)]
        if not hasattr(codegen, "set_env"):
            missing.append("set_env (of the codegen)")
        if missing:
            return f"numba {numba.__version__}'s code library has no {', '.join(missing)}"
        plain = numba.njit(lambda: None)._compiler   # (a dispatcher compiles nothing until called)
        missing = [name for name in ("pipeline_class", "targetdescr", "targetoptions", "locals")
                   if not hasattr(plain, name)]
        if missing:
            return f"numba {numba.__version__}'s dispatcher's compiler has no {', '.join(missing)}"
    except Exception as error:   # (any failure of the probe is a misfit: the public mechanism serves)
        return f"probing numba {numba.__version__} failed: {type(error).__name__}: {error}"
    return None


class LinkOnlyLibrary(JITCodeLibrary):
    """The machine code library of a function only compiled code calls: linked into its callers, never run alone.

    numba finalises every function's library as if it were an entry point:
    it links in the whole call tree below it, optimises that module again and
    emits it as machine code. Along a chain of callees that repeats the same
    work at every level, and the machine code is never run: only the entry
    point's (``kernel.shots``) is. This library holds its own function,
    optimised on its own as it is added (numba's per-function passes); an
    ``EntryLibrary`` links every library of its call tree once and optimises
    and emits the whole tree once. Each library is linked once, at the entry
    point, rather than a callee's whole tree into every caller along the way:
    LLVM's linking and cloning of the same modules again at every level was
    most of that step's time.

    A caller numba compiles on its own (a plain ``numba.njit`` function) links
    ``_get_module_for_linking``: this function with its whole call tree.

    numba gives each compiled function an environment and points a global of
    the machine code at it (``set_env``); nothing reads a callee's at run time
    (a kernel loaded from the disk cache never sets its callees' either), so
    this library's codegen leaves it alone and no global of it is emitted.
    """

    def __init__(self, codegen, name):
        super().__init__(codegen, name)
        self._tree_module = None
        self._codegen_without_env = _CodegenWithoutEnv(codegen)

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


class _LibraryCompiler(_FunctionCompiler):
    """numba's function compiler, giving each compiled function a library of the class ``library_class``."""

    def __init__(self, py_func, targetdescr, targetoptions, locals, pipeline_class, library_class):
        super().__init__(py_func, targetdescr, targetoptions, locals, pipeline_class)
        self.library_class = library_class

    def _compile_core(self, args, return_type):
        # numba 0.68's body (``BODIES``), with the library given to ``compile_extra``.
        flags = nbcompiler.Flags()
        self.targetdescr.options.parse_as_flags(flags, self.targetoptions)
        flags = self._customize_flags(flags)
        context = self.targetdescr.target_context
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
    copy each (the copies cost a quarter of a cold compile; sharing them
    costs the shots nothing measurable). It has no wrapper for Python:
    calling it from Python is an error (``analytic.fast.compiled``'s Python-callable
    twins are for that).
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


#: Options of an ``Internal`` function besides those ``analytic.fast.compiled`` gives every callee:
#: no wrappers to and from Python objects (nothing but compiled code calls it; a wrapper
#: unboxing the 31-number ``Params`` for each of some 80 functions lengthened a cold compile
#: by half).
WITHOUT_WRAPPERS = dict(no_cpython_wrapper=True, no_cfunc_wrapper=True)


def dispatcher(function, **options) -> Internal:
    """``function`` as an ``Internal`` dispatcher with ``options`` (``WITHOUT_WRAPPERS`` added)."""
    return Internal(py_func=function, locals={}, targetoptions={**options, **WITHOUT_WRAPPERS})


def entry(function, **options):
    """``function`` as a dispatcher Python calls (``numba.njit(**options)``), whose machine code
    links its call tree of ``Internal`` functions once (``EntryLibrary``)."""
    compiled = numba.njit(**options)(function)
    compiled._compiler = _LibraryCompiler(function, compiled.targetdescr, compiled.targetoptions, compiled.locals,
                                          compiled._compiler.pipeline_class, EntryLibrary)
    return compiled
