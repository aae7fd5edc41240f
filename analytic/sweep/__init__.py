"""Design sweeps and uncertainty at scale: grids, samples and uncertain inputs, shot in chunks.

The layers, each its own module: ``spec`` (sweep files, checked) and
``distributions``; ``expand`` (a chunk's inputs) and ``designs`` (its kernel
rows).
"""

from __future__ import annotations

from analytic.sweep.spec import Sweep, load_sweep, sweep_from_dict

__all__ = ["Sweep", "load_sweep", "sweep_from_dict"]
