"""Running sweeps in this process: the table, resuming after an interrupt, refusals before any work,
the report, and Sobol' indices of the Ishigami function through the same pipeline."""

from __future__ import annotations

import dataclasses
import json
import math
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pyarrow.dataset as ds
import pytest

from analytic.cli import main
from analytic.fast import shoot
from analytic.sweep import analyses, read_table, run_sweep, storage, sweep_from_dict
from analytic.sweep.designs import kernel_rows
from analytic.sweep.evaluate import OUTCOMES
from analytic.sweep.sweep_file import DATA_DIR

ROOT = Path(__file__).parents[1]
GRID = ('design = "paper_table3.toml"\nchunk_size = {chunk}\n[grid]\n'
        '"machine.sling_length" = {{from = "40 cm", to = "61 cm", steps = {steps}}}\n'
        '"machine.release_angle" = {{from = 30.0, to = 60.0, steps = 5}}\n')
#: The Ishigami function's indices for a = 7, b = 0.1 from its closed-form
#: variances, x uniform on [-pi, pi]^3: V = a^2/8 + b pi^4/5 + b^2 pi^8/18 + 1/2,
#: V1 = (1 + b pi^4/5)^2 / 2, V2 = a^2/8, V3 = 0, V13 = 8 b^2 pi^8/225. The
#: first-order values, 0.3139, 0.4424 and 0, are those of Saltelli et al.,
#: "Global Sensitivity Analysis: The Primer" (Wiley 2008), as quoted in
#: SALib's ``test_functions.Ishigami``.
_A, _B = 7.0, 0.1
_V = _A**2 / 8 + _B * math.pi**4 / 5 + _B**2 * math.pi**8 / 18 + 0.5
_V1, _V2, _V13 = (1 + _B * math.pi**4 / 5) ** 2 / 2, _A**2 / 8, 8 * _B**2 * math.pi**8 / 225
ISHIGAMI_S1 = (_V1 / _V, _V2 / _V, 0.0)
ISHIGAMI_ST = ((_V1 + _V13) / _V, _V2 / _V, _V13 / _V)


def sweep_file(tmp_path: Path, steps: int = 8, chunk: int = 7) -> Path:
    path = tmp_path / "sweep.toml"
    path.write_text(GRID.format(chunk=chunk, steps=steps))
    return path


def folder_state(folder: Path) -> dict:
    """Every file under ``folder`` with its inode, size and modification time (empty if absent)."""
    if not folder.exists():
        return {}
    return {str(p.relative_to(folder)): (p.stat().st_ino, p.stat().st_size, p.stat().st_mtime_ns)
            for p in folder.rglob("*")}


def test_sweep_writes_one_table_of_inputs_status_and_outcomes(tmp_path, capsys):
    out = tmp_path / "out"
    assert main(["sweep", str(sweep_file(tmp_path)), "--out", str(out), "--json", "--quiet"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert list(report)[:5] == ["shots", "chunks", "chunks_written", "ok", "seconds"]
    assert report["shots"] == 40 and report["chunks"] == 6 and report["chunks_written"] == 6
    table = ds.dataset(str(out)).to_table().sort_by("index")   # the interface: one table
    assert table.num_rows == 40 and report["ok"] == int(np.sum(table["status"].to_numpy(zero_copy_only=False) == "ok"))
    assert table.column_names[:4] == ["index", "machine.sling_length", "machine.release_angle", "status"]
    assert {"range", "release_time", "release_vx", "apex_height", "steps"} <= set(table.column_names)
    assert sorted(p.name for p in out.glob("*.parquet")) == [f"chunk-{k:06d}.parquet" for k in range(6)]
    # Each row is the shot of its design: the batch on the same rows.
    sweep = sweep_from_dict({"design": "paper_table3", "grid": {
        "machine.sling_length": {"from": "40 cm", "to": "61 cm", "steps": 8},
        "machine.release_angle": {"from": 30.0, "to": 60.0, "steps": 5}}})
    columns = {f: table[f].to_numpy() for f in sweep.fields}
    direct = shoot(kernel_rows(sweep.base, columns))
    assert np.array_equal(table["range"].to_numpy(), direct.range, equal_nan=True)
    # The same columns, of the same types, as the batch's own table (``Shots.to_arrow``).
    names = ["status", *OUTCOMES]
    assert table.select(names).combine_chunks().equals(direct.to_arrow(names)) and names == table.column_names[3:]
    assert table["machine.sling_length"].to_numpy()[0] == 0.40   # "40 cm", in the file's unit


@pytest.mark.slow   # a command in a fresh process, interrupted: about 5 s, more on a busy machine
def test_an_interrupted_sweep_resumes_writing_each_chunk_once(tmp_path):
    path, out = sweep_file(tmp_path, steps=60, chunk=3), tmp_path / "out"   # 100 chunks
    # SIGINT's default action restored in the child: pytest-xdist's workers ignore SIGINT, a child
    # inherits that, and Python then installs no KeyboardInterrupt handler (the command ran on to 0).
    process = subprocess.Popen([sys.executable, "-m", "analytic", "sweep", str(path), "--out", str(out), "--quiet"],
                               cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                               preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    deadline = time.monotonic() + 120
    while len(list(out.glob("chunk-*.parquet"))) < 2 and process.poll() is None and time.monotonic() < deadline:
        time.sleep(0.01)
    process.send_signal(signal.SIGINT)
    _, stderr = process.communicate(timeout=60)
    assert process.returncode == 130, stderr
    first = folder_state(out)
    written = sorted(name for name in first if name.startswith("chunk-"))
    assert 2 <= len(written) < 100 and "interrupted" in stderr
    assert not any(name.startswith(".") for name in first)   # no half-written chunk left behind

    result = run_sweep(sweep_from_path(path), out)
    assert result.chunks_written == 100 - len(written) and result.shots_run == 300 - 3 * len(written)
    after = folder_state(out)
    assert {name: after[name] for name in first} == first       # the first run's chunks untouched
    index = read_table(out, ["status"])["index"].to_numpy()
    assert np.array_equal(index, np.arange(300))               # every row exactly once
    assert run_sweep(sweep_from_path(path), out).chunks_written == 0


def sweep_from_path(path):
    from analytic.sweep import load_sweep

    return load_sweep(path)


@pytest.mark.parametrize("case", ["unknown-field", "bad-distribution", "zero-steps", "other-sweep", "no-scheduler"])
def test_bad_input_exits_2_naming_the_reason_and_writes_nothing(tmp_path, capsys, case):
    out = tmp_path / "out"
    path = sweep_file(tmp_path)
    extra = []
    if case == "unknown-field":
        path.write_text(path.read_text().replace("machine.sling_length", "machine.sling_lenght"))
        expected = "grid.machine.sling_lenght"
    elif case == "bad-distribution":
        path.write_text(path.read_text() + '[sample]\nn = 4\nmethod = "random"\nseed = 0\n'
                        '"projectile.mass" = {distribution = "normal", mean = 0.0456, sd = -1.0}\n')
        expected = "sample.projectile.mass.sd = -1.0: must be positive"
    elif case == "zero-steps":
        path.write_text(path.read_text().replace("steps = 5", "steps = 0"))
        expected = "grid.machine.release_angle.steps = 0"
    elif case == "other-sweep":
        assert main(["sweep", str(path), "--out", str(out), "--quiet"]) == 0
        path.write_text(path.read_text().replace("steps = 5", "steps = 6"))
        expected = "holds the results of a different sweep (differs in sweep.chunks"
    else:
        extra = ["--scheduler", "tcp://127.0.0.1:9", "--connect-timeout", "2"]
        expected = "cannot reach a Dask scheduler at 'tcp://127.0.0.1:9'"
    capsys.readouterr()
    before = folder_state(out)
    assert main(["sweep", str(path), "--out", str(out), "--quiet", *extra]) == 2
    assert expected in capsys.readouterr().err
    assert folder_state(out) == before


def test_report_writes_the_map_and_summary_and_refuses_an_unfinished_sweep(tmp_path, capsys):
    out = tmp_path / "out"
    assert main(["sweep", str(sweep_file(tmp_path)), "--out", str(out), "--quiet"]) == 0
    capsys.readouterr()
    assert main(["sweep", "--report", str(out), "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["grid"]["shape"] == [8, 5] and summary["statuses"] == {"ok": 40}
    assert (out / "_report" / "grid.png").stat().st_size > 10_000
    assert ds.dataset(str(out)).count_rows() == 40             # the report does not disturb the table
    storage.chunk_path(out, 3).unlink()
    assert main(["sweep", "--report", str(out)]) == 2
    assert "5 of 6 chunks written" in capsys.readouterr().err
    assert main(["sweep", "--report", str(tmp_path)]) == 2      # not a results folder


def test_a_map_keeps_failures_as_their_status(tmp_path):
    sweep = sweep_from_dict({"design": "paper_table3", "chunk_size": 50, "grid": {
        "machine.counterweight_mass": {"values": [0.05, 6.5]},
        "machine.release_angle": {"values": [30.0, 45.0]}}})
    run_sweep(sweep, tmp_path)
    grid = analyses.grid_map(storage.read_settings(tmp_path), read_table(tmp_path))
    assert grid.status.tolist() == [["never_fires"] * 2, ["ok"] * 2]
    assert np.isnan(grid.value[0]).all() and (grid.value[1] > 30.0).all()


def test_ishigami_sobol_indices_match_the_known_values_within_their_intervals(tmp_path, capsys):
    out = tmp_path / "ishigami"
    assert main(["sweep", str(DATA_DIR / "sweeps" / "ishigami.toml"), "--out", str(out), "--quiet"]) == 0
    capsys.readouterr()
    assert main(["sweep", "--report", str(out), "--json"]) == 0
    indices = json.loads(capsys.readouterr().out)["sensitivity"]
    for i, field in enumerate(("x1", "x2", "x3")):
        got = indices[field]
        assert abs(got["S1"] - ISHIGAMI_S1[i]) <= got["S1_conf"], (field, got, ISHIGAMI_S1[i])
        assert abs(got["ST"] - ISHIGAMI_ST[i]) <= got["ST_conf"], (field, got, ISHIGAMI_ST[i])
        assert got["ST_conf"] < 0.05       # the intervals are tight enough for the check to mean something
    assert (out / "_report" / "sensitivity.png").is_file()
    # Rows in another order (as files may be read) give the same indices: each is placed by its index.
    settings, table = storage.read_settings(out), read_table(out)
    ordered, shuffled = (analyses.sensitivity(settings, t) for t in (table, table.take(np.arange(20480)[::-1])))
    assert np.array_equal(ordered.first, shuffled.first) and np.array_equal(ordered.total, shuffled.total)
    # The bootstrap intervals are seeded: the same report each time.
    assert np.array_equal(ordered.first_conf, shuffled.first_conf)


def test_a_sweep_of_a_coefficient_from_zero_starts_at_the_ideal_machine(tmp_path, capsys):
    # A bearing of known radius with zero friction is the ideal machine's (bit for bit on the same rows).
    from analytic.design import Losses
    from analytic.design_file import default_design, save_design
    from analytic.sweep.plot import grid_figure

    ideal = default_design()
    save_design(dataclasses.replace(ideal, losses=Losses(axle_friction=0.15, axle_radius=0.0064)), tmp_path / "d.toml")
    path = tmp_path / "sweep.toml"
    path.write_text('design = "d.toml"\n[grid]\n"losses.axle_friction" = {from = 0.0, to = 0.2, steps = 5}\n')
    out = tmp_path / "out"
    assert main(["sweep", str(path), "--out", str(out), "--quiet"]) == 0, capsys.readouterr().err
    table = ds.dataset(str(out)).to_table().sort_by("index")
    assert table["status"].to_pylist() == ["ok"] * 5
    ranges = table["range"].to_numpy()
    assert ranges[0] == shoot([ideal]).range[0] and np.all(np.diff(ranges) < 0.0)
    settings = storage.read_settings(out)
    figure = grid_figure(analyses.grid_map(settings, read_table(out)), "range", settings["sweep"]["units"])
    assert figure.axes[0].get_xlabel() == "losses.axle_friction"   # dimensionless: no empty "()"


def test_the_report_gives_every_figure_its_unit_in_the_chosen_units(tmp_path, capsys):
    out = tmp_path / "out"
    assert main(["sweep", str(sweep_file(tmp_path)), "--out", str(out), "--quiet"]) == 0
    capsys.readouterr()
    assert main(["sweep", "--report", str(out), "--json"]) == 0
    best = json.loads(capsys.readouterr().out)["grid"]["best"]
    assert main(["sweep", "--report", str(out)]) == 0
    metric = next(line for line in capsys.readouterr().out.splitlines() if "best range" in line)
    assert f"best range {best['value']:.6g} m at" in metric
    assert main(["sweep", "--report", str(out), "--units", "imperial", "--json"]) == 0
    imperial_json = json.loads(capsys.readouterr().out)
    assert imperial_json["grid"]["best"] == best and imperial_json["units"]["json"].startswith("SI")
    assert main(["sweep", "--report", str(out), "--units", "imperial"]) == 0
    imperial = next(line for line in capsys.readouterr().out.splitlines() if "best range" in line)
    assert f"best range {best['value'] / 0.3048:.6g} ft at" in imperial   # 1 ft = 0.3048 m by definition
