"""The two mechanisms that compile the fast path (``analytic.fast.compiled``): the same bits, the choice, the bound.

The linked mechanism (``analytic.fast.numba_linking``) rests on numba's internals and
the public one on its public API; both compile the same model source. These
tests shoot the bench's designs and the cross-check's ideal ones in the ideal
scope on the mechanism this process does not use, in a child process, and
compare every entry of every result row with this process's bit for bit; they
check that a linking machinery that does not fit the numba installed leaves the
public mechanism in charge without a word to the user, that importing the fast
path builds and deletes nothing, and that the numba installed is one this
project has tested.
"""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys
from pathlib import Path

import numba
import numpy as np
import pytest

from analytic import fast, scope
from analytic.aero import DRAG_TABLE
from analytic.fast import compiled, kernel
from analytic.reference import DEFAULT_ATOL, DEFAULT_RTOL
from analytic.scope import IDEAL
from support import compile_a_stand_in_entry_point

ROOT = Path(__file__).resolve().parents[1]
#: The bench's designs compared: the paper's optimum and this many drawn over Table II.
BENCH_DESIGNS = 200


def _design_sets() -> dict[str, list]:
    """The designs compared, every one in the ideal scope: the bench's (``benchmarks.designs``) and
    those of the cross-check's default suite that the ideal scope handles (``crosscheck.cases``:
    hinged and fixed counterweights, the drag models, the winds, the sling rule, the failures)."""
    from analytic.parameters import params
    from benchmarks.designs import bench_designs
    from crosscheck.cases import default_suite

    return {"bench": bench_designs(BENCH_DESIGNS, 0),
            "crosscheck": [case.design for case in default_suite()
                           if scope.needed(params(case.design), loads=False) == IDEAL]}


def results() -> dict[str, np.ndarray]:
    """The ideal scope's result record (``kernel.RESULT_DTYPE``) of every design of ``_design_sets()``,
    by set: ``{name: (designs,) array}``, the same names on either mechanism.

    Only the ideal scope, the smallest, is compiled: it holds everything each mechanism does
    (the entry point, the kernel, DOP853, the model's equations, events and sequence, each callee
    compiled once and built into the entry point's machine code), in the shortest cold compile.
    """
    arrays = {}
    entry_point = fast.entry_point(IDEAL)
    fast.compile(IDEAL)
    for name, designs in _design_sets().items():
        rows = fast.pack_many(designs)
        assert scope.needed_rows(rows, loads=False) == IDEAL, name
        out = np.empty(len(rows), kernel.RESULT_DTYPE)
        entry_point(rows, 0, len(rows), DRAG_TABLE, fast.COEFFICIENTS, DEFAULT_RTOL, DEFAULT_ATOL, False, out,
                    fast._NO_RECORDING, fast._NO_SAMPLES)
        arrays[name] = out
    return arrays


def _bits(column: np.ndarray) -> np.ndarray:
    """A result field's bytes, one row a record (field by field: a record's padding is not its value)."""
    return np.ascontiguousarray(column).view(np.uint8).reshape(len(column), -1)


def _other_mechanism() -> str:
    """The mechanism this process does not use (the linked one only where it fits)."""
    if compiled.mechanism() == "linked":
        return "public"
    if isinstance(compiled._linking(), str):
        pytest.skip(f"the linked mechanism does not fit: {compiled._linking()}")
    return "linked"


@pytest.mark.slow
@pytest.mark.timeout(600)   # (the other mechanism's cold compile, after a source of the model changed)
def test_both_mechanisms_give_the_same_bits(tmp_path):
    """The other mechanism's result records (``results()``, in a new interpreter with ``TREBUCHET_NUMBA`` set
    to it) equal this process's bit for bit, NaN payloads too.

    The reference numbers are this process's own: the same designs shot by its mechanism in the same
    run on the same machine, never figures recorded elsewhere (the last bits of libm and numpy
    differ between CPUs). Only the ideal scope is compared: a cold compile of the public mechanism's
    scope that handles everything takes minutes of the suite's two cores, the ideal one's a fraction
    of that, and the larger scopes are compiled from the same source by the same ``compiled.callee``
    and ``compiled.entry``; within either mechanism a smaller scope gives the larger one's bits
    (``test_analytic_scope.py``, on whichever mechanism the suite runs: ``TREBUCHET_NUMBA``).
    The other mechanism's entry point is cached on disk under its own name, so this compiles it
    only in a fresh copy or after a source of the model changed.
    """
    other = _other_mechanism()
    code = (f"import sys; sys.path.insert(0, {str(ROOT / 'tests')!r}); import numpy as np; "
            "from analytic.fast import compiled; from test_analytic_numba_mechanisms import results; "
            f"np.savez({str(tmp_path / 'other.npz')!r}, **results()); print(compiled.mechanism())")
    child = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                             text=True, cwd=ROOT, env={**os.environ, compiled.MECHANISM_VARIABLE: other})
    ours = results()   # (while the child compiles)
    out, err = child.communicate()
    assert child.returncode == 0, err[-3000:]
    assert out.split()[-1] == other
    theirs = np.load(tmp_path / "other.npz")
    assert sorted(theirs.files) == sorted(ours)
    for name, array in ours.items():
        for field in kernel.RESULT_DTYPE.names:
            mine, other_field = array[field], theirs[name][field]
            differ = (_bits(mine) != _bits(other_field)).any(axis=1)
            assert not differ.any(), (f"{name}.{field}: {compiled.mechanism()} and {other} differ at rows "
                                      f"{np.flatnonzero(differ)[:5]}: {mine[differ][:5]} against "
                                      f"{other_field[differ][:5]}")
    assert ours["bench"].shape == (BENCH_DESIGNS + 1,)
    statuses = set(ours["crosscheck"]["status"].tolist())
    assert kernel.OK in statuses and len(statuses) > 3   # throws and failures of several kinds, compared whole


# --------------------------------------------------------------------------- #
# The choice of mechanism
# --------------------------------------------------------------------------- #

def test_the_linked_mechanism_is_chosen_wherever_it_fits_and_the_public_one_otherwise():
    linking = compiled._linking()
    assert compiled.select("", linking)[0] == compiled.select("auto", linking)[0] == (
        "public" if isinstance(linking, str) else "linked")
    assert compiled.select("public", linking) == ("public", "TREBUCHET_NUMBA=public")
    assert compiled.select("", "numba 9.9's JITCodeLibrary has no _final_module") == (
        "public", "numba 9.9's JITCodeLibrary has no _final_module")
    with pytest.raises(RuntimeError, match="TREBUCHET_NUMBA=linked, but numba 9.9"):
        compiled.select("linked", "numba 9.9's JITCodeLibrary has no _final_module")
    with pytest.raises(ValueError, match="TREBUCHET_NUMBA='fast': expected one of auto, linked, public"):
        compiled.select("fast", linking)


@pytest.mark.parametrize("misfit", ["signature", "body", "probe raises", "import"])
def test_a_linking_machinery_that_does_not_fit_leaves_the_public_mechanism_in_charge(misfit, monkeypatch):
    from analytic.fast import numba_linking

    if misfit == "signature":
        function, _ = numba_linking.SIGNATURES["compile_extra"]
        monkeypatch.setitem(numba_linking.SIGNATURES, "compile_extra", (function, ("typingctx", "targetctx")))
    elif misfit == "body":
        function, _ = numba_linking.BODIES["CPUCodeLibrary.finalize"]
        monkeypatch.setitem(numba_linking.BODIES, "CPUCodeLibrary.finalize", (function, "0" * 16))
    elif misfit == "probe raises":
        monkeypatch.setattr(numba_linking, "LinkOnlyLibrary", None)
    else:
        monkeypatch.setitem(sys.modules, "analytic.fast.numba_linking", None)   # (an import that fails)
        monkeypatch.delattr(fast, "numba_linking")
    compiled._linking.cache_clear()
    try:
        reason = compiled._linking()
    finally:
        compiled._linking.cache_clear()
    assert isinstance(reason, str)
    assert compiled.select("", reason) == ("public", reason)


def test_the_compile_command_says_which_mechanism_compiled(monkeypatch, capsys):
    from analytic.cli import main

    monkeypatch.setattr(fast, "compile_all", lambda scopes, progress: {s.name: 1.0 for s in scopes})
    monkeypatch.setattr(compiled, "_selected", lambda: ("public", "numba 9.9's JITCodeLibrary has no _final_module"))
    assert main(["compile", "--scope", "ideal"]) == 0
    assert capsys.readouterr().out == ("fast path ready (ideal 1.0 s; numba mechanism public: "
                                       "numba 9.9's JITCodeLibrary has no _final_module)\n")


def test_a_machinery_that_does_not_import_falls_back_without_a_word(tmp_path):
    # A fresh process in which the linking module cannot import (as on a numba without the
    # internals it imports): the public mechanism builds the scopes' twins, and nothing is said.
    code = """if True:
        import sys
        sys.modules["analytic.fast.numba_linking"] = None
        from analytic import scope
        from analytic.fast import compiled
        twins = compiled.kernel_scope(scope.IDEAL)
        print(compiled.mechanism(), twins["kernel"].shots.py_func.__qualname__)
        print(compiled.mechanism_reason())
    """
    env = {name: value for name, value in os.environ.items() if name != compiled.MECHANISM_VARIABLE}   # (auto)
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                          env={**env, "NUMBA_CACHE_DIR": str(tmp_path)})
    mechanism, reason = done.stdout.splitlines()
    assert mechanism == f"public shots_ideal{compiled.PUBLIC_LABEL}"
    assert reason.startswith("analytic.fast.numba_linking does not import: ")
    assert done.stderr == ""


@pytest.mark.parametrize("change", ["pass renamed", "event kind removed"])
def test_the_progress_needs_no_pass_name_numba_does_not_promise(change, monkeypatch, capsys):
    # The last label knows the entry point's last step by numba's name for its pass; on a numba
    # that names it otherwise, or has no such event, the compile goes on without that label.
    from numba.core import event

    if change == "pass renamed":
        monkeypatch.setattr(fast, "LOWERING_PASS", "a pass numba renamed")
    else:
        install = event.install_listener

        def install_listener(kind, listener):
            if kind == "numba:run_pass":
                raise ValueError(f"{kind!r} is not a valid event kind")
            return install(kind, listener)

        monkeypatch.setattr(event, "install_listener", install_listener)
    compile_a_stand_in_entry_point(IDEAL)
    err = capsys.readouterr().err
    assert err.startswith("compiling the fast path's ideal scope once")
    assert "the whole kernel's machine code" not in err


# --------------------------------------------------------------------------- #
# Importing builds nothing
# --------------------------------------------------------------------------- #

def test_importing_the_fast_path_builds_nothing_and_deletes_nothing(tmp_path):
    """The twins and the cache's check wait for the first use: an import compiles no dispatcher and
    leaves a stale cache file where it is; the first use drops it."""
    first_use = """if True:
        from analytic import scope
        from analytic.fast import compiled
        print(compiled.cache_directory(compiled.kernel_scope(scope.IDEAL)["kernel"].shots))
    """
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path)}
    run = lambda code: subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                                      env=env).stdout
    directory = Path(run(first_use).split()[-1])
    mechanism = compiled.mechanism()
    stale = directory / f"kernel.shots_ideal{compiled.PUBLIC_LABEL if mechanism == 'public' else ''}-1.py311.nbi"
    stale.write_text("stale")
    (directory / compiled.stamp_name(mechanism)).write_text("an older model's fingerprint")
    imports = """if True:
        import gc, importlib, json, pkgutil
        import numba, scipy.integrate
        from numba.core.dispatcher import Dispatcher
        count = lambda: sum(isinstance(o, Dispatcher) for o in gc.get_objects())
        before = count()
        import analytic
        for module in pkgutil.walk_packages(analytic.__path__, "analytic."):
            if not module.name.endswith("__main__"):
                importlib.import_module(module.name)
        from analytic.fast import compiled
        print(json.dumps({"dispatchers": count() - before, "scopes": len(compiled._scopes),
                          "twins": compiled._built_model_twins.cache_info().currsize}))
    """
    assert json.loads(run(imports).splitlines()[-1]) == {"dispatchers": 0, "scopes": 0, "twins": 0}
    assert stale.exists()
    run(first_use)
    assert not stale.exists()


def test_the_lazy_names_are_the_twins():
    assert compiled.eom_ is compiled.callable_twins["eom"] and compiled.peaks_ is compiled.callable_twins["peaks"]
    assert set(compiled.kernel_twins) == set(compiled.callable_twins) == {
        m.__name__.rsplit(".", 1)[-1] for m in compiled.MODEL_MODULES}
    with pytest.raises(AttributeError, match="has no attribute 'eom_twins'"):
        compiled.eom_twins


# --------------------------------------------------------------------------- #
# The numba this project has tested
# --------------------------------------------------------------------------- #

def _numba_bound() -> tuple[str, tuple[int, int], tuple[int, int]]:
    """pyproject.toml's numba requirement, its lower and its upper bound (major, minor)."""
    requirement = re.search(r'"(numba>=(\d+)\.(\d+),<(\d+)\.(\d+))"', (ROOT / "pyproject.toml").read_text())
    assert requirement, "pyproject.toml bounds numba as numba>=X.Y,<X.Z"
    text, *numbers = requirement.groups()
    numbers = [int(n) for n in numbers]
    return text, tuple(numbers[:2]), tuple(numbers[2:])


def test_numba_is_a_version_this_project_has_tested():
    requirement, lower, upper = _numba_bound()
    installed = tuple(int(part) for part in numba.__version__.split(".")[:2])
    assert lower <= installed < upper, (
        f"numba {numba.__version__} is not a version this project has tested ({requirement} in pyproject.toml). "
        "Run the suite on both mechanisms, TREBUCHET_NUMBA=public and TREBUCHET_NUMBA=linked (python -m analytic "
        "compile says which one compiled), update analytic/fast/numba_linking.py where the linked one no longer fits "
        "(problem() says why), then widen the bound in pyproject.toml and numba_linking.TESTED_NUMBA.")
    assert numba_linking_tested() == lower


def numba_linking_tested() -> tuple[int, int]:
    from analytic.fast import numba_linking

    return tuple(int(part) for part in numba_linking.TESTED_NUMBA.split("."))


def test_the_linking_machinery_fits_the_numba_tested():
    # A numba the bound allows but whose internals moved (a patch release) would otherwise leave
    # every user on the public mechanism's longer cold compile without anyone noticing.
    linking = compiled._linking()
    assert not isinstance(linking, str), (
        f"the linked mechanism does not fit numba {numba.__version__}: {linking}. The fast path falls back to "
        "the public mechanism (the same numbers, a longer cold compile); update analytic/fast/numba_linking.py.")
