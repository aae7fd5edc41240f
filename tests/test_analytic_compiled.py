"""The compiled model (``analytic.fast.compiled``): its disk cache follows every source it was built from,
and the linked mechanism's machinery (``analytic.fast.numba_linking``) does what it is for.

numba keys its cache on each function's own file: a kernel that calls into
another file keeps the old machine code after that file changes. These tests
build a miniature model the way ``analytic.fast.compiled`` builds the real one, in
fresh processes (as a user's next command would), and edit the callee. The
tests of the linking machinery run whichever mechanism the process uses
(``TREBUCHET_NUMBA``), wherever the machinery fits the numba installed.
"""

from __future__ import annotations

import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from analytic import default_design
from analytic.fast import compiled
from analytic.parameters import params

_PARAMS = params(default_design())

_MODEL = {
    "geo.py": "def lever(x, p):\n    return {factor} * p[0] * x\n",
    "eqs.py": "from toy.geo import lever\n\ndef force(x, p):\n    return lever(x, p) + p[1]\n",
    "kernel.py": textwrap.dedent("""\
        import numba
        from analytic.fast.compiled import CALLABLE, cache_directory, callee, compile_modules, drop_stale_cache
        from toy import eqs, geo
        modules = compile_modules((geo, eqs), lambda function, inline: callee(function))
        force = modules["eqs"].force

        @numba.njit(**CALLABLE)
        def total(n, p):
            s = 0.0
            for i in range(n):
                s += force(float(i), p)
            return s

        if {stamped}:
            drop_stale_cache(cache_directory(total), [geo.__file__, eqs.__file__, __file__])
        """),
}


def _write_model(root: Path, factor: float, stamped: bool) -> None:
    package = root / "toy"
    package.mkdir(exist_ok=True)
    (package / "__init__.py").write_text("")
    for name, text in _MODEL.items():
        (package / name).write_text(text.format(factor=factor, stamped=stamped))


def _run(root: Path) -> tuple[float, int]:
    """``total(4, (1.0, 0.5))`` and the kernel's cache hits, in a fresh process."""
    code = ("from toy import kernel; v = kernel.total(4, (1.0, 0.5)); "
            "print(v, sum(kernel.total.stats.cache_hits.values()))")
    mechanism = {compiled.MECHANISM_VARIABLE: compiled.mechanism()}   # (this process's, in the child too)
    done = subprocess.run([sys.executable, "-c", code], cwd=root, check=True, capture_output=True, text=True,
                          env={"PYTHONPATH": f"{root}:{Path(compiled.__file__).parents[1]}", "PATH": "", **mechanism})
    value, hits = done.stdout.split()
    return float(value), int(hits)


@pytest.mark.parametrize("stamped", [True, False], ids=["stamped", "unstamped"])
def test_editing_a_callee_file_reaches_the_cached_kernel_only_with_the_stamp(tmp_path, stamped):
    _write_model(tmp_path, factor=2.0, stamped=stamped)
    assert _run(tmp_path) == (2.0 * (0 + 1 + 2 + 3) + 4 * 0.5, 0)   # compiled and cached
    assert _run(tmp_path) == (14.0, 1)                               # loaded from the cache
    _write_model(tmp_path, factor=3.0, stamped=stamped)              # edit geo.py only
    value, _ = _run(tmp_path)
    if stamped:
        assert value == 3.0 * 6 + 2.0     # the edit reached the kernel
    else:
        assert value == 14.0              # numba alone keeps the stale machine code


def test_the_real_model_is_stamped_with_its_sources():
    directory = compiled.cache_directory(compiled.eom_.terms)
    stamp = (directory / compiled.stamp_name(compiled.mechanism())).read_text()
    assert stamp == compiled.source_fingerprint(compiled.SOURCES)
    names = {path.name for path in compiled.SOURCES}
    assert {"eom.py", "stages.py", "aero.py", "geometry.py", "limits.py", "kernel.py", "numba_linking.py"} <= names


def test_each_mechanism_drops_only_its_own_stale_cache(tmp_path):
    # Both mechanisms cache in the same directory (numba's, beside the sources), under their own
    # names and stamps: a stale stamp of one drops its files and leaves the other's.
    sources = [Path(compiled.__file__), Path(compiled.__file__).with_name("kernel.py")]
    names = {"linked": "kernel.shots_ideal-419.py311.nbi", "public": "kernel.shots_ideal_public-419.py311.1.nbc",
             "older": "compiled.terms-12.py311.nbi", "another module's": "toy.total-3.py311.nbi"}
    for name in names.values():
        (tmp_path / name).write_text("")
    assert [compiled.cache_mechanism(name) for name in names.values()] == ["linked", "public", "linked", "linked"]
    assert compiled.drop_stale_cache(tmp_path, sources, compiled.stamp_name("public"), "public")
    assert sorted(path.name for path in tmp_path.glob("*.nb?")) == sorted(
        [names["linked"], names["older"], names["another module's"]])
    assert compiled.drop_stale_cache(tmp_path, sources, compiled.stamp_name("linked"), "linked")
    assert [path.name for path in tmp_path.glob("*.nb?")] == [names["another module's"]]
    assert not compiled.drop_stale_cache(tmp_path, sources, compiled.stamp_name("public"), "public")   # stamped
    assert {path.name for path in tmp_path.glob("*.sha256")} == {compiled.stamp_name(m) for m in compiled.MECHANISMS}


def test_every_analytic_module_the_model_imports_is_a_source_of_the_stamp():
    """A constant the compiled code reads from another module freezes into the machine code."""
    import ast

    sources = {path.stem for path in compiled.SOURCES}
    compiled_code = [Path(module.__file__) for module in compiled.MODEL_MODULES] + [
        Path(compiled.__file__).with_name(name) for name in ("dop853.py", "kernel_loads.py", "kernel.py")]
    for path in compiled_code:
        tree = ast.parse(path.read_text())
        for node in ast.walk(tree):
            if isinstance(node, ast.ImportFrom) and node.module and node.module.startswith("analytic."):
                assert node.module.split(".")[-1] in sources, f"{path.name} imports {node.module}"


def test_an_internal_function_is_compiled_once_per_type_not_per_constant():
    """Constants passed to it (a stage, a joint) share one copy: numba alone makes one per value."""
    import numba

    def scaled(k, x):
        return x * (k + 1)

    shared, plain = compiled.callee(scaled), numba.njit(scaled)

    def caller(f):
        @numba.njit
        def run(x):
            return f(0, x) + f(1, x) + f(2, x)
        return run

    assert caller(shared)(1.0) == caller(plain)(1.0) == 6.0
    copies = shared.overloads if compiled.mechanism() == "linked" else shared.typed_for
    assert len(copies) == 1
    assert len(plain.overloads) == 3     # numba's own behaviour, which the kernel avoids


def test_a_kernel_only_function_called_from_python_says_what_to_call():
    from analytic import eom

    with pytest.raises(TypeError, match="compiled callers only"):
        compiled.kernel_twins["eom"].terms(0.1, 0.2, 0.3, 0.0, 0.0, 0.0, _PARAMS)
    assert compiled.eom_.terms(0.1, 0.2, 0.3, 0.0, 0.0, 0.0, _PARAMS) == eom.terms(0.1, 0.2, 0.3, 0.0, 0.0, 0.0,
                                                                                   _PARAMS)


def _linking():
    """``analytic.fast.numba_linking``, where it fits the numba installed (its tests are skipped elsewhere:
    ``test_analytic_numba_mechanisms`` fails on a numba this project has not tested)."""
    linking = compiled._linking()
    if isinstance(linking, str):
        pytest.skip(f"the linking machinery does not fit: {linking}")
    return linking


def _internal(function):
    return _linking().dispatcher(function, **compiled.INTERNAL)


def test_internal_functions_are_emitted_as_machine_code_only_inside_their_entry_point(monkeypatch):
    """numba alone optimises and emits every callee's library as if it were an entry point,
    the whole call tree below it again at each level; an ``Internal`` one is only linked."""
    import numba
    from numba.core.codegen import JITCodeLibrary

    emitted = []
    emit = JITCodeLibrary._finalize_specific

    def recording(library):
        emitted.append(library.name)
        return emit(library)

    monkeypatch.setattr(JITCodeLibrary, "_finalize_specific", recording)

    def chain(make):
        def inner_step(x):
            return 2.0 * x + 1.0

        def outer_step(x):
            return inner(x) * inner(x + 1.0)

        inner, outer = make(inner_step), make(outer_step)

        @numba.njit
        def entry_point(x):
            return outer(x) - 1.0
        return entry_point

    assert chain(_internal)(1.0) == chain(numba.njit)(1.0) == 3.0 * 5.0 - 1.0
    names = [name.rsplit(".", 1)[-1] for name in emitted]
    assert names.count("entry_point") == 2          # one per chain
    assert names.count("inner_step") == names.count("outer_step") == 1   # the plain numba chain's only


def test_an_entry_point_links_each_function_of_its_call_tree_once(monkeypatch):
    """A diamond (the top calls two functions that both call the leaf), compiled as the kernel is:
    the entry point links the four functions once each, and none of them links its callees."""
    from llvmlite.binding.module import ModuleRef

    links = []
    link_in = ModuleRef.link_in

    def counting(module, other, preserve=False):
        if preserve:   # a library's module linked into a caller's (a function's own IR is linked without)
            links.append(other)
        return link_in(module, other, preserve)

    def leaf(x):
        return x + 1.0

    def left(x):
        return 2.0 * leaf_(x)

    def right(x):
        return leaf_(x) - 3.0

    def top(x):
        return left_(x) * right_(x)

    leaf_, left_, right_, top_ = (_internal(f) for f in (leaf, left, right, top))

    def diamond(x):
        return top_(x)

    entry_point = _linking().entry(diamond, **compiled.CALLABLE)
    monkeypatch.setattr(ModuleRef, "link_in", counting)
    assert entry_point(1.0) == (2.0 * 2.0) * (2.0 - 3.0)
    defined = [[f.name for f in module.functions if not f.is_declaration] for module in links]
    for name in ("leaf", "left", "right", "top"):
        # (numba names a function's symbol with its qualified name's length before it: 4leaf, 3top)
        assert sum(any(f"{len(name)}{name}B" in symbol for symbol in symbols) for symbols in defined) == 1, name
    libraries = [next(iter(f.overloads.values())).library for f in (leaf_, left_, right_, top_)]
    assert all(isinstance(library, _linking().LinkOnlyLibrary) for library in libraries)
    assert all(library._tree_module is None for library in libraries)
