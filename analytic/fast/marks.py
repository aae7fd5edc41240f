"""How the kernel's functions are compiled: marks that ``analytic.fast.compiled`` reads.

The kernel's modules (``analytic.fast.dop853``, ``kernel_loads``, ``kernel``) are plain
Python; ``analytic.fast.compiled.kernel_scope`` compiles them in each scope
(``analytic.scope``), reading these marks for each function's options. This module
imports nothing, so the kernel's modules and ``analytic.fast.compiled`` need not import
each other.
"""

from __future__ import annotations


def internal(function=None, *, allocates=False, **options):
    """Decorator: mark ``function`` to be compiled as an ``Internal`` dispatcher (``compiled.INTERNAL``'s
    options plus ``options``) in every scope (``analytic.fast.compiled.kernel_scope``); it stays a
    Python function.

    ``allocates``: the function creates or returns arrays, so it keeps numba's
    reference counting (the others do without it: ``compiled.INTERNAL``).
    """
    if allocates:
        options = {"_nrt": True, **options}

    def wrap(f):
        f.compile_options = options
        return f
    return wrap if function is None else wrap(function)


def entry(function):
    """Decorator: mark ``function`` as a scope's compiled entry point (``CALLABLE``: Python calls it,
    and its machine code, with all it calls, is cached on disk); it stays a Python function."""
    function.entry_point = True
    return function
