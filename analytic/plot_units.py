"""A finished figure shown in other units (``--units imperial``): its axes, titles and labels, the data left in SI.

The plotting modules draw in SI; this converts at the very edge, as the
tick labels are made: each axis whose label ends in an SI unit in brackets
(``range (m)``) gets ticks placed at round numbers of the shown unit and
labelled in it, and every figure in a title or legend followed by an SI unit
(``range 133.33 m``) is rewritten in the shown unit to as many significant digits.
"""

from __future__ import annotations

import re

import numpy as np
from matplotlib.ticker import FuncFormatter, LogFormatterSciNotation, LogLocator, MaxNLocator

from analytic.units import SYSTEMS, display

#: An axis label's unit: the last bracket of the label.
_LABEL_UNIT = re.compile(r"\(([^()]*)\)\s*$")
#: A figure followed by an SI unit in a title: ``133.33 m``, ``-3.9 N``.
_FIGURE = re.compile(r"(?<![\w.+-])(-?\d+(?:\.(\d+))?) (m/s\^2|m/s|m|kg|N|J)(?![\w/])")


class ShownLocator(MaxNLocator):
    """Ticks at round numbers of the shown unit (``factor`` shown units per SI unit)."""

    def __init__(self, factor: float):
        super().__init__(nbins="auto", steps=[1, 2, 2.5, 5, 10])
        self.factor = factor

    def tick_values(self, vmin, vmax):
        return np.asarray(super().tick_values(vmin * self.factor, vmax * self.factor)) / self.factor


class ShownLogLocator(LogLocator):
    """A log axis's ticks at the decades of the shown unit (``factor`` shown units per SI unit)."""

    def __init__(self, factor: float):
        super().__init__()
        self.factor = factor

    def tick_values(self, vmin, vmax):
        return np.asarray(super().tick_values(vmin * self.factor, vmax * self.factor)) / self.factor


def _shown_ticks(axis, factor: float) -> None:
    """``axis`` (data in SI) ticked and labelled in the shown unit, ``factor`` of them per SI unit."""
    if axis.get_scale() == "log":
        labels = LogFormatterSciNotation()
        axis.set_major_locator(ShownLogLocator(factor))
        axis.set_major_formatter(FuncFormatter(lambda value, position: labels(value * factor, position)))
        axis.set_minor_formatter(FuncFormatter(lambda value, position: ""))
    else:
        axis.set_major_locator(ShownLocator(factor))
        axis.set_major_formatter(FuncFormatter(lambda value, _: f"{value * factor:.6g}"))


def shown_text(text: str, system: str) -> str:
    """``text`` with each figure followed by an SI unit in ``system``'s unit, to as many significant
    digits (the figure was rounded to them: more would show the rounding's error, 3.3 times larger in ft)."""
    def convert(match: re.Match) -> str:
        number, shown = display(float(match.group(1)), match.group(3), system)
        digits = max(2, len(match.group(1).lstrip("-").replace(".", "").lstrip("0")))
        return f"{number:#.{digits}g}".rstrip(".") + f" {shown}"

    return _FIGURE.sub(convert, text)


def in_units(figure, system: str):
    """``figure`` (a ``matplotlib.figure.Figure`` drawn in SI) showing ``system``'s units; returned."""
    if not SYSTEMS[system]:
        return figure
    for ax in figure.axes:
        for axis in (ax.xaxis, ax.yaxis):
            match = _LABEL_UNIT.search(axis.get_label_text())
            if match is None or match.group(1) not in SYSTEMS[system]:
                continue
            factor, shown = display(1.0, match.group(1), system)
            _shown_ticks(axis, factor)
            axis.set_label_text(axis.get_label_text()[:match.start()] + f"({shown})")
        ax.set_title(shown_text(ax.get_title(), system))
        for text in ax.texts:   # labels and annotations on the axes (a peak's value)
            text.set_text(shown_text(text.get_text(), system))
        for text in ax.get_legend().get_texts() if ax.get_legend() is not None else ():
            text.set_text(shown_text(text.get_text(), system))
            match = _LABEL_UNIT.search(text.get_text())
            if match is not None and match.group(1) in SYSTEMS[system]:
                text.set_text(text.get_text()[:match.start()] + f"({SYSTEMS[system][match.group(1)][0]})")
    if figure._suptitle is not None:
        figure._suptitle.set_text(shown_text(figure._suptitle.get_text(), system))
    return figure
