"""The layout's import rules, checked from the sources (ast), so that a lazy import inside a function counts too.

The product code is four packages, each importing only those below it::

    analytic       the model -> its two paths -> the tools -> the command lines
    engine_model   the same machine in pymunk (which of analytic it may use: test_engine_imports.py)
    crosscheck     analytic + engine_model
    benchmarks     anything below
    workbench      the local web page: analytic, engine_model and crosscheck (not benchmarks); nothing imports it

Inside ``analytic`` the same holds for its layers (``ANALYTIC_LAYERS``). No
module imports in a circle. An import counts wherever it is written (module
level or inside a function) and so does ``importlib.import_module("name")``;
an import under ``if TYPE_CHECKING:`` does not, as it never runs (the modules
use ``from __future__ import annotations``). Starting another command as a
child process (``[python, "-m", "benchmarks", ...]``) is not an import; such
hand-overs are listed apart and each one out of ``analytic`` is declared in
``HANDOVERS``.
"""

from __future__ import annotations

import ast
import json
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
#: The product packages, lowest first: each may import only itself and those before it.
PACKAGES = ("analytic", "engine_model", "crosscheck", "benchmarks", "workbench")
#: ``analytic``'s layers, lowest first: a module may import only its own layer and those before it.
#: A module of ``analytic`` not named here fails ``test_every_analytic_module_has_a_layer``.
ANALYTIC_LAYERS = {
    "model": {"analytic.design", "analytic.design_file", "analytic.design_space", "analytic.units",
              "analytic.fields", "analytic.aero", "analytic.eom", "analytic.friction", "analytic.geometry",
              "analytic.limits", "analytic.outcome", "analytic.parameters", "analytic.peaks",
              "analytic.plausibility", "analytic.states", "analytic.stages", "analytic.sequence", "analytic.result", "analytic.data",
              "analytic.suggest", "analytic.floating_arm", "analytic.scope", "analytic.ideal", "analytic.data.strength",
              # the summary rows of a shot every table shows
              "analytic.summary",
              # the exit codes and checks every command line shares: it imports nothing
              "analytic.cli_shared"},
    "paths": {"analytic.reference", "analytic.reference.loads", "analytic.reference.ode", "analytic.fast.compiled",
              "analytic.fast.numba_linking", "analytic.fast.kernel", "analytic.fast",
              "analytic.fast.dop853", "analytic.fast.kernel_loads", "analytic.fast.motion", "analytic.fast.marks",
              # the public names, loaded on first use from the model and the paths
              "analytic"},
    "tools": {"analytic.aim", "analytic.chart", "analytic.plot", "analytic.plot_units", "analytic.report", "analytic.calibrate*",
              "analytic.optimise*", "analytic.sweep*",
              "analytic.firing*"},
    "command lines": {"analytic.cli", "analytic.__main__", "analytic.calibrate.cli", "analytic.optimise.cli",
                      "analytic.sweep.cli", "analytic.firing.cli"},
}
#: Import edges known to break the rules, each with what removes it (remove the entry with it).
KNOWN = {
    ("analytic.result", "analytic.plot"): "broken by the results branch",   # and plot -> result: a circle
}
#: Commands started as a child process from ``analytic``: (module, the command's package) -> why.
HANDOVERS = {
    ("analytic.cli", "benchmarks"): "python -m analytic bench, the older name of python -m benchmarks",
}
_DYNAMIC = {"import_module", "__import__", "run_module"}


def module_names(root: Path) -> dict[str, Path]:
    """Every product module under ``root``: dotted name -> file."""
    names = {}
    for package in PACKAGES:
        for path in sorted((root / package).rglob("*.py")):
            parts = list(path.relative_to(root).with_suffix("").parts)
            if parts[-1] == "__init__":
                parts.pop()
            names[".".join(parts)] = path
    return names


def _type_checking_nodes(tree: ast.AST) -> set[int]:
    """ids of the nodes under ``if TYPE_CHECKING:``."""
    skipped = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.If) and getattr(node.test, "id", getattr(node.test, "attr", None)) == "TYPE_CHECKING":
            skipped |= {id(inner) for statement in node.body for inner in ast.walk(statement)}
    return skipped


def _imported(name: str, path: Path) -> tuple[set[str], set[str]]:
    """The dotted names ``path`` (module ``name``) imports, and the modules it starts with ``-m``."""
    tree = ast.parse(path.read_text(), filename=str(path))
    skipped = _type_checking_nodes(tree)
    imported, started = set(), set()
    for node in ast.walk(tree):
        if id(node) in skipped:
            continue
        if isinstance(node, ast.Import):
            imported |= {alias.name for alias in node.names}
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                package = name.split(".") if path.name == "__init__.py" else name.split(".")[:-1]
                base = ".".join(package[:len(package) - node.level + 1] + ([base] if base else []))
            # ``from analytic import fast`` loads analytic.fast; ``from analytic.design import Design``
            # resolves to analytic.design (``_resolve``).
            imported |= {f"{base}.{alias.name}" for alias in node.names}
        elif (isinstance(node, ast.Call) and getattr(node.func, "id", getattr(node.func, "attr", None)) in _DYNAMIC
              and node.args and isinstance(node.args[0], ast.Constant) and isinstance(node.args[0].value, str)):
            imported.add(node.args[0].value)
        elif isinstance(node, (ast.List, ast.Tuple)):
            values = [getattr(item, "value", None) for item in node.elts]
            started |= {value for flag, value in zip(values, values[1:]) if flag == "-m" and isinstance(value, str)}
    return imported, started


def _resolve(name: str, modules: dict[str, Path]) -> str | None:
    """The product module ``name`` loads (``analytic.fast.simulate_fast`` -> ``analytic.fast``), or None."""
    while name and name not in modules:
        name = name.rpartition(".")[0]
    return name or None


def import_graph(root: Path) -> tuple[dict[str, set[str]], dict[str, set[str]]]:
    """The product modules' imports among themselves, and the product commands each starts."""
    modules = module_names(root)
    graph, handovers = {}, {}
    for name, path in modules.items():
        imported, started = _imported(name, path)
        targets = {_resolve(target, modules) for target in imported}
        graph[name] = {target for target in targets if target not in (None, name)}
        handovers[name] = {target for target in started if target.split(".")[0] in PACKAGES}
    return graph, handovers


def cycles(graph: dict[str, set[str]], known: dict = KNOWN) -> list[list[str]]:
    """Each circle of imports in ``graph`` (edges in ``known`` left out), as the modules around it."""
    graph = {name: {t for t in targets if (name, t) not in known} for name, targets in graph.items()}
    found, done = [], set()
    for start in sorted(graph):
        path, on_path, stack = [], set(), [(start, iter(sorted(graph[start])))]
        path.append(start)
        on_path.add(start)
        while stack:
            node, targets = stack[-1]
            target = next(targets, None)
            if target is None:
                stack.pop()
                on_path.discard(path.pop())
                done.add(node)
            elif target in on_path:
                found.append(path[path.index(target):] + [target])
            elif target not in done and target in graph:
                path.append(target)
                on_path.add(target)
                stack.append((target, iter(sorted(graph[target]))))
    return found


def _analytic_layer(module: str) -> int:
    for rank, members in enumerate(ANALYTIC_LAYERS.values()):
        exact = {m for m in members if not m.endswith("*")}
        if module in exact:
            return rank
    for rank, members in enumerate(ANALYTIC_LAYERS.values()):
        if any(module.startswith(m[:-1]) for m in members if m.endswith("*")):
            return rank
    raise KeyError(module)


def layer_breaches(graph: dict[str, set[str]], known: dict = KNOWN) -> list[str]:
    """Every import of a package above the importer's, or of an analytic layer above its own."""
    breaches = []
    for name, targets in sorted(graph.items()):
        for target in sorted(targets):
            if (name, target) in known:
                continue
            mine, theirs = PACKAGES.index(name.split(".")[0]), PACKAGES.index(target.split(".")[0])
            if theirs > mine:
                breaches.append(f"{name} imports {target} ({PACKAGES[theirs]} is above {PACKAGES[mine]})")
            elif mine == theirs == 0 and _analytic_layer(target) > _analytic_layer(name):
                layers = list(ANALYTIC_LAYERS)
                breaches.append(f"{name} ({layers[_analytic_layer(name)]}) imports {target} "
                                f"({layers[_analytic_layer(target)]})")
    return breaches


GRAPH, STARTED = import_graph(ROOT)


def test_the_scan_sees_every_package():
    assert {"analytic.eom", "analytic.cli", "engine_model.shot", "crosscheck.cli", "benchmarks.cli"} <= set(GRAPH)
    assert "analytic.fast" in GRAPH["analytic.cli"]   # a lazy import inside a function counts


def test_every_analytic_module_has_a_layer():
    for name in GRAPH:
        if name.split(".")[0] == "analytic":
            _analytic_layer(name)   # KeyError names a module to place in ANALYTIC_LAYERS


def test_no_module_imports_in_a_circle():
    found = cycles(GRAPH)
    assert not found, "imports in a circle: " + "; ".join(" -> ".join(c) for c in found)


def test_each_package_imports_only_those_below_it_and_analytic_its_layers_in_order():
    breaches = layer_breaches(GRAPH)
    assert not breaches, "\n".join(breaches)


def test_analytic_imports_neither_crosscheck_nor_engine_model_nor_benchmarks():
    # The issue's own words, apart from the layer table: a breach here is named as such.
    reached = {(name, target) for name, targets in GRAPH.items() if name.split(".")[0] == "analytic"
               for target in targets if target.split(".")[0] in ("crosscheck", "engine_model", "benchmarks")}
    assert not reached


def test_importing_every_analytic_module_loads_none_of_the_packages_above_it():
    # The same rule at run time, in a fresh process: every module of analytic and its command
    # line's parser (which imports each subcommand's).
    names = sorted(name for name in GRAPH if name.split(".")[0] == "analytic" and name != "analytic.__main__")
    code = ("import importlib, json, sys\n"
            f"for name in {names!r}: importlib.import_module(name)\n"
            "importlib.import_module('analytic.cli').build_parser()\n"
            f"print(json.dumps(sorted(m for m in sys.modules if m.split('.')[0] in {PACKAGES[1:]!r})))")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT, check=True)
    assert json.loads(done.stdout) == []


def test_workbench_imports_no_benchmarks_and_nothing_imports_it():
    # benchmarks and workbench sit side by side at the top: neither is below the other.
    reached = {(name, target) for name, targets in GRAPH.items() for target in targets
               if (name.split(".")[0] == "workbench") != (target.split(".")[0] == "workbench")
               and (target.split(".")[0] in ("workbench", "benchmarks"))}
    assert not reached
    assert "analytic.reference" in GRAPH["workbench.shot"]   # the scan sees the workbench


def test_analytic_starts_other_commands_only_where_declared():
    started = {(name, target.split(".")[0]) for name, targets in STARTED.items() if name.split(".")[0] == "analytic"
               for target in targets if target.split(".")[0] != "analytic"}
    assert started == set(HANDOVERS)


def test_every_known_breach_is_still_there():
    # An entry of KNOWN whose import is gone must go too, so the list never hides a new one.
    for name, target in KNOWN:
        assert target in GRAPH.get(name, set()), f"{name} no longer imports {target}: remove it from KNOWN"


#: The layout's documented map: a table of every module (``docs/contributing.md``, "Module by module").
MAP = ROOT / "docs" / "contributing.md"


def documented_map(text: str) -> list[tuple[str, str]]:
    """``(path, layer)`` of each row of the map's table, in order: rows whose first cell is a
    module's path in backticks (``| `analytic/eom.py` | model | ... |``)."""
    rows = []
    for line in text.splitlines():
        cells = [cell.strip() for cell in line.strip().strip("|").split("|")]
        if len(cells) >= 2 and cells[0].startswith("`") and cells[0].endswith(".py`"):
            rows.append((cells[0].strip("`"), cells[1]))
    return rows


def map_mismatches(rows: list[tuple[str, str]], modules: dict[str, Path], root: Path) -> list[str]:
    """What the map gets wrong about the tree: a module listed twice, listed but absent, present but
    not listed, or in another analytic layer than the rules' (``ANALYTIC_LAYERS``)."""
    paths = {str(path.relative_to(root)): name for name, path in modules.items()}
    listed = [path for path, _ in rows]
    wrong = [f"{path} is listed {listed.count(path)} times" for path in sorted(set(listed)) if listed.count(path) > 1]
    wrong += [f"{path} is listed but is not in the tree" for path in sorted(set(listed) - set(paths))]
    wrong += [f"{path} is in the tree but not in the map" for path in sorted(set(paths) - set(listed))]
    layers = list(ANALYTIC_LAYERS)
    for path, layer in rows:
        name = paths.get(path)
        if name is not None and name.split(".")[0] == "analytic":
            rule = layers[_analytic_layer(name)]
            if layer != rule:
                wrong.append(f"{path}: the map says {layer!r}, the rules {rule!r}")
        elif name is not None and layer != name.split(".")[0]:
            wrong.append(f"{path}: the map says {layer!r}, its package is {name.split('.')[0]!r}")
    return wrong


def test_the_documented_map_lists_every_module_once_in_the_layer_the_rules_give_it():
    rows = documented_map(MAP.read_text())
    assert not map_mismatches(rows, module_names(ROOT), ROOT), "\n".join(map_mismatches(rows, module_names(ROOT), ROOT))


def test_the_map_check_can_fail():
    modules = module_names(ROOT)
    rows = documented_map(MAP.read_text())
    first = rows[0]
    mangled = rows[1:] + [("analytic/nowhere.py", "model"), rows[1]]
    mangled = [(path, "tools") if path == "analytic/eom.py" else (path, layer) for path, layer in mangled]
    wrong = map_mismatches(mangled, modules, ROOT)
    assert f"{first[0]} is in the tree but not in the map" in wrong
    assert "analytic/nowhere.py is listed but is not in the tree" in wrong
    assert f"{rows[1][0]} is listed 2 times" in wrong
    assert "analytic/eom.py: the map says 'tools', the rules 'model'" in wrong


#: The two paths' rooms: the model never imports them, and within analytic only the fast path's imports
#: numba (the benchmarks, above it, may).
ROOMS = ("analytic.reference", "analytic.fast")


def test_the_two_paths_live_in_their_own_rooms():
    model = set(ANALYTIC_LAYERS["model"])
    for name, targets in GRAPH.items():
        if name in model:
            assert not {t for t in targets if t.startswith(ROOMS)}, f"{name} imports a path's room"
    numba_users = {name for name, path in module_names(ROOT).items()
                   if "numba" in {m.split(".")[0] for m in _imported(name, path)[0]}}
    inside = {name for name in numba_users if name.split(".")[0] == "analytic"}
    assert inside and all(name.startswith("analytic.fast") for name in inside), inside
    assert len(list((ROOT / "analytic").glob("*.py"))) <= 32   # the package's own top level stays small


# --------------------------------------------------------------------------- #
# The checks can fail: a tree with planted bad imports
# --------------------------------------------------------------------------- #

@pytest.fixture()
def planted(tmp_path: Path) -> Path:
    files = {
        "analytic/__init__.py": "",
        "analytic/eom.py": "def f():\n    from analytic.reference import simulate\n",
        "analytic/reference.py": "from analytic import eom\nfrom typing import TYPE_CHECKING\n"
                                 "if TYPE_CHECKING:\n    from analytic.cli import main\n",
        "analytic/cli.py": "import importlib\n\ndef g():\n    return importlib.import_module('crosscheck.cli')\n"
                           "\nCOMMAND = ['python', '-m', 'engine_model']\n",
        "engine_model/__init__.py": "from crosscheck import cli\n",
        "crosscheck/__init__.py": "",
        "crosscheck/cli.py": "from analytic import eom\n",
        "benchmarks/__init__.py": "",
    }
    for name, text in files.items():
        (tmp_path / name).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / name).write_text(text)
    return tmp_path


def test_the_checks_see_planted_circles_breaches_and_hand_overs(planted):
    graph, started = import_graph(planted)
    assert cycles(graph, known={}) == [["analytic.eom", "analytic.reference", "analytic.eom"]]
    assert "analytic.cli" not in graph["analytic.reference"]   # under TYPE_CHECKING: never runs
    breaches = layer_breaches(graph, known={})
    assert "analytic.cli imports crosscheck.cli (crosscheck is above analytic)" in breaches
    assert "engine_model imports crosscheck.cli (crosscheck is above engine_model)" in breaches
    assert "analytic.eom (model) imports analytic.reference (paths)" in breaches
    assert started["analytic.cli"] == {"engine_model"}
