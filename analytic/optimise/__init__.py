"""The design optimiser: maximise range over the paper's design variables within its size limits.

One entry point, ``optimise(problem)``, returns an ``Optimisation``; the
problem (what may vary, the limits, the problem file) is
``analytic.design_space``'s, shared with the sweeps. Inside: ``constraints``
(the limits, on the machine at rest), ``evaluate`` (shooting candidates on
either path), ``search`` (differential evolution, then SLSQP), ``kkt`` (the
first-order check), ``robust`` (release-angle scatter), ``sensitivity``
(scans through the optimum), ``report`` and ``plot`` (text and figures), and
``cli`` (``python -m analytic optimise``).
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from analytic.design_file import default_design
from analytic.optimise.evaluate import FAILURE_RANGE, FAST, Evaluator
from analytic.design_space import Problem, bolted, default_problem, load_problem, variables_of
from analytic.optimise.report import PAPER_LABEL, START_LABEL
from analytic.optimise.robust import DEFAULT_NODES, Scatter, release_scatter
from analytic.optimise.search import Optimum, Settings, maximise
from analytic.optimise.sensitivity import Sensitivity, scan

#: Why a problem under the ideal release rule has no robust variant.
IDEAL_NO_SCATTER = "release.rule 'ideal' finds each design's release itself: there is no set release angle to scatter"

__all__ = ["Optimisation", "Problem", "Settings", "default_problem", "load_problem", "optimise"]


@dataclass(frozen=True)
class Optimisation:
    """The result of ``optimise``: the optimum, its robust variant, the paper's design beside them.

    Attributes
    ----------
    problem : the problem optimised.
    optima : ``"optimum"`` -> its ``Optimum``; with a release-angle scatter also
        ``"robust optimum"`` (the expected range maximised).
    paper : (6,) the paper's Table III design variables, m and rad.
    ranges : ``PAPER_LABEL`` and each label of ``optima`` -> its range at the
        final integrator tolerance, m.
    scatter : the release-angle scatter of the robust variant, or ``None``.
    node_ranges : with a scatter, the same labels -> (n_nodes,) ranges at its
        quadrature nodes, m; else ``None``.
    peaks : the same labels -> their peak loads (``analytic.result.PEAK_NAMES`` -> N or m/s^2;
        empty for a design that does not throw).
    sensitivity : the range along each free variable through the optimum.
    path : ``"fast"`` or ``"reference"``, how the shots were simulated.
    seconds : wall time.
    compared : the label of ``paper`` in ``ranges`` and ``peaks``: ``PAPER_LABEL``, or
        ``START_LABEL`` when the search started from a design (``optimise(start=...)``), which
        ``paper`` then holds.
    """

    problem: Problem
    optima: dict[str, Optimum]
    paper: np.ndarray
    ranges: dict[str, float]
    scatter: Scatter | None
    node_ranges: dict[str, np.ndarray] | None
    peaks: dict[str, dict[str, float]]
    sensitivity: Sensitivity
    path: str
    seconds: float
    compared: str = PAPER_LABEL

    @property
    def optimum(self) -> Optimum:
        """The nominal optimum (the range maximised)."""
        return self.optima["optimum"]


def optimise(problem: Problem, *, seed: int = 0, robust_sigma: float | None = None,
             nodes: int = DEFAULT_NODES, path: str = FAST, workers: int | None = None,
             progress: bool = False, start: np.ndarray | None = None,
             settings: Settings | None = None, check: Callable[[], None] | None = None) -> Optimisation:
    """Maximise the range over the problem's free variables, and everything the report shows.

    The global stage (differential evolution) warm-starts the local one
    (SLSQP); the first-order (KKT) conditions are checked at the optimum. With
    ``robust_sigma`` the expected range under a normal release-angle scatter is
    then maximised too, from the nominal optimum. The paper's Table III design
    is shot under the same problem for comparison, and the range is scanned
    along each free variable through the optimum.

    Parameters
    ----------
    problem : Problem
        What may vary, what is fixed and the size limits (``load_problem``,
        ``default_problem``).
    seed : int
        Seeds the global stage; the same seed gives the same optimum.
    robust_sigma : float, optional
        Standard deviation of the release-angle scatter, rad, > 0.
    nodes : int
        Gauss-Hermite nodes of the scatter's expectation.
    path : {"fast", "reference"}
        Shots compiled and batched on threads, or the reference simulator in
        worker processes (``evaluate.Evaluator``; the reference path spawns
        processes, so a script calling it needs ``if __name__ == "__main__":``).
    workers : int, optional
        Threads (fast path) or processes (reference path) shooting at once.
    progress : bool
        Show progress bars (tqdm, on stderr).
    start : (6,) or (n,), optional
        A design the search starts from (in the global stage's first population; m and rad), shot
        beside the optimum instead of the paper's design, under ``START_LABEL``: a problem around a
        design (``analytic.optimise.around``) starts from that design, and ends on one at least as
        good when it meets the problem's limits.
    settings : Settings, optional
        The search's budget (``search.Settings``); default ``Settings(seed=seed)``.
    check : callable, optional
        Called before every batch of shots (``evaluate.Evaluator``); what it raises ends the
        optimisation there and is raised again (the workbench stops a cancelled job so).

    Returns
    -------
    Optimisation

    Raises
    ------
    ValueError
        For a ``robust_sigma`` that is not a positive angle, fewer than one
        node, an unknown path or fewer than one worker; or a ``robust_sigma`` with a
        problem that limits or minimises loads (not offered: the loads are the
        nominal shot's), or with a problem under the ideal release rule (no release angle to scatter).
    """
    if robust_sigma is not None and not (math.isfinite(robust_sigma) and robust_sigma > 0.0):
        raise ValueError(f"robust_sigma = {robust_sigma!r}: must be a positive angle in rad")
    if robust_sigma is not None and problem.outcome_constraints:
        raise ValueError("robust_sigma: a problem with [loads] is optimised for the nominal shot only")
    if robust_sigma is not None and problem.release_rule == "ideal":
        raise ValueError(f"robust_sigma: {IDEAL_NO_SCATTER}")
    began = time.perf_counter()
    settings = Settings(seed=seed) if settings is None else settings
    scatter = None if robust_sigma is None else release_scatter(robust_sigma, nodes)
    compared = PAPER_LABEL if start is None else START_LABEL
    if start is not None:
        paper = problem.complete(np.asarray(start, dtype=float))
    else:
        paper = problem.complete(variables_of(default_design().machine))
        if problem.kind != "hinged":   # the paper's frame and arms, its counterweight bolted on
            paper = bolted(paper)
    with Evaluator(problem, path=path, workers=workers, check=check) as evaluator:
        optima = {"optimum": maximise(problem, evaluator, settings, progress=progress, include=start)}
        if scatter is not None:
            optima["robust optimum"] = maximise(problem, evaluator, settings, scatter=scatter,
                                                start=optima["optimum"].values, progress=progress)
        designs = {compared: paper} | {label: o.values for label, o in optima.items()}
        throws = evaluator.throws(np.array(list(designs.values())), settings.final_tolerance, loads=True)
        ranges = {label: (FAILURE_RANGE if t.range is None else t.range) for label, t in zip(designs, throws, strict=True)}
        peaks = {label: t.loads for label, t in zip(designs, throws, strict=True)}
        node_ranges = None if scatter is None else dict(zip(designs, evaluator.node_ranges(
            list(designs.values()), settings.final_tolerance, scatter), strict=True))
        sensitivity = scan(evaluator, problem, optima["optimum"].values, optima["optimum"].score,
                           settings.search_tolerance)
    return Optimisation(problem=problem, optima=optima, paper=paper, ranges=ranges, scatter=scatter,
                        node_ranges=node_ranges, peaks=peaks, sensitivity=sensitivity, path=evaluator.path,
                        seconds=time.perf_counter() - began, compared=compared)
