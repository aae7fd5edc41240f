"""Sweep throughput: one sweep end to end in this process and on a Dask ``LocalCluster``."""

from __future__ import annotations

import resource
import shutil
import tempfile
import time
from pathlib import Path

from analytic.design_space import VARIABLE_NAMES
from analytic.sweep import OnDask, read_table, run_sweep, sweep_from_dict
from analytic.sweep.spec import DEFAULT_CHUNK_SIZE
from analytic.sweep.storage import tables_identical


def throughput_sweep(shots: int, chunk_size: int, seed: int = 0):
    """The throughput part's sweep: ``shots`` designs drawn at random over the paper's problem box."""
    return sweep_from_dict({"name": "throughput", "problem": "paper_problem", "chunk_size": chunk_size,
                            "sample": {"n": shots, "method": "random", "seed": seed,
                                       **{f"machine.{name}": {} for name in VARIABLE_NAMES}}})


def throughput(shots: int = 40_960, chunk_size: int | None = None, workers: int = 2, repeat: int = 2,
               cluster=None) -> dict:
    """One sweep end to end in this process and on a ``LocalCluster`` of ``workers``: shots/s and their ratio.

    Each executor's time is the best of ``repeat`` runs into fresh folders
    (Parquet written, as a user's sweep); the cluster's start-up is timed
    apart. ``cluster``: an ``OnDask`` to use instead of starting one.
    """
    sweep = throughput_sweep(shots, chunk_size or DEFAULT_CHUNK_SIZE)
    with tempfile.TemporaryDirectory(prefix="sweep-bench-") as folder:
        def best(executor, label: str) -> float:
            times = []
            for i in range(repeat):
                out = Path(folder) / f"{label}-{i}"
                times.append(run_sweep(sweep, out, executor).seconds)
                if i:
                    shutil.rmtree(out)
            return min(times)

        in_process_s = best(None, "in-process")
        began = time.perf_counter()
        owned = cluster is None
        cluster = OnDask.local(workers) if owned else cluster
        start_s = time.perf_counter() - began
        try:
            cluster_s = best(cluster, "cluster")
            peak_mb = cluster.client.run(lambda: resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024)
        finally:
            if owned:
                cluster.close()
        identical = tables_identical(read_table(Path(folder) / "in-process-0"), read_table(Path(folder) / "cluster-0"))
        parquet_bytes = sum(p.stat().st_size for p in (Path(folder) / "in-process-0").glob("*.parquet"))
    return {"sweep_shots": sweep.shots, "sweep_chunk_size": sweep.chunk_size, "sweep_chunks": sweep.chunks,
            "sweep_in_process_shots_per_s": sweep.shots / in_process_s,
            "sweep_cluster_shots_per_s": sweep.shots / cluster_s,
            "sweep_cluster_ratio": in_process_s / cluster_s, "sweep_cluster_workers": workers,
            "sweep_cluster_start_s": start_s if owned else None,
            "sweep_worker_peak_rss_mb": sorted(peak_mb.values()),
            "sweep_parquet_bytes_per_shot": parquet_bytes / sweep.shots,
            "sweep_tables_identical": bool(identical)}
