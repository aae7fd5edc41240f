"""The benchmark's figure: time per shot of each path, and the paths' agreement per design."""

from __future__ import annotations

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure


def save_bench_figure(figures: dict, path) -> None:
    """Time per shot of each path (histogram, log scale) and the fast path's range difference per design."""
    per = figures["per_design"]
    fig = Figure(figsize=(11, 4.2), layout="constrained")
    FigureCanvasAgg(fig)
    times, agree = fig.subplots(1, 2)
    series = [("reference with histories", per["reference_full_s"]), ("reference (summary)", per["reference_s"]),
              ("fast path", per["fast_s"])]
    everything = np.concatenate([np.asarray(v) for _, v in series])
    bins = np.logspace(np.log10(everything.min()) - 0.05, np.log10(everything.max()) + 0.05, 60)
    for label, values in series:
        times.hist(np.asarray(values) * 1e3, bins=bins * 1e3, alpha=0.7,
                   label=f"{label}: median {np.median(values) * 1e3:.3g} ms")
    times.set(xscale="log", xlabel="time per shot (ms)", ylabel="designs",
              title=f"{figures['designs']} designs, speed-up {figures['speedup']:.0f}x")
    times.legend(fontsize=8)
    diffs = np.maximum(np.asarray(per["range_rel_diff"]), 1e-17)
    agree.semilogy(diffs, ".", ms=4, label="|fast / reference - 1| in range")
    agree.axhline(1e-7, color="C3", ls="--", label="the paths' bound 1e-7")
    agree.axhline(np.finfo(float).eps, color="0.5", ls=":", label="machine epsilon")
    agree.set(xlabel="design (thrown ones, in order)", ylabel="relative range difference",
              title="agreement of the two paths", ylim=(1e-17, 1e-5))
    agree.legend(fontsize=8)
    fig.savefig(path, dpi=120)

