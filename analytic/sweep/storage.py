"""Where a sweep's results live: one Parquet file per chunk, and the sweep's settings beside them.

``DIR/chunk-000012.parquet`` holds chunk 12 (its ``index`` column gives each
row's place in the sweep); ``DIR/_sweep.json`` holds the settings that decide
every number (the sweep, the model's sources, the tolerances). Names that
start with ``_`` or ``.`` are skipped by ``pyarrow.dataset.dataset(DIR)``,
which reads the chunks as one table. A chunk is written to a hidden file
and renamed into place, so a chunk file exists only once it is complete:
an interrupted sweep resumes by skipping the chunks whose files exist.
"""

from __future__ import annotations

import json
import os
import re
from pathlib import Path

import numpy as np

from analytic.design import DesignError
from analytic.result import arrow_table

SETTINGS_NAME = "_sweep.json"
#: Where ``--report`` writes unless told otherwise (skipped by pyarrow's dataset discovery).
REPORT_NAME = "_report"
#: Version of this layout; a folder of another version is refused, not misread (2: the chunks hold
#: the ``launch_angle`` column).
FORMAT = 2
#: The settings that decide a sweep's numbers (its name does not).
IDENTITY = ("format", "sweep", "model")
_CHUNK = re.compile(r"chunk-(\d{6,})\.parquet")


def chunk_path(out: Path, chunk: int) -> Path:
    return Path(out) / f"chunk-{chunk:06d}.parquet"


def settings_of(sweep) -> dict:
    """The settings stored with a sweep's results (JSON-ready): its name, its description and the model's
    identity; all but the name must match for a folder's chunks to be resumed (``IDENTITY``)."""
    from analytic.sweep.evaluate import model_identity

    return json.loads(json.dumps({"format": FORMAT, "name": sweep.name, "sweep": sweep.describe(),
                                  "model": model_identity(sweep)}))


def check_folder(out: str | Path, settings: dict) -> set[int]:
    """The chunks of this sweep already written in ``out``; writes nothing.

    A missing or empty folder has none. A folder that holds a different
    sweep (or anything that is not a sweep's results) is refused.

    Raises
    ------
    DesignError
        field ``--out``, naming the folder and what differs.
    """
    out = Path(out)
    if not out.exists():
        return set()
    if not out.is_dir():
        raise DesignError("--out", str(out), "is a file, not a folder")
    stored = out / SETTINGS_NAME
    if not stored.is_file():
        if any(out.iterdir()):
            raise DesignError("--out", str(out), f"holds files but no {SETTINGS_NAME}: not a sweep's results; "
                                                 f"give an empty or new folder")
        return set()
    old = read_settings(out)
    differences = _differences({key: old.get(key) for key in IDENTITY}, {key: settings[key] for key in IDENTITY})
    if differences:
        raise DesignError("--out", str(out), f"holds the results of a different sweep (differs in "
                                             f"{', '.join(differences[:6])}{', ...' if len(differences) > 6 else ''}); "
                                             f"give another folder, or delete this one to start again")
    return written_chunks(out)


def read_settings(out: str | Path) -> dict:
    """The settings stored in a results folder."""
    path = Path(out) / SETTINGS_NAME
    try:
        return json.loads(path.read_text())
    except (OSError, ValueError) as error:
        raise DesignError("results", str(out), f"{SETTINGS_NAME} cannot be read: {error}") from None


def _differences(old, new, where: str = "") -> list[str]:
    """Dotted places where two JSON values differ."""
    if isinstance(old, dict) and isinstance(new, dict):
        found = []
        for key in sorted(set(old) | set(new), key=str):
            found += _differences(old.get(key), new.get(key), f"{where}.{key}" if where else str(key))
        return found
    return [] if old == new else [where or "settings"]


def create(out: str | Path, settings: dict) -> None:
    """Make the results folder and store the settings in it (kept if already there)."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    if not (out / SETTINGS_NAME).exists():
        _write_atomically(out / SETTINGS_NAME, lambda tmp: tmp.write_text(json.dumps(settings, indent=1)))


def written_chunks(out: str | Path) -> set[int]:
    """Numbers of the chunk files present in ``out``."""
    return {int(match[1]) for path in Path(out).iterdir() if (match := _CHUNK.fullmatch(path.name))}


def write_chunk(out: str | Path, chunk: int, table: dict[str, np.ndarray]) -> None:
    """Write one chunk's columns as its Parquet file, atomically (complete or absent)."""
    import pyarrow.parquet as pq

    arrays = arrow_table(table)   # the status as a dictionary, as Shots.to_arrow gives it
    _write_atomically(chunk_path(out, chunk), lambda tmp: pq.write_table(arrays, tmp, use_dictionary=["status"]))


def _write_atomically(path: Path, write) -> None:
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    try:
        write(tmp)
        os.replace(tmp, path)
    finally:
        tmp.unlink(missing_ok=True)


def read_table(out: str | Path, columns: list[str] | None = None, ordered: bool = True):
    """The whole sweep as one ``pyarrow.Table`` (``columns``: only these, plus ``index``).

    ``ordered``: sort the rows by ``index``; without it they come in whatever
    order the files are read, and the table is not copied to sort it.
    """
    import pyarrow.dataset as ds

    wanted = None if columns is None else ["index", *[c for c in columns if c != "index"]]
    table = ds.dataset(str(out), format="parquet").to_table(columns=wanted)
    return table.sort_by("index") if ordered else table


def tables_identical(left, right) -> bool:
    """Whether two results tables have the same columns and the same values bit for bit (NaN where NaN)."""
    if left.column_names != right.column_names or left.num_rows != right.num_rows:
        return False
    for name in left.column_names:
        a, b = (table[name].to_numpy(zero_copy_only=False) for table in (left, right))
        if a.dtype == np.float64:
            a, b = a.view(np.int64), b.view(np.int64)
        if not np.array_equal(a, b):
            return False
    return True
