"""engine_model may use analytic's shared contract and nothing of its model, so the cross-check stays honest.

Allowed: ``analytic.design`` and ``analytic.design_file`` (the design
description and its files), ``analytic.units`` (the units a file's values may
carry, which the file reader converts), ``analytic.aero`` (drag tables, which the design
needs), ``analytic.result`` (the shared result types), ``analytic.outcome``
(statuses and outcome messages), ``analytic.limits`` (the bounds that end a
stage or a shot), ``analytic.geometry`` (part positions from coordinates
and the release rule), ``analytic.cli_shared`` (the command lines' exit codes and checks
of output paths and options, and their progress bars), ``analytic.plausibility`` (warnings on
implausible inputs, which every shot carries), ``analytic.suggest`` (the "did you mean" of the
file reader's messages), ``analytic.plot_units`` (a drawing's ticks in the chosen units) and
``analytic.data.strength`` (the materials' and projectiles' limits, and the beam's stress from a peak
moment, which the design and the shot's readouts use; with ``analytic.data``, its package of data files) and
``analytic.summary`` (the rows a shot's summary reads in, which the shared result type uses). None of them holds any dynamics: no equations of
motion, no integrator, no event loop. Everything else of ``analytic``
(equations, simulators, integrators) is what the engine is checked against,
and must not leak in.
"""

from __future__ import annotations

import ast
import json
import subprocess
import sys
from pathlib import Path

import pytest

ALLOWED = {"analytic", "analytic.design", "analytic.design_file", "analytic.units", "analytic.aero",
           "analytic.result", "analytic.outcome", "analytic.limits", "analytic.geometry", "analytic.cli_shared",
           "analytic.plausibility", "analytic.suggest", "analytic.plot_units", "analytic.data",
           "analytic.data.strength", "analytic.summary"}
PACKAGE = Path(__file__).resolve().parents[1] / "engine_model"
MODULES = sorted(p.stem for p in PACKAGE.glob("*.py") if p.stem != "__main__")


def test_every_module_is_scanned():
    # The package's own layout: guard against the glob silently matching nothing.
    assert {"build", "shot", "flight", "render", "cli"} <= set(MODULES)


def test_importing_every_module_loads_no_other_analytic_module():
    names = ", ".join(f"engine_model.{name}" for name in MODULES)
    code = (f"import json, sys, importlib\n"
            f"for name in {[f'engine_model.{m}' for m in MODULES]!r}: importlib.import_module(name)\n"
            f"print(json.dumps(sorted(m for m in sys.modules if m.split('.')[0] == 'analytic')))")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          cwd=PACKAGE.parent, check=True)
    loaded = set(json.loads(done.stdout))
    assert loaded <= ALLOWED, f"importing {names} loaded {sorted(loaded - ALLOWED)}"


def _analytic_references(path: Path) -> list[tuple[int, str]]:
    """Every import of an analytic module in a file, and every string naming one (importlib)."""
    found = []
    for node in ast.walk(ast.parse(path.read_text(), filename=str(path))):
        if isinstance(node, ast.Import):
            found += [(node.lineno, alias.name) for alias in node.names]
        elif isinstance(node, ast.ImportFrom) and node.module:
            found.append((node.lineno, node.module))
            if node.module == "analytic":
                found += [(node.lineno, f"analytic.{alias.name}") for alias in node.names]
        elif isinstance(node, ast.Constant) and isinstance(node.value, str) and node.value.startswith("analytic."):
            found.append((node.lineno, node.value))
    return [(line, name) for line, name in found if name.split(".")[0] == "analytic"]


@pytest.mark.parametrize("module", MODULES)
def test_source_imports_only_the_allowed_analytic_modules(module):
    # Also catches imports inside functions, which the subprocess check would only see when run.
    path = PACKAGE / f"{module}.py"
    bad = [(line, name) for line, name in _analytic_references(path)
           if ".".join(name.split(".")[:2]) not in ALLOWED]
    assert not bad, f"{path.name} reaches into analytic beyond {sorted(ALLOWED)}: {bad}"


def test_the_scan_sees_a_forbidden_import(tmp_path):
    # The guard must be able to fail: a lazy import of the analytic simulator is flagged.
    sample = tmp_path / "sample.py"
    sample.write_text("def f():\n    from analytic.reference import simulate\n    from analytic import eom\n")
    assert [name for _, name in _analytic_references(sample)] == ["analytic.reference", "analytic", "analytic.eom"]
