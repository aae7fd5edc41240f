"""One chunk of a sweep, computed: its inputs, then the fast path's batch (or the test function) on them.

``chunk_table(sweep, chunk)`` is the whole unit of work an executor runs,
in this process or on a Dask worker: a function of ``(sweep, chunk)``
alone, so the same chunk gives the same numbers wherever it runs.
"""

from __future__ import annotations

import numpy as np

from analytic.result import SHOT_COLUMNS, Status
from analytic.sweep.designs import kernel_rows
from analytic.sweep.expand import chunk_inputs
from analytic.sweep.spec import Sweep

#: The outcome columns of a trebuchet sweep, after the inputs and ``status``: the table of
#: shots' columns (``analytic.result.SHOT_COLUMNS``) but the peak loads, which a sweep does not seek.
OUTCOMES = tuple(name for name in SHOT_COLUMNS if name != "status" and not name.startswith("peak_"))


def chunk_table(sweep: Sweep, chunk: int, threads: int | None = None) -> dict[str, np.ndarray]:
    """Chunk ``chunk`` of ``sweep`` as columns, each of shape (m,), its batch on ``threads``
    threads (default: every processor this process may use).

    Returns
    -------
    dict
        ``index`` (int64, the rows' positions in the sweep), each varied field
        (file units), ``status`` (str) and the outcomes: ``OUTCOMES`` for a
        trebuchet (SI; NaN where a shot did not get there), ``y`` for a test function.
    """
    index, inputs = chunk_inputs(sweep, chunk)
    table = {"index": index, **inputs}
    if sweep.base.kind == "function":
        from SALib.test_functions import Ishigami

        table["status"] = np.full(len(index), Status.OK.value)
        table["y"] = Ishigami.evaluate(np.column_stack([inputs[f] for f in sweep.fields]))
        return table
    from analytic import fast

    # The table holds no peak loads, so the batch does not look for them.
    shots = fast.shoot(kernel_rows(sweep.base, inputs), threads=threads, loads=False)
    table.update(shots.columns(("status", *OUTCOMES)))
    return table


def model_identity(sweep: Sweep) -> dict:
    """What, besides the sweep, decides its numbers: the model's sources and the integrator's tolerances.

    Stored with the results, so that chunks computed by another version of
    the model are never mixed with these.
    """
    if sweep.base.kind == "function":
        from importlib.metadata import version

        return {"function": sweep.base.name, "salib": version("SALib")}
    from analytic.fast import compiled
    from analytic.limits import DEFAULT_ATOL, DEFAULT_RTOL

    return {"sources_sha256": compiled.source_fingerprint(compiled.SOURCES), "rtol": DEFAULT_RTOL,
            "atol": DEFAULT_ATOL}
