"""Design sweeps and uncertainty at scale: grids, samples and uncertain inputs, shot in chunks.

``python -m analytic sweep SWEEP.toml --out DIR [--workers N | --scheduler ADDRESS]``;
from Python::

    from analytic.sweep import load_sweep, run_sweep, read_table, OnDask

    sweep = load_sweep("grid.toml")              # checked before any work
    run_sweep(sweep, "out/grid")                 # in-process, every core
    with OnDask.local(2) as cluster:             # or OnDask.connect("tcp://host:8786")
        run_sweep(sweep, "out/grid", cluster)    # resumes: written chunks are kept
    table = read_table("out/grid")               # a pyarrow Table in row order

The layers, each its own module: ``spec`` (what a sweep is), ``sweep_file``
(sweep files, checked) and ``distributions``; ``expand`` (a chunk's inputs) and ``designs`` (its kernel
rows); ``evaluate`` (a chunk computed); ``executors`` and ``worker``;
``storage`` (Parquet per chunk, settings beside); ``run``; ``analyses``,
``plot`` and ``report`` (``--report``); ``cli``.
"""

from __future__ import annotations

from analytic.sweep.executors import ExecutorError, InProcess, OnDask
from analytic.sweep.run import SweepRun, run_sweep
from analytic.sweep.spec import Sweep
from analytic.sweep.storage import read_table
from analytic.sweep.sweep_file import load_sweep, sweep_from_dict

__all__ = ["ExecutorError", "InProcess", "OnDask", "Sweep", "SweepRun", "load_sweep", "read_table",
           "run_sweep", "sweep_from_dict"]
