"""A shot's design file at the fitted parameters, written as the user wrote it: same tables, units and comments.

The user's design file is edited, not regenerated (tomlkit keeps its
layout): each fitted field and each of the shot's settings and ``[given]``
fields is set where the file has it, in the unit the file wrote it in
(``"14 lb"`` stays pounds), or added to its table in file units where the
file leaves it out. A fitted value is rounded to the precision its
uncertainty supports (``digits_for``); a shot's setting and a given field
are copied as the calibration file wrote them. The design's ``name`` and the
file's name are the shot's setting (``prototype-61-counterweight_mass-5kg``),
or the design file's stem when the shot sets nothing.
"""

from __future__ import annotations

import math
import re
from pathlib import Path
from typing import Any

from analytic.calibrate.fit import Calibration
from analytic.calibrate.spec import RELEASE_ANGLE_OFFSET, ShotSpec, dotted_table
from analytic.fields import field

#: Significant figures of a fitted value's uncertainty kept when rounding the value.
UNCERTAINTY_FIGURES = 2


def digits_for(sd: float) -> int:
    """Decimal places that keep ``UNCERTAINTY_FIGURES`` significant figures of ``sd`` (at least 0)."""
    if not math.isfinite(sd) or sd <= 0.0:
        return 6
    return max(0, UNCERTAINTY_FIGURES - 1 - math.floor(math.log10(sd)))


def setting_name(shot: ShotSpec) -> str:
    """The shot's file stem and settings as a name safe for a file (``prototype-61-counterweight_mass-5kg``)."""
    stem = Path(shot.design_file).stem
    parts = [stem] + [f"{name.rpartition('.')[2]}-{value}" for name, value in shot.written.items()]
    return re.sub(r"[^A-Za-z0-9_.+-]", "", "-".join(str(p) for p in parts))


def _in_unit_of(written: Any, value: float, decimals: int, kind) -> Any:
    """``value`` (file units) in the unit of ``written`` (a text with units keeps its unit)."""
    if isinstance(written, str) and kind.file_unit:
        from analytic.units import registry

        unit = registry().Quantity(written).units
        magnitude = registry().Quantity(value, kind.file_unit).to(unit).magnitude
        scale = registry().Quantity(1.0, kind.file_unit).to(unit).magnitude
        places = max(0, decimals - math.floor(math.log10(abs(scale)))) if scale else decimals
        return f"{_rounded(magnitude, places):g} {unit:~}".replace(" ** ", "^")
    return _rounded(value, decimals)


def _rounded(value: float, decimals: int) -> float:
    """``value`` to ``decimals`` places, or to two significant figures where that would make it 0
    (a positive field, such as a drag factor, must stay positive)."""
    rounded = round(value, decimals)
    return rounded if rounded != 0.0 or value == 0.0 else float(f"{value:.2g}")


def _set(document, name: str, value: Any) -> None:
    """Set ``table.key`` in the document, in the table the file has (``[machine]``) or a new one."""
    import tomlkit

    target = field(name)
    if target.table not in document:
        document[target.table] = tomlkit.table()
    document[target.table][target.key] = value


def fitted_text(result: Calibration, shot: ShotSpec) -> str:
    """The text of ``shot``'s design file at the fitted parameters (module docstring)."""
    import tomlkit

    spec = result.spec
    path = spec.path.parent / shot.design_file
    document = tomlkit.parse(path.read_text())
    for name, value in {**_written_given(spec), **shot.written}.items():
        _set(document, name, value)
    for j, parameter in enumerate(spec.parameters):
        decimals = digits_for(float(result.uncertainties[j]))
        target = parameter.field if parameter.name != RELEASE_ANGLE_OFFSET else field("machine.release_angle")
        existing = document.get(target.table, {}).get(target.key)
        value = float(result.values[j])
        if parameter.name == RELEASE_ANGLE_OFFSET:
            value += math.degrees(shot.design.machine.release_angle)
        _set(document, target.name, _in_unit_of(_unwrapped(existing), value, decimals, target.kind))
    document["name"] = setting_name(shot)
    text = tomlkit.dumps(document)
    return text if text.endswith("\n") else text + "\n"


def _written_given(spec) -> dict[str, Any]:
    """``[given]`` as the calibration file wrote it."""
    from analytic.design_file import read_toml

    return {field(name).name: value for name, value in dotted_table("given", read_toml(spec.path).get("given")).items()}


def _unwrapped(item: Any) -> Any:
    return item.unwrap() if hasattr(item, "unwrap") else item
