"""The designs the benchmarks shoot: the paper's optimum and a seeded sample over its Table II bounds."""

from __future__ import annotations

from analytic.design import Base
from analytic.design_file import default_design
from analytic.design_space import default_problem, sample_designs
from crosscheck.cases import REALISTIC_LOSSES, ROLLING_SAMPLE_FRAME_MASS

#: The losses whose cost the benchmark measures: the cross-check's realistic ones (a steel axle
#: and hinge pin in plain bearings, a sled on a wooden base).
TYPICAL_LOSSES = REALISTIC_LOSSES

#: The frame the benchmark's designs roll on: the cross-check's frame for sampled designs
#: (``crosscheck.cases.ROLLING_SAMPLE_FRAME_MASS``, 10 kg, about the 6.5 kg counterweight
#: every benchmark design carries): a wooden frame and wheels a machine of this size stands
#: on, light enough that the frame moves by centimetres during the shot.
ROLLING_FRAME = Base("rolling", ROLLING_SAMPLE_FRAME_MASS)


def bench_designs(count: int, seed: int):
    """The paper's optimum and ``count`` designs drawn uniformly over the paper's problem box."""
    return [default_design(), *sample_designs(default_problem(), count, seed, lambda i: f"bench-{seed}-{i:03d}")]
