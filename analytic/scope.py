"""What a copy of the model handles: switches the compiled path turns off to compile less.

The model's source handles every machine. It asks, where a design may need
more than the ideal hinged machine, both whether this copy handles that part
and whether the design needs it: ``if FRICTION and lossy(p)``,
``if FLOATING_ARM and p.kind == FLOATING``. Each switch here is a module
global, True for the Python model the reference path runs.

The compiled path (``analytic.fast.compiled.kernel_scope``) compiles the kernel
in a few ``Scope``s, each with its own copy of the model's globals. numba
reads a global as a constant and prunes a branch on a constant before it
types the code (its dead-branch pruning), so a scope that turns a part off
never types, lowers or optimises it: the ideal scope compiles in a fraction
of the time of the whole model (``python -m benchmarks --cold`` measures each
scope's), and its shots skip the tests of what they do not use. A design runs in the smallest scope that holds it (``needed``);
the same arithmetic in every scope gives the same bits.
"""

from __future__ import annotations

import itertools
from typing import NamedTuple

import numpy as np

from analytic.design import KINDS
from analytic.parameters import Params

#: ``Params.kind`` of the floating arm (``eom.FLOATING``; the model imports this module).
_FLOATING = float(KINDS.index("floating-arm"))

#: Any friction: the axle's, the hinge's, the base's, the guide's or the track's.
FRICTION = True
#: The rolling frame.
ROLLING = True
#: The floating arm (``eom.FLOATING``); the hinged and the fixed ones are always handled.
FLOATING_ARM = True
#: The projectile's drag in stages 1-2 (``projectile.drag_during_swing``).
SWING_DRAG = True
#: The sling's and the pouch's masses (``machine.sling_mass``, ``machine.pouch_mass``).
SLING = True
#: The peak loads (the kernel's ``track_loads``).
LOADS = True
#: Recording the motion (the kernel's ``rec``, for ``analytic.fast.motion``).
RECORDING = True


class Scope(NamedTuple):
    """The switches of one compiled copy of the model, by their global's name in lower case."""

    name: str
    friction: bool
    rolling: bool
    floating_arm: bool
    swing_drag: bool
    loads: bool
    sling: bool
    recording: bool

    def globals(self) -> dict[str, bool]:
        """The switches as the model's module globals (``FRICTION``, ...)."""
        return {field.upper(): getattr(self, field) for field in self._fields[1:]}

    def holds(self, other: Scope) -> bool:
        """Whether this scope handles everything ``other`` does."""
        return all(getattr(self, field) or not getattr(other, field) for field in self._fields[1:])


#: Everything: any design, the peak loads, the motion recorded.
EVERYTHING = Scope("everything", True, True, True, True, True, True, True)
#: The ideal machine (hinged or fixed, no friction, a fixed frame, drag in flight only) with its peak loads.
IDEAL_LOADS = Scope("ideal_loads", False, False, False, False, True, False, False)
#: The ideal machine without its loads: what a search or a sweep of ideal designs runs.
IDEAL = Scope("ideal", False, False, False, False, False, False, False)
#: The compiled scopes, smallest first: a design runs in the first that holds what it needs.
SCOPES = (IDEAL, IDEAL_LOADS, EVERYTHING)



def needs(p) -> tuple:
    """``(friction, rolling, floating_arm, swing_drag, sling)``: what the design ``p`` needs, as the model
    tests it (``friction.lossy``, ``p.rolling``, ``p.kind == eom.FLOATING``, ``p.drag_swing > 0``,
    ``eom.sling_weighs``).

    ``p`` is a ``Params`` of floats (each entry then a bool) or of column arrays, one entry
    per design (each entry then a bool array).
    """
    friction = (p.mua_s > 0.0) | (p.muh_s > 0.0) | (p.mub_s > 0.0) | (p.mug_s > 0.0) | (p.mut_s > 0.0)
    return friction, p.rolling != 0.0, p.kind == _FLOATING, p.drag_swing > 0.0, (p.mS > 0.0) | (p.mQ > 0.0)


def _smallest(asked: tuple) -> Scope:
    request = Scope("asked", *asked)
    return next(scope for scope in SCOPES if scope.holds(request))


#: The smallest scope for each combination of what may be asked.
_SMALLEST = {asked: _smallest(asked) for asked in itertools.product((False, True), repeat=7)}


def needed(p, loads: bool, recording: bool = False) -> Scope:
    """The smallest of ``SCOPES`` for one design's ``Params`` ``p`` and what is asked of it."""
    friction, rolling, floating_arm, swing_drag, sling = needs(p)
    return _SMALLEST[(friction, rolling, floating_arm, swing_drag, bool(loads), bool(recording), sling)]


def needed_rows(rows: np.ndarray, loads: bool, recording: bool = False) -> Scope:
    """The smallest of ``SCOPES`` that holds every design row of ``rows`` (S, N_PARAMS)."""
    columns = Params(*np.asarray(rows).T)
    friction, rolling, floating_arm, swing_drag, sling = (bool(x.any()) for x in needs(columns))
    return _SMALLEST[(friction, rolling, floating_arm, swing_drag, bool(loads), bool(recording), sling)]
