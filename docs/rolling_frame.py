"""Range of the paper's design against the mass of a rolling frame: ``python docs/rolling_frame.py [OUT.png]``.

Writes the figure of the worked answer in ``docs/guide/rolling-frame.md`` (default
``docs/rolling-frame.png``) and prints the numbers behind it.
"""

from __future__ import annotations

import dataclasses
import sys
from pathlib import Path

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from analytic import shoot
from analytic.design import Base
from analytic.design_file import default_design


def main(out: Path) -> None:
    design = default_design()
    masses = np.geomspace(0.2, 2000.0, 61)
    rolling = shoot([dataclasses.replace(design, base=Base("rolling", float(m))) for m in masses])
    fixed = shoot([design])
    ratio = rolling.range / fixed.range[0]
    machine = design.machine.arm_mass + design.machine.counterweight_mass + design.projectile.mass

    figure = Figure(figsize=(8.5, 4.2), layout="constrained")
    FigureCanvasAgg(figure)
    ax = figure.subplots()
    ax.semilogx(masses, rolling.range, "-", color="C0", lw=2, label="on frictionless wheels")
    ax.axhline(fixed.range[0], color="0.3", ls="--", label=f"bolted down: {fixed.range[0]:.2f} m")
    ax.axvline(machine, color="C3", ls=":", label=f"arm + counterweight + ball: {machine:.2f} kg")
    ax.set(xlabel="frame mass (kg)", ylabel="range (m)",
           title=f"{design.name}: golf ball, 6.5 kg counterweight, release at 43.4 deg")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    out.parent.mkdir(parents=True, exist_ok=True)
    figure.savefig(out, dpi=110)
    for m in (0.5, 2.0, 5.0, 20.0, 100.0, 1000.0):
        i = int(np.argmin(np.abs(masses - m)))
        print(f"frame {masses[i]:8.2f} kg: range {rolling.range[i]:6.2f} m ({100 * (ratio[i] - 1):+5.1f} %)")
    print(f"written to {out}")


if __name__ == "__main__":
    main(Path(sys.argv[1]) if len(sys.argv) > 1 else Path(__file__).with_name("rolling-frame.png"))
