"""One chunk of a sweep, computed: its inputs, then the fast path's batch (or the test function) on them.

``chunk_table(sweep, chunk)`` is the whole unit of work an executor runs,
in this process or on a Dask worker: a function of ``(sweep, chunk)``
alone, so the same chunk gives the same numbers wherever it runs.
"""

from __future__ import annotations

import numpy as np

from analytic.design import Design
from analytic.design_file import design_from_dict
from analytic.result import SHOT_COLUMNS, Status
from analytic.data.strength import bending_stress
from analytic.sweep.designs import kernel_rows
from analytic.sweep.expand import chunk_inputs
from analytic.sweep.spec import Sweep, design_data

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
        trebuchet (SI; NaN where a shot did not get there), and ``breaking_columns``' for a
        base design with an arm's section or a projectile's limit; ``y`` for a test function.
    """
    index, inputs = chunk_inputs(sweep, chunk)
    table = {"index": index, **inputs}
    if sweep.base.kind == "function":
        from SALib.test_functions import Ishigami

        table["status"] = np.full(len(index), Status.OK.value)
        table["y"] = Ishigami.evaluate(np.column_stack([inputs[f] for f in sweep.fields]))
        return table
    from analytic import fast

    # The table holds no peak loads, so the batch does not look for them unless it says what they break.
    design = design_from_dict(design_data(sweep.base, {field: float(column[0]) for field, column in inputs.items()}))
    breaking = design.machine.arm_section is not None or design.projectile.acceleration_limit is not None
    shots = fast.shoot(kernel_rows(sweep.base, inputs), threads=threads, loads=breaking)
    table.update(shots.columns(("status", *OUTCOMES)))
    if breaking:
        table.update(breaking_columns(design, inputs, shots.peak_arm_bending_moment,
                                      shots.peak_projectile_acceleration))
    return table


def breaking_columns(design: Design, inputs: dict[str, np.ndarray], moment: np.ndarray,
                     acceleration: np.ndarray) -> dict[str, np.ndarray]:
    """Will it break, row by row: ``peak_arm_stress`` (Pa) and ``arm_safety_factor`` where the sweep's
    ``design`` (its base, any row of it) has an arm's section (the factor NaN without a strength), ``projectile_survives``
    (1.0 or 0.0) where its projectile has a limit; NaN where a shot did not get there.

    Parameters
    ----------
    inputs : the chunk's varied fields, each (m,), file units (the beam's width and depth may vary).
    moment, acceleration : (m,) the peak arm bending moment (N m) and projectile acceleration (m/s^2).
    """
    section, limit = design.machine.arm_section, design.projectile.acceleration_limit
    columns = {}
    if section is not None:
        width = inputs.get("machine.arm_beam.width", section.width)
        depth = inputs.get("machine.arm_beam.depth", section.depth)
        columns["peak_arm_stress"] = bending_stress(moment, width, depth)
        strength = section.bending_strength
        columns["arm_safety_factor"] = (np.full(len(moment), np.nan) if strength is None
                                        else strength / columns["peak_arm_stress"])
    if limit is not None:
        columns["projectile_survives"] = np.where(np.isnan(acceleration), np.nan, (acceleration <= limit) * 1.0)
    return columns


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
