"""The example notebook (``docs/builders.ipynb``) runs from top to bottom and is stored with what it
printed and drew; and a ``Shot`` shows itself in Jupyter."""

from __future__ import annotations

from pathlib import Path

import pytest

from analytic.reference import simulate

ROOT = Path(__file__).parents[1]
NOTEBOOK = ROOT / "docs" / "builders.ipynb"
#: Seconds a cell may take: the optimiser's cell is the longest (a few seconds on the fast
#: path once compiled; a cold numba cache adds the compile, about a minute on two cores).
CELL_TIMEOUT = 900


@pytest.mark.slow
def test_the_example_notebook_runs_and_is_stored_with_its_outputs():
    """Executed in a real kernel, checked, and written back with its outputs (no run times), so that
    the repository's page and the documentation site (which does not execute it) show its pictures."""
    import nbclient
    import nbformat

    notebook = nbformat.read(NOTEBOOK, as_version=4)
    # Run from the repository's top folder, as the notebook says: the kernel imports this checkout.
    client = nbclient.NotebookClient(notebook, timeout=CELL_TIMEOUT, kernel_name="python3", record_timing=False,
                                     coalesce_streams=True,
                                     resources={"metadata": {"path": str(ROOT)}})
    client.execute()
    outputs = [output for cell in notebook.cells if cell.cell_type == "code" for output in cell.outputs]
    assert not [o for o in outputs if o.output_type == "error"]
    html = [o for o in outputs if o.output_type == "execute_result" and "text/html" in o.get("data", {})]
    assert html and "peak axle load" in html[0]["data"]["text/html"]
    images = [o for o in outputs if "image/png" in o.get("data", {})]
    assert len(images) >= 3   # the shot's plot, the chart and the calibration, inline
    printed = "".join(o.get("text", "") for o in outputs if o.output_type == "stream")
    assert " ft " in printed and " lbf " in printed   # the imperial example
    assert "drag factor" in printed and " kg: " in printed and "+-" in printed   # calibration, predictions
    notebook.metadata.pop("widgets", None)
    nbformat.write(notebook, NOTEBOOK)


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
