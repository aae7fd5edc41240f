"""The example notebook (``docs/builders.ipynb``) runs from top to bottom and is stored with what it
printed and drew; and a ``Shot`` shows itself in Jupyter."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import pytest

from analytic.reference import simulate

ROOT = Path(__file__).parents[1]
NOTEBOOK = ROOT / "docs" / "builders.ipynb"


def _runner():
    """``docs/execute_notebook.py`` (``make notebook``), loaded from its file."""
    spec = importlib.util.spec_from_file_location("execute_notebook", ROOT / "docs" / "execute_notebook.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _check_outputs(notebook) -> None:
    outputs = [output for cell in notebook.cells if cell.cell_type == "code" for output in cell.outputs]
    assert not [o for o in outputs if o.output_type == "error"]
    html = [o for o in outputs if o.output_type == "execute_result" and "text/html" in o.get("data", {})]
    assert html and "peak axle load" in html[0]["data"]["text/html"]
    images = [o for o in outputs if "image/png" in o.get("data", {})]
    assert len(images) >= 3   # the shot's plot, the chart and the calibration, inline
    printed = "".join(o.get("text", "") for o in outputs if o.output_type == "stream")
    assert " ft " in printed and " lbf " in printed   # the imperial example
    assert "drag factor" in printed and " kg: " in printed and "+-" in printed   # calibration, predictions


@pytest.mark.slow
def test_the_example_notebook_runs_and_is_stored_with_its_outputs():
    """Executed in a real kernel (``make notebook``'s run), checked, and written back with its outputs,
    so that the repository's page and the documentation site (which does not execute it) show what
    this run printed and drew; the file is rewritten only where its text changed."""
    import nbformat

    notebook = _runner().execute(NOTEBOOK)
    _check_outputs(notebook)
    text = nbformat.writes(notebook) + "\n"
    if NOTEBOOK.read_text() != text:
        NOTEBOOK.write_text(text)


def test_the_stored_notebook_holds_its_outputs():
    """The repository's page and the documentation site (which does not execute it) show the stored
    outputs: the test above (or ``make notebook``) stores them."""
    import nbformat

    _check_outputs(nbformat.read(NOTEBOOK, as_version=4))


def test_a_shot_shows_an_html_summary(table3):
    html = simulate(table3, histories=False)._repr_html_()
    assert html.startswith("<table>") and "paper-table3" in html
    for words in ("ok: thrown", "range", "peak sling tension", "peak axle load", "peak hinge load", " g at "):
        assert words in html


def test_the_html_summary_escapes_text(table3):
    import dataclasses

    shot = dataclasses.replace(simulate(table3, histories=False), warnings=("a <b>bold</b> & claim",))
    html = shot._repr_html_()
    assert "&lt;b&gt;bold&lt;/b&gt; &amp; claim" in html and "<b>" not in html
