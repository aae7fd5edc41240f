"""A sweep's inputs, one chunk at a time: grid points, random or Sobol' draws, uncertain offsets.

Row ``i`` of a sweep is grid point ``i // R`` with sample row ``i % R`` (R
sample rows per grid point), and every chunk computes its own rows from
``(sweep, chunk)`` alone, so that any executor, on any machine, in any
order, produces the same numbers, and no more than one chunk of inputs ever
exists at once. The draws do not even depend on the chunk size: the random
stream is counter-based (Philox, advanced to the chunk's first row) and the
Sobol' sequence is fast-forwarded to it.
"""

from __future__ import annotations

import warnings

import numpy as np

from analytic.sweep.spec import Sample, Sweep

#: Philox yields 4 64-bit words per counter step and a double takes one word:
#: each random row takes a whole number of steps so that a chunk can start
#: at any row by advancing the counter.
_WORDS_PER_STEP = 4


def chunk_inputs(sweep: Sweep, chunk: int) -> tuple[np.ndarray, dict[str, np.ndarray]]:
    """The rows of chunk ``chunk``: their indices and each varied field's values.

    Returns
    -------
    index : (m,) int64, the rows' positions in the sweep.
    values : field -> (m,) float, in file units (degrees for angles), for ``sweep.fields``.
    """
    start, stop = sweep.chunk_rows(chunk)
    index = np.arange(start, stop, dtype=np.int64)
    rows_per_point = sweep.sample_rows
    values: dict[str, np.ndarray] = {}
    if sweep.grid:
        point = np.unravel_index(index // rows_per_point, sweep.grid_shape)
        for axis, position in zip(sweep.grid, point):
            values[axis.field] = np.asarray(axis.values)[position]
    if sweep.sample is not None:
        units = sample_units(sweep.sample, index % rows_per_point)
        for j, varied in enumerate(sweep.sample.fields):
            drawn = varied.distribution.ppf(units[:, j])
            if varied.around_base:
                drawn = values.get(varied.field, sweep.base.values.get(varied.field)) + drawn
            values[varied.field] = drawn
    return index, {field: values[field] for field in sweep.fields}


def sample_units(sample: Sample, rows: np.ndarray) -> np.ndarray:
    """Unit numbers of sample rows ``rows`` (a run of consecutive values, wrapping at ``sample.rows``
    back to 0 where a chunk spans several grid points), shape (m, D)."""
    units = np.empty((len(rows), len(sample.fields)))
    # Split where the row number wraps: each piece is a consecutive range.
    breaks = np.flatnonzero(np.diff(rows) != 1) + 1
    for piece in np.split(np.arange(len(rows)), breaks):
        if len(piece):
            first = int(rows[piece[0]])
            units[piece] = unit_block(sample, first, first + len(piece))
    return units


def unit_block(sample: Sample, start: int, stop: int) -> np.ndarray:
    """Unit numbers of sample rows ``[start, stop)``, shape (stop - start, D)."""
    if sample.method == "random":
        return _random_block(sample, start, stop)
    return _saltelli_block(sample, start, stop)


def _random_block(sample: Sample, start: int, stop: int) -> np.ndarray:
    dimensions = len(sample.fields)
    width = -(-dimensions // _WORDS_PER_STEP) * _WORDS_PER_STEP
    bit_generator = np.random.Philox(sample.seed)
    bit_generator.advance(start * width // _WORDS_PER_STEP)
    return np.random.Generator(bit_generator).random((stop - start, width))[:, :dimensions]


def _saltelli_block(sample: Sample, start: int, stop: int) -> np.ndarray:
    """Rows ``[start, stop)`` of Saltelli's scheme as SALib lays it out (``SALib.sample.sobol.sample``
    with ``calc_second_order=False``, unit bounds): for each point ``j`` of a scrambled Sobol'
    sequence in 2D dimensions, split into A = its first D and B = its last D numbers, the
    rows A, then A with column k taken from B for each k, then B."""
    from scipy.stats import qmc  # here, not at import: scipy.stats takes a second to import

    dimensions = len(sample.fields)
    per_point = dimensions + 2
    first, last = start // per_point, (stop - 1) // per_point
    sequence = qmc.Sobol(d=2 * dimensions, scramble=True, seed=sample.seed)
    if first:
        sequence.fast_forward(first)
    with warnings.catch_warnings():
        # scipy warns when n is not a power of 2; the whole sequence is one
        # (the sweep file is checked for it), a chunk is only a slice of it.
        warnings.filterwarnings("ignore", message="The balance properties of Sobol' points", category=UserWarning)
        points = sequence.random(last - first + 1)
    a, b = points[:, :dimensions], points[:, dimensions:]
    block = np.repeat(a, per_point, axis=0).reshape(len(points), per_point, dimensions)
    for k in range(dimensions):
        block[:, 1 + k, k] = b[:, k]
    block[:, -1, :] = b
    block = block.reshape(-1, dimensions)
    offset = first * per_point
    return block[start - offset:stop - offset]
