"""Run the example notebook (``docs/builders.ipynb``) from top to bottom and store it with its outputs.

``make notebook`` runs this after a change that alters what the notebook prints or draws: the
repository's page and the documentation site (which does not execute it) show the stored
outputs. ``tests/test_analytic_notebook.py`` runs the same ``execute``, checks the outputs and
stores them too.
"""

from __future__ import annotations

import sys
from pathlib import Path

ROOT = Path(__file__).parents[1]
NOTEBOOK = ROOT / "docs" / "builders.ipynb"
#: Seconds a cell may take: the optimiser's cell is the longest (a few seconds on the fast
#: path once compiled; a cold numba cache adds the compile, about a minute on two cores).
CELL_TIMEOUT = 900


def execute(path: Path = NOTEBOOK):
    """The notebook at ``path`` executed in a real kernel from the repository's top folder (the
    kernel imports this checkout), with its outputs and without run times."""
    import nbclient
    import nbformat

    notebook = nbformat.read(path, as_version=4)
    client = nbclient.NotebookClient(notebook, timeout=CELL_TIMEOUT, kernel_name="python3", record_timing=False,
                                     coalesce_streams=True, resources={"metadata": {"path": str(ROOT)}})
    client.execute()
    notebook.metadata.pop("widgets", None)
    return notebook


def main() -> int:
    import nbformat

    nbformat.write(execute(), NOTEBOOK)
    print(f"stored {NOTEBOOK.relative_to(ROOT)} with its outputs")
    return 0


if __name__ == "__main__":
    sys.exit(main())
