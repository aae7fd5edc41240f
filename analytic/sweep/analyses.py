"""What a finished sweep says: maps over its grid, the spread of its output, Sobol' sensitivity indices.

Each analysis reads the results table (``storage.read_table``, its rows in
any order: each is placed by its ``index``) and the stored settings
(``storage.read_settings``), never the sweep file, so a report describes
exactly what was shot. The output studied is the sweep's
``output`` column: ``range``, or ``y`` for a test function. Failed shots
are kept as failures (their status), never counted as a zero output.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from analytic.outcome import Status

#: Quantiles of the output reported, in per cent.
QUANTILES = (5, 25, 50, 75, 95)
#: Bootstrap resamples and confidence level of the Sobol' indices' intervals (SALib's defaults).
SOBOL_RESAMPLES = 100
SOBOL_CONFIDENCE = 0.95
#: Seed of SALib's bootstrap, so that a report is the same each time it is
#: made. Not 0: SALib tests ``if seed:`` and leaves a 0 seed unseeded.
SOBOL_SEED = 1
OK = Status.OK.value


@dataclass(frozen=True)
class GridMap:
    """The output over a grid of one or two fields (a sample at each point is averaged).

    Attributes
    ----------
    fields : the grid's fields, (1,) or (2,).
    axes : each field's values, file units.
    value : grid shape; the mean output of a point's thrown shots, NaN where it did not throw.
    status : grid shape, str; ``ok`` where at least half a point's shots threw, else its most common failure.
    thrown : grid shape; the fraction of the point's shots that threw.
    shots_per_point : designs at each grid point (1 without a sample).
    """

    fields: tuple[str, ...]
    axes: tuple[np.ndarray, ...]
    value: np.ndarray
    status: np.ndarray
    thrown: np.ndarray
    shots_per_point: int

    @property
    def best(self) -> tuple[float, tuple[float, ...]] | None:
        """The largest value and where it is (field values), or None if nothing threw."""
        shown = np.where(self.status == OK, self.value, np.nan)
        if np.isnan(shown).all():
            return None
        at = np.unravel_index(int(np.nanargmax(shown)), shown.shape)
        return float(shown[at]), tuple(float(axis[i]) for axis, i in zip(self.axes, at))


@dataclass(frozen=True)
class Spread:
    """The distribution of the output over a sample.

    Attributes
    ----------
    shots, thrown : designs, and how many threw.
    statuses : status -> count.
    mean, sd : of the thrown shots' output (NaN if none threw).
    quantiles : per cent -> the output's quantile among thrown shots.
    reach : (distance, probability that a shot, failures included, reaches at least it).
    values : (thrown,) the thrown shots' outputs, sorted.
    """

    shots: int
    thrown: int
    statuses: dict
    mean: float
    sd: float
    quantiles: dict
    reach: tuple[tuple[float, float], ...]
    values: np.ndarray


@dataclass(frozen=True)
class Sensitivity:
    """Sobol' first-order and total indices of the output, with confidence half-widths (SALib).

    Every array has shape (D,), one entry per field in ``fields``.
    """

    fields: tuple[str, ...]
    first: np.ndarray
    first_conf: np.ndarray
    total: np.ndarray
    total_conf: np.ndarray
    base_samples: int
    confidence: float


def status_codes(column) -> tuple[tuple[str, ...], np.ndarray]:
    """A status column (pyarrow, text or dictionary) as codes into the statuses it holds.

    Returns
    -------
    names : the statuses present, each once.
    codes : (S,) int8, each row's position in ``names`` (no text per row: for
        10^8 rows, text would take gigabytes).
    """
    import pyarrow as pa
    import pyarrow.compute as pc

    names: list[str] = []
    parts = [np.empty(0, dtype=np.int8)]
    for chunk in column.chunks:
        if not pa.types.is_dictionary(chunk.type):
            chunk = pc.dictionary_encode(chunk)
        local = chunk.dictionary.to_pylist()
        names += [name for name in local if name not in names]
        recode = np.array([names.index(name) for name in local], dtype=np.int8)
        parts.append(recode[chunk.indices.to_numpy(zero_copy_only=False)])
    return tuple(names), np.concatenate(parts)


def status_counts(names: tuple[str, ...], codes: np.ndarray) -> dict[str, int]:
    """Status -> number of rows, in ``Status`` order."""
    counts = np.bincount(codes, minlength=len(names))
    order = [status.value for status in Status]
    return {name: int(counts[names.index(name)]) for name in sorted(names, key=order.index) if counts[names.index(name)]}


def grid_map(settings: dict, table) -> GridMap | None:
    """The map over the grid, if the sweep's grid has one or two fields."""
    sweep = settings["sweep"]
    grid = sweep["grid"]
    if not 1 <= len(grid) <= 2:
        return None
    shape = tuple(len(axis["values"]) for axis in grid)
    points = int(np.prod(shape))
    per_point = sweep["shots"] // points
    output = table[sweep["output"]].to_numpy(zero_copy_only=False)
    names, codes = status_codes(table["status"])
    point = table["index"].to_numpy() // per_point
    thrown = codes == (names.index(OK) if OK in names else -1)
    count = np.bincount(point[thrown], minlength=points)
    total = np.bincount(point[thrown], weights=output[thrown], minlength=points)
    with np.errstate(invalid="ignore", divide="ignore"):
        value = np.where(count > 0, total / np.maximum(count, 1), np.nan)
    fraction = count / per_point
    tally = np.bincount(point * len(names) + codes, minlength=points * len(names)).reshape(points, len(names))
    tally[:, [name == OK for name in names]] = -1
    worst = np.asarray(names)[np.argmax(tally, axis=1)]
    point_status = np.where(fraction >= 0.5, OK, worst)
    return GridMap(fields=tuple(axis["field"] for axis in grid),
                   axes=tuple(np.asarray(axis["values"]) for axis in grid),
                   value=value.reshape(shape), status=point_status.reshape(shape), thrown=fraction.reshape(shape),
                   shots_per_point=per_point)


def spread(settings: dict, table, distances=None) -> Spread | None:
    """The output's distribution, if the sweep draws a sample and has no grid (else the rows mix designs).

    ``distances``: where to give the probability of reaching; by default five
    round numbers across the thrown outputs.
    """
    sweep = settings["sweep"]
    if sweep["sample"] is None or sweep["grid"]:
        return None
    output = table[sweep["output"]].to_numpy(zero_copy_only=False)
    names, codes = status_codes(table["status"])
    thrown = np.sort(output[codes == (names.index(OK) if OK in names else -1)])
    if distances is None:
        distances = _round_numbers(thrown)
    reach = tuple((float(d), float(np.count_nonzero(thrown >= d)) / len(output)) for d in distances)
    have = len(thrown) > 0
    return Spread(shots=len(output), thrown=len(thrown), statuses=status_counts(names, codes),
                  mean=float(thrown.mean()) if have else float("nan"),
                  sd=float(thrown.std(ddof=1)) if len(thrown) > 1 else float("nan"),
                  quantiles={q: float(np.percentile(thrown, q)) if have else float("nan") for q in QUANTILES},
                  reach=reach, values=thrown)


def _round_numbers(values: np.ndarray) -> list[float]:
    if not len(values):
        return []
    from matplotlib.ticker import MaxNLocator

    low, high = np.percentile(values, [2, 98])
    ticks = MaxNLocator(nbins=5).tick_values(low, high)
    return [float(t) for t in ticks if low <= t <= high]


def sensitivity(settings: dict, table) -> Sensitivity | str:
    """Sobol' first-order and total indices by SALib's estimator, or why there are none.

    Needs a Sobol' sample (Saltelli's scheme, rows as SALib lays them out), no
    grid, and every shot thrown: a failed shot has no output to attribute.
    """
    sweep = settings["sweep"]
    sample = sweep["sample"]
    if sample is None or sample["method"] != "sobol":
        return "needs [sample] method = \"sobol\""
    if sweep["grid"]:
        return "not computed over a grid (one set of indices per grid point)"
    names, codes = status_codes(table["status"])
    failed = int(np.count_nonzero(codes != (names.index(OK) if OK in names else -1)))
    if failed:
        return (f"{failed} of {len(codes)} shots did not throw; indices of {sweep['output']} need every shot "
                f"to throw: narrow the distributions")
    from SALib.analyze import sobol

    fields = tuple(v["field"] for v in sample["fields"])
    problem = {"num_vars": len(fields), "names": list(fields), "bounds": [[0.0, 1.0]] * len(fields)}
    # SALib reads the outputs in the sample's row order: place each by its index.
    output = np.empty(table.num_rows)
    output[table["index"].to_numpy()] = table[sweep["output"]].to_numpy(zero_copy_only=False)
    indices = sobol.analyze(problem, output, calc_second_order=False,
                            num_resamples=SOBOL_RESAMPLES, conf_level=SOBOL_CONFIDENCE, seed=SOBOL_SEED)
    return Sensitivity(fields=fields, first=np.asarray(indices["S1"]), first_conf=np.asarray(indices["S1_conf"]),
                       total=np.asarray(indices["ST"]), total_conf=np.asarray(indices["ST_conf"]),
                       base_samples=sample["n"], confidence=SOBOL_CONFIDENCE)
