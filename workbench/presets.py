"""The page's presets: designs that span real machines, each read from a design file shipped with the packages."""

from __future__ import annotations

import re
from importlib.resources import files
from pathlib import Path
from typing import Any

from analytic.design_file import default_design, design_to_dict, load_design

_HERE = Path(__file__).with_name("presets")
_ANALYTIC_DATA = Path(str(files("analytic.data")))
_ANALYTIC_DESIGNS = _ANALYTIC_DATA / "designs"
#: Trebuchator's presets, entered as design files (``analytic/data/designs/trebuchator``).
_TREBUCHATOR = _ANALYTIC_DESIGNS / "trebuchator"
#: Trebuchator's presets on the page, by their files' names: the machines smallest first, then the
#: laboratory's reference machine.
TREBUCHATOR_PRESETS = ("backyard", "simple-fixed", "floating-arm", "punkin", "siege", "warwolf", "man-thrower",
                       "lab")


def trebuchator_title(name: str) -> str:
    """The title of Trebuchator's preset ``name`` on the page: the one its design file's header gives
    (its first line: ``# Trebuchator's preset "backyard" (Backyard Classic), entered ...``)."""
    path = _TREBUCHATOR / f"{name}.toml"
    with path.open(encoding="utf-8") as file:
        header = file.readline()
    match = re.match(rf'# Trebuchator\'s preset "{re.escape(name)}" \((.+)\), entered', header)
    if match is None:
        raise ValueError(f"{path}: its first line does not name Trebuchator's preset {name!r} and its title")
    return f"Trebuchator: {match[1]}"


#: Preset name -> (title on the page, how to load it).
PRESETS = {
    "paper-table3": ("Paper's optimum (Table III)", default_design),
    "paper-table3-fixed": ("Paper's optimum, counterweight bolted on",
                           lambda: load_design(_ANALYTIC_DATA / "paper_table3_fixed.toml")),
    "paper-table3-floating": ("Paper's optimum as a floating arm",
                              lambda: load_design(_ANALYTIC_DATA / "paper_table3_floating.toml")),
    "prototype-61": ("Paper's prototype as fired (61 deg)", lambda: load_design(_ANALYTIC_DESIGNS / "prototype-61.toml")),
    "virtual-trebuchet": ("Virtual Trebuchet's default", lambda: load_design(_HERE / "virtual-trebuchet.toml")),
    "backyard": ("Backyard build (ft, lb)", lambda: load_design(_HERE / "backyard.toml")),
    "pumpkin-hurler": ("Pumpkin hurler", lambda: load_design(_HERE / "pumpkin.toml")),
    "warwolf-scale": ("Siege engine at Warwolf scale", lambda: load_design(_HERE / "warwolf.toml")),
    **{f"trebuchator-{name}": (trebuchator_title(name), lambda name=name: load_design(_TREBUCHATOR / f"{name}.toml"))
       for name in TREBUCHATOR_PRESETS},
}


def presets_json() -> list[dict[str, Any]]:
    """Every preset as the page takes it: name, title and the design's tables (file units)."""
    return [{"name": name, "title": title, "design": design_to_dict(load())} for name, (title, load) in PRESETS.items()]
