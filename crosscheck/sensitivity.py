"""How far a design's own outcome moves when its inputs move by a few parts in 1e9: the cross-check's
measure of a case too sensitive to compare.

Two integrations of one machine part ways where the machine itself amplifies
a tiny difference: a long swing that winds the sling round the arm, a release
whose condition is met at a grazing angle while the speed changes fast. There a
difference between the analytic model and the engine says nothing about either
model. The cross-check tells such a case from a disagreement by measuring it:
the analytic model's reference path (``analytic.reference``) shoots the design
again with every numeric input multiplied by ``1 + e``, ``|e|`` at most
``tolerances.SENSITIVITY_PERTURBATION`` and drawn afresh for each input and
each of ``tolerances.SENSITIVITY_RUNS`` runs, and the spread of each compared
quantity over those runs and the unperturbed one is the case's sensitivity.
A quantity whose spread alone is larger than its tolerance cannot be compared.

A multiplier keeps every zero a zero and every sign its sign: a perturbed
design is the same kind of machine with the same losses switched on, and it
passes the same checks.
"""

from __future__ import annotations

import dataclasses
import math
import zlib

import numpy as np

from analytic.design import Design, DesignError
from analytic.reference import simulate
from analytic.result import Shot
from crosscheck import tolerances as tol

#: The design's tables whose numbers are perturbed (every float field of each).
_TABLES = ("machine", "projectile", "environment", "base", "losses")


def perturbed(design: Design, size: float, rng: np.random.Generator) -> Design:
    """``design`` with each of its numeric inputs multiplied by ``1 + e``, ``e`` uniform in
    ``[-size, size]`` (drawn from ``rng``); the choices (kind, rule, drag model) and zeros kept."""
    tables = {}
    for table in _TABLES:
        part = getattr(design, table)
        changes = {f.name: value * (1.0 + size * rng.uniform(-1.0, 1.0))
                   for f in dataclasses.fields(part)
                   if isinstance(value := getattr(part, f.name), float) and value != 0.0 and math.isfinite(value)}
        tables[table] = dataclasses.replace(part, **changes)
    return dataclasses.replace(design, **tables)


def summary(design: Design) -> Shot:
    """The reference path's summary with everything the cross-check compares: the peak loads, the
    work each loss took and a rolling frame's place at landing."""
    return simulate(design, histories=False, loads=True, after_release=True)


def spread(design: Design, compare_rows, *, runs: int = tol.SENSITIVITY_RUNS,
           size: float = tol.SENSITIVITY_PERTURBATION) -> dict[str, float]:
    """The sensitivity of each compared quantity of ``design``: the largest difference between
    the reference path's shot of ``design`` and of ``runs`` perturbed copies (``perturbed``), in the
    quantity's own unit (SI, radians).

    Parameters
    ----------
    design : the case's design.
    compare_rows : ``(shot_a, shot_b) -> rows``, the cross-check's own comparison
        (``crosscheck.comparison.compare_shots``), so that the quantities are the ones compared.
    runs, size : how many perturbed copies, and the largest relative change of an input.

    Returns
    -------
    dict
        Quantity name to spread. ``"outcome"`` is 1.0 when a perturbed copy ends in another
        status than the design (0.0 otherwise); a quantity that only some of the runs reach
        (one copy thrown, another not) is left out: the outcome says it.

    The draws are seeded by the design's name, so a case's sensitivity is the same at every run.
    """
    rng = np.random.default_rng(zlib.crc32(design.name.encode()))
    base = summary(design)
    largest: dict[str, float] = {}
    counts: dict[str, int] = {}
    done = 0
    for _ in range(runs):
        try:
            other = summary(perturbed(design, size, rng))
        except DesignError:   # a value on the very edge of its bound: that copy is not a design
            continue
        done += 1
        for row in compare_rows(base, other):
            if row.quantity == "outcome":
                largest["outcome"] = max(largest.get("outcome", 0.0), 0.0 if row.ok else 1.0)
            elif row.difference is not None and math.isfinite(row.difference):
                largest[row.quantity] = max(largest.get(row.quantity, 0.0), abs(row.difference))
                counts[row.quantity] = counts.get(row.quantity, 0) + 1
    return {name: value for name, value in largest.items() if name == "outcome" or counts[name] == done}
