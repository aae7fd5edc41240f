"""Sweeps on a real 2-worker Dask LocalCluster: the same table bit for bit as in this process, the
kernel loaded once per worker, and a worker killed mid-sweep costing only its chunks."""

from __future__ import annotations

import os
import signal

import numpy as np
import pyarrow as pa
import pytest

from analytic.sweep import OnDask, read_table, run_sweep, storage, sweep_from_dict

#: Starting two spawned workers (each imports numba and loads the kernel)
#: takes 5 to 20 s on two busy cores; one cluster serves the whole module, so under pytest-xdist
#: (``make test``: ``--dist loadgroup``) the module runs whole on one worker, in file order (its
#: last test kills one of the cluster's workers).
pytestmark = [pytest.mark.slow, pytest.mark.xdist_group("sweep-dask")]

GRID_WITH_FAILURES = {"design": "paper_table3", "chunk_size": 40, "grid": {
    "machine.counterweight_mass": {"from": 0.05, "to": 6.5, "steps": 12},
    "machine.release_angle": {"from": -60.0, "to": 85.0, "steps": 20}}}
SOBOL_AROUND_THE_DESIGN = {"design": "paper_table3", "chunk_size": 50, "sample": {"n": 32, "method": "sobol", "seed": 4},
                           "uncertain": {"machine.release_angle": {"distribution": "normal", "sd": "2 deg"},
                                         "environment.wind_speed": {"distribution": "uniform", "half_width": 2.0},
                                         "projectile.mass": {"distribution": "normal", "sd": "0.5 g"}}}


@pytest.fixture(scope="module")
def cluster():
    with OnDask.local(2) as executor:
        yield executor


def assert_identical(left: pa.Table, right: pa.Table) -> None:
    """Same columns, same values bit for bit (NaN where NaN)."""
    assert left.column_names == right.column_names
    for name in left.column_names:
        a, b = left[name].to_numpy(zero_copy_only=False), right[name].to_numpy(zero_copy_only=False)
        if a.dtype == np.float64:
            a, b = a.view(np.int64), b.view(np.int64)
        assert np.array_equal(a, b), name


def test_each_worker_loads_the_kernel_once_as_it_starts(cluster):
    def loaded():
        from analytic import fast

        return fast._compile_seconds is not None

    # Before any chunk ran: the worker plugin loaded it.
    assert cluster.client.run(loaded) == {address: True for address in cluster.client.nthreads()}
    assert len(cluster.client.nthreads()) == 2 and cluster.threads_per_chunk >= 1


@pytest.mark.parametrize("data", [GRID_WITH_FAILURES, SOBOL_AROUND_THE_DESIGN], ids=["grid", "sobol"])
def test_the_cluster_writes_the_same_table_bit_for_bit(cluster, tmp_path, data):
    sweep = sweep_from_dict(data)
    here, there = tmp_path / "in-process", tmp_path / "cluster"
    run_sweep(sweep, here)
    result = run_sweep(sweep, there, cluster)
    assert result.chunks_written == sweep.chunks and result.executor.startswith("local cluster")
    assert_identical(read_table(here), read_table(there))
    assert {"ok", "never_fires"} <= set(read_table(here)["status"].to_pylist()) or "sample" in data


def test_the_benchmark_s_throughput_part_compares_the_executors_on_one_sweep(cluster):
    from benchmarks.sweep import throughput

    figures = throughput(shots=600, chunk_size=100, repeat=1, cluster=cluster)
    assert figures["sweep_tables_identical"] and figures["sweep_chunks"] == 6
    assert figures["sweep_cluster_ratio"] == pytest.approx(
        figures["sweep_cluster_shots_per_s"] / figures["sweep_in_process_shots_per_s"])
    assert all(50 < mb < 4000 for mb in figures["sweep_worker_peak_rss_mb"])


def test_the_command_runs_on_a_running_scheduler_and_a_worker_refuses_another_model(cluster, tmp_path, capsys):
    from analytic.cli import main
    from analytic.sweep.worker import shoot_chunk

    path = tmp_path / "sweep.toml"
    path.write_text('design = "paper_table3"\nchunk_size = 10\n[grid]\n'
                    '"machine.release_angle" = {from = 30, to = 60, steps = 25}\n')
    address = cluster.cluster.scheduler_address
    assert main(["sweep", str(path), "--out", str(tmp_path / "remote"), "--scheduler", address, "--json",
                 "--quiet"]) == 0
    assert '"chunks_written": 3' in capsys.readouterr().out
    assert main(["sweep", str(path), "--out", str(tmp_path / "here"), "--quiet"]) == 0
    assert_identical(read_table(tmp_path / "here"), read_table(tmp_path / "remote"))
    sweep = sweep_from_dict({"design": "paper_table3", "grid": {"machine.release_angle": {"values": [40.0]}}})
    with pytest.raises(RuntimeError, match="another version of the model"):
        cluster.client.submit(shoot_chunk, sweep, 0, 1, {"sources_sha256": "0" * 64}).result()


# Last: it kills one of the module's workers (its nanny starts another).
def test_a_worker_killed_mid_sweep_costs_only_its_chunks(cluster, tmp_path):
    sweep = sweep_from_dict({**GRID_WITH_FAILURES, "chunk_size": 12})     # 20 chunks
    pids = cluster.client.run(os.getpid)
    written, killed = [], []

    def kill_once(chunk: int) -> None:
        written.append(chunk)
        if not killed:
            victim = next(iter(pids.values()))
            os.kill(victim, signal.SIGKILL)
            killed.append(victim)

    result = run_sweep(sweep, tmp_path / "cluster", cluster, on_chunk=kill_once)
    assert killed and killed[0] not in cluster.client.run(os.getpid).values()
    assert sorted(written) == list(range(sweep.chunks)) and result.chunks_written == sweep.chunks
    assert storage.written_chunks(tmp_path / "cluster") == set(range(sweep.chunks))
    run_sweep(sweep, tmp_path / "in-process")
    assert_identical(read_table(tmp_path / "in-process"), read_table(tmp_path / "cluster"))
