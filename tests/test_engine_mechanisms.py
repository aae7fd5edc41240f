"""The engine's two ways into pymunk (``engine_model.readout``): its private cffi binding and its public
API give the same shots, bit for bit; the binding is used only where it fits; pymunk is bounded above
at the newest major version tested."""

from __future__ import annotations

import os
import re
import subprocess
import sys
import tomllib
from importlib.metadata import version
from pathlib import Path

import pytest
from packaging.requirements import Requirement
from packaging.version import Version

from engine_model import readout
from support import engine_records

ROOT = Path(__file__).resolve().parents[1]
TESTS = Path(__file__).resolve().parent
#: One design of every kind the engine builds (the cross-check's default suite): the paper's,
#: with every loss, on wheels, a fixed counterweight with every loss, a floating arm with every
#: loss, drag through the swing in a headwind, and one that fails (no landing).
DESIGNS = ["table3", "table3-all-losses", "table3-rolling-100kg", "paper-table3-fixed-all-losses",
           "table3-floating-arm-all-losses", "swing-drag-headwind", "fails-no_landing"]
#: pymunk's private names, which only ``engine_model/readout.py`` may touch.
PRIVATE = re.compile(r"_chipmunk|\._body\b|\._constraint\b|\._space\b|_bodies_to_check|_add_later|_remove_later"
                     r"|_post_step_callbacks|\._handlers\b")


def _run(code: str, mechanism: str | None = None) -> subprocess.Popen:
    """``code`` in a new interpreter (tests/ on its path), with ``TREBUCHET_PYMUNK`` set to ``mechanism``
    (None: unset), started at once: the caller waits on it."""
    env = {key: value for key, value in os.environ.items() if key != readout.VARIABLE}
    if mechanism is not None:
        env[readout.VARIABLE] = mechanism
    return subprocess.Popen([sys.executable, "-c", f"import sys; sys.path.insert(0, {str(TESTS)!r})\n{code}"],
                            cwd=ROOT, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


def _finished(process: subprocess.Popen) -> str:
    out, err = process.communicate(timeout=240)
    assert process.returncode == 0, err
    return out


def _differences(public: dict, binding: dict) -> list[str]:
    return [f"{name} {path}: public {public[name].get(path)} != binding {binding[name].get(path)}"
            for name in binding for path in sorted(set(binding[name]) | set(public[name]))
            if public[name].get(path) != binding[name].get(path)]


def test_the_public_api_throws_every_kind_of_design_as_the_binding_does_bit_for_bit():
    """This process's mechanism (``TREBUCHET_PYMUNK`` as the suite was started with) against the other's, in
    a new interpreter."""
    import json

    here = readout.mechanism()
    code = ("import json\nfrom engine_model import readout\nfrom support import engine_records\n"
            f"print(json.dumps([readout.mechanism(), engine_records({DESIGNS!r})]))")
    other = _run(code, "public" if here == "binding" else "binding")   # runs while this process throws
    records = {here: engine_records(DESIGNS)}
    there, records_there = json.loads(_finished(other))
    assert {here, there} == {"binding", "public"}, (
        f"pymunk's private binding does not fit pymunk {version('pymunk')} (readout._binding_fits): the "
        f"engine runs on its public API alone; update engine_model/readout.py's private names to it")
    records[there] = records_there
    public, binding = records["public"], records["binding"]
    assert not _differences(public, binding), "\n".join(_differences(public, binding)[:20])
    statuses = {binding[name]["json['status']"] for name in DESIGNS}
    assert {"'ok'", "'no_landing'"} <= statuses   # a throw and a failure, each compared whole


def _missing() -> readout._Calls:
    raise ImportError("cannot import name 'lib' from 'pymunk._chipmunk'")


def _renamed() -> readout._Calls:
    return readout._binding_calls()._replace(position=None)   # the first call then raises TypeError


def _renamed_attribute() -> readout._Calls:
    raise AttributeError("module 'pymunk._chipmunk' has no attribute 'lib'")


def _one_ulp_off() -> readout._Calls:
    calls = readout._binding_calls()
    return calls._replace(angle=lambda handle: calls.angle(handle) * (1.0 + 2.0 ** -52))


def _limit_ignored() -> readout._Calls:
    return readout._binding_calls()._replace(set_max_force=lambda handle, limit: None)


@pytest.mark.parametrize("binding", [_missing, _renamed_attribute, _renamed, _one_ulp_off, _limit_ignored],
                         ids=["import-error", "attribute-error", "type-error", "a-reading-one-ulp-off",
                              "a-setting-ignored"])
def test_a_binding_that_does_not_fit_falls_back_to_the_public_api(binding):
    mechanism, calls = readout._choose(None, binding)
    body = object()
    assert mechanism == "public" and calls.step is None and calls.body(body) is body


def test_the_variable_picks_the_mechanism_and_names_its_choices():
    assert readout._choose(None)[0] == readout._choose("")[0] == readout._choose("binding")[0] == "binding"
    assert readout._choose("public", _missing)[0] == "public"   # the binding is not even loaded
    with pytest.raises(ValueError, match=r"TREBUCHET_PYMUNK='Public': must be one of 'binding', 'public'"):
        readout._choose("Public")


def test_a_pymunk_without_the_binding_throws_through_the_public_api():
    """Its private module gone (as a pymunk release may rename it): the engine imports, says so, and throws
    the shot this process throws."""
    code = ("import json, sys, types\nimport pymunk\n"
            "sys.modules['pymunk._chipmunk'] = types.SimpleNamespace(lib=types.SimpleNamespace())\n"
            "from engine_model import readout\nfrom support import engine_records\n"
            "print(json.dumps([readout.mechanism(), engine_records(['table3'])]))")
    import json

    other = _run(code)
    binding = engine_records(["table3"])
    mechanism, public = json.loads(_finished(other))
    assert mechanism == "public"
    assert not _differences(public, binding), "\n".join(_differences(public, binding)[:20])


def test_only_readout_touches_pymunks_private_names():
    found = [f"{path.name}:{number}: {line.strip()}"
             for path in sorted((ROOT / "engine_model").glob("*.py")) if path.name != "readout.py"
             for number, line in enumerate(path.read_text().splitlines(), 1) if PRIVATE.search(line)]
    assert not found, "pymunk's private names outside engine_model/readout.py:\n" + "\n".join(found)
    assert PRIVATE.search((ROOT / "engine_model" / "readout.py").read_text())   # the pattern sees them


def test_pymunk_is_bounded_above_at_a_tested_major_version():
    """pymunk's next major version may change its public API or its private binding: the bound says
    which versions the engine has been run on, both ways."""
    dependencies = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["dependencies"]
    (pymunk,) = [Requirement(line) for line in dependencies if Requirement(line).name == "pymunk"]
    uppers = [Version(spec.version) for spec in pymunk.specifier if spec.operator in ("<", "<=")]
    assert uppers, f"pyproject.toml's {pymunk} has no upper bound: bound it above the newest version tested"
    installed = version("pymunk")
    assert pymunk.specifier.contains(installed), (
        f"pymunk {installed} is installed, outside the tested {pymunk} in pyproject.toml. Run the engine's "
        f"tests on it twice, with {readout.VARIABLE}=public and without it (.venv/bin/python -m pytest "
        f"tests/test_engine_*.py), and if both pass, widen the bound to take it in "
        f"(docs/dependencies.md says why it is there).")
