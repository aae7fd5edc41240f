"""A measured track's file: time and position of one tracked point, as a video-analysis tool exports it.

Any delimited text with a header row naming ``t``, ``x`` and ``y`` (in any
order, any case, among other columns) and one row per frame below it::

    t,x,y
    0.000,412,633
    0.004,415,631

Tracker's table export (Open Source Physics: File > Export > Data) reads as
it is: the lines above the header (the track's name, ``#multi:``) are
skipped, the delimiter is the header's own (tab, comma, semicolon or
spaces), other columns (``v_{x}``, ``a``, ...) are ignored, a frame whose
``x`` and ``y`` are both empty (a step not marked) is skipped, and with a
semicolon, tab or space delimiter a decimal comma (``0,004``) is read as a
decimal point. What cannot be read so is refused, naming the file, the line
and the reason: no header row, a header naming ``t``, ``x`` or ``y`` twice (a
several-track export: export one track), a cell that is not a number, a
time that does not increase, too few points.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

#: Delimiters tried on a header row, in order; None is any run of spaces.
DELIMITERS = ("\t", ",", ";", None)
#: The columns a track needs.
COLUMNS = ("t", "x", "y")
#: Fewest points a track may hold: its time origin is fitted, and a track of a few points
#: fixes little else; a real one holds tens to hundreds of frames.
MIN_POINTS = 5
_NUMBER = re.compile(r"^[+-]?(\d+(\.\d*)?|\.\d+)([eE][+-]?\d+)?$")


class TrackFileError(ValueError):
    """A track file that cannot be read: ``file, line N: reason`` (line 0: the file as a whole)."""

    def __init__(self, path: Path, line: int, reason: str):
        self.path, self.line, self.reason = path, line, reason
        super().__init__(f"{path}{f', line {line}' if line else ''}: {reason}")


@dataclass(frozen=True)
class TrackTable:
    """The numbers of a track file, as written.

    Attributes
    ----------
    path : the file.
    t : (n,) times, strictly increasing, in the file's unit (s).
    xy : (n, 2) positions, in the file's unit.
    lines : (n,) the line of each point in the file, from 1.
    skipped : frames left out because their x and y are both empty.
    """

    path: Path
    t: np.ndarray
    xy: np.ndarray
    lines: np.ndarray
    skipped: int


def _cells(line: str, delimiter: str | None) -> list[str]:
    return [cell.strip().strip('"').strip("'").strip() for cell in line.split(delimiter)]


def _header(line: str) -> tuple[str | None, dict[str, int]] | None:
    """The delimiter and the columns of ``t``, ``x``, ``y`` if ``line`` is a header row naming them."""
    for delimiter in DELIMITERS:
        names = [cell.lower() for cell in _cells(line, delimiter)]
        if all(name in names for name in COLUMNS):
            return delimiter, {name: names.index(name) for name in COLUMNS}
    return None


def _number(path: Path, number: int, column: str, cell: str, decimal_comma: bool) -> float:
    text = cell.replace(",", ".", 1) if decimal_comma and cell.count(",") == 1 and "." not in cell else cell
    if not _NUMBER.match(text):
        raise TrackFileError(path, number, f"{column} is {cell!r}: not a number")
    return float(text)


def read_track(path: str | Path) -> TrackTable:
    """Read a track file (module docstring).

    Raises
    ------
    TrackFileError
        naming the file, the line and the reason.
    """
    path = Path(path)
    try:
        text = path.read_bytes().decode("utf-8-sig")
    except OSError as error:
        raise TrackFileError(path, 0, f"cannot be read: {error.strerror}") from None
    except UnicodeDecodeError as error:
        raise TrackFileError(path, 0, f"not a text file in UTF-8 (byte {error.start}); save it as UTF-8 "
                                      f"text or CSV") from None
    header = None
    rows: list[tuple[int, float, float, float]] = []
    skipped = 0
    for number, line in enumerate(text.splitlines(), 1):
        if not line.strip() or line.lstrip().startswith("#"):
            continue
        if header is None:
            found = _header(line)
            if found is not None:
                delimiter, columns = found
                names = [cell.lower() for cell in _cells(line, delimiter)]
                for name in COLUMNS:
                    if names.count(name) > 1:
                        raise TrackFileError(path, number, f"the header names {name!r} {names.count(name)} "
                                                           f"times (an export of several tracks): export one "
                                                           f"track, its t, x and y")
                header = delimiter, columns, number
                continue
            if any(_NUMBER.match(_cells(line, delimiter)[0].replace(",", ".", 1)) for delimiter in DELIMITERS):
                raise TrackFileError(path, number, "data before a header row: the file needs a header row "
                                                   "naming t, x and y (separated by tabs, commas, semicolons "
                                                   "or spaces) above the numbers")
            continue   # a title line above the header (Tracker's track name)
        delimiter, columns, _ = header
        cells = _cells(line, delimiter)
        needed = max(columns.values()) + 1
        if len(cells) < needed:
            cells += [""] * (needed - len(cells))
        t, x, y = (cells[columns[name]] for name in COLUMNS)
        if not x and not y:
            skipped += 1   # a frame without a marked step
            continue
        decimal_comma = delimiter != ","
        for name, cell in (("t", t), ("x", x), ("y", y)):
            if not cell:
                raise TrackFileError(path, number, f"{name} is empty (with the other coordinate given)")
        rows.append((number, *(_number(path, number, name, cell, decimal_comma)
                               for name, cell in (("t", t), ("x", x), ("y", y)))))
    if header is None:
        raise TrackFileError(path, 0, "no header row naming t, x and y (separated by tabs, commas, semicolons "
                                      "or spaces)")
    for (_, before, _, _), (number, t, _, _) in zip(rows, rows[1:]):
        if not t > before:
            raise TrackFileError(path, number, f"t = {t:g} does not come after the previous row's {before:g}: "
                                               f"the rows must be in order of time, one per frame")
    if len(rows) < MIN_POINTS:
        raise TrackFileError(path, 0, f"{len(rows)} point{'s' if len(rows) != 1 else ''} below the header on "
                                      f"line {header[2]}: a track needs at least {MIN_POINTS}")
    table = np.array([row[1:] for row in rows])
    return TrackTable(path, table[:, 0].copy(), table[:, 1:].copy(), np.array([row[0] for row in rows]), skipped)
