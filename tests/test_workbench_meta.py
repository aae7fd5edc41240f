"""``GET /api/meta`` gives the page the design's defaults, which fields apply under which choices, and the
peak loads: each checked against the design contract and the shot it describes, not against itself."""

from __future__ import annotations

import json
import math

import pytest

from analytic.design import DesignError
from analytic.design_file import design_from_dict, design_to_dict, load_design
from analytic.design_space import LOADS, default_problem
from analytic.optimise.plot import score_label
from analytic.reference import simulate
from analytic.summary import peak_label
from support import TABLE3_FILE, bolted, page_client

TABLE3_FLOATING = TABLE3_FILE.with_name("paper_table3_floating.toml")


@pytest.fixture(scope="module")
def meta():
    return page_client().get("/api/meta").json()


def fields_of(meta) -> dict[str, dict]:
    return {row["name"]: row for group in meta["groups"] for row in group["fields"]}


def tables(design) -> dict:
    return json.loads(json.dumps(design_to_dict(design)))


def table3() -> dict:
    return tables(load_design(TABLE3_FILE))


def built(layout: dict):
    return design_from_dict(layout, name="meta")


def value_of(design, name: str):
    table, key = name.split(".")
    value = getattr(getattr(design, table), key)
    return math.degrees(value) if key == "release_angle" and value is not None else value


def test_each_default_is_what_a_design_file_that_leaves_the_field_out_gets(meta):
    """Every field the page shows with a default: the Table III file with that field left out builds a
    design whose value is the default (file units); and the ones the brief names are there."""
    fields = fields_of(meta)
    defaulted = {name: row["default"] for name, row in fields.items() if "default" in row}
    assert {"projectile.drag_factor", "environment.air_density", "losses.axle_radius", "losses.hinge_radius",
            "machine.kind", "base.mobility"} <= set(defaulted)
    for name, default in defaulted.items():
        layout = table3()
        table, key = name.split(".")
        layout.get(table, {}).pop(key, None)
        assert value_of(built(layout), name) == default, name


def test_a_static_coefficient_left_out_takes_its_kinetic_one(meta):
    """``default_from``: the static coefficient the design uses when the file leaves it out is the field
    the page says (``Losses.static``), on a hinged and a floating-arm machine."""
    fields = fields_of(meta)
    pointing = {name: row["default_from"] for name, row in fields.items() if "default_from" in row}
    assert len(pointing) == 5
    for name, kinetic in pointing.items():
        layout = tables(load_design(TABLE3_FLOATING)) if "guide" in name or "track" in name else table3()
        layout["losses"] = {kinetic.split(".")[1]: 0.3, "axle_radius": 0.01, "hinge_radius": 0.01}
        friction = name.split(".")[1].removesuffix("_static_friction")
        assert built(layout).losses.static(friction) == 0.3, name


def test_fields_without_a_default_have_none_to_show(meta):
    """What a design must give has no default to show: the machine's sizes and masses, the projectile's."""
    fields = fields_of(meta)
    for name in ("machine.arm_long", "machine.counterweight_mass", "projectile.mass", "projectile.drag_coefficient",
                 "base.mass"):
        assert "default" not in fields[name] and "default_from" not in fields[name], name


# ---- only what applies -------------------------------------------------------------------------

def applies(rule: dict, layout: dict, fields: dict) -> bool:
    """The page's reading of a rule (applies.js): a field left out takes its default."""
    def value(name):
        table, key = name.split(".")
        given = layout.get(table, {}).get(key)
        return given if given is not None else fields[name].get("default")

    def holds(condition):
        if "positive" in condition:
            return any((value(n) or 0) > 0 for n in condition["positive"])
        return (value(condition["field"]) in condition["in"]) if "in" in condition \
            else value(condition["field"]) not in condition["not_in"]

    return all(holds(c) for c in rule["when"])


def machines() -> dict[str, dict]:
    """The kinds of machine, each under every drag law and release rule the rules turn on."""
    kinds = {"hinged": table3(), "fixed": tables(bolted(load_design(TABLE3_FILE))),
             "floating-arm": tables(load_design(TABLE3_FLOATING))}
    out = {}
    for kind, layout in kinds.items():
        for drag in ("none", "constant", "smooth-sphere", "golf-ball"):
            variant = json.loads(json.dumps(layout))
            variant["projectile"]["drag"] = drag
            variant["projectile"].pop("drag_coefficient", None)
            if drag == "constant":
                variant["projectile"]["drag_coefficient"] = 0.47
            out[f"{kind}-{drag}"] = variant
        ideal = json.loads(json.dumps(layout))
        ideal["machine"]["release_rule"] = "ideal"
        out[f"{kind}-ideal"] = ideal
    return out


def put(layout: dict, name: str, value) -> dict:
    out = json.loads(json.dumps(layout))
    table, key = name.split(".")
    out.setdefault(table, {})[key] = value
    if name.startswith("losses.hinge"):
        out["losses"]["hinge_radius"] = 0.01   # a coefficient needs its radius (the contract's own rule)
    if name == "base.mobility":
        out["base"]["mass"] = 100.0
    return out


#: A value the design contract refuses, by a rule's ``refuses``.
REFUSED = {"positive": 0.1, "set": 0.5}


def test_where_a_rule_says_the_contract_refuses_a_value_it_does_so_at_that_field(meta):
    """Each rule with ``refuses``: on every machine where it does not apply, such a value is refused by
    ``analytic.design`` naming the rule's field; each such rule fails on at least one machine."""
    fields, failed = fields_of(meta), set()
    for rule in (r for r in meta["rules"] if "refuses" in r):
        refused = rule["refuses"][0] if isinstance(rule["refuses"], list) else REFUSED[rule["refuses"]]
        for name, layout in machines().items():
            if applies(rule, layout, fields):
                continue
            failed.add(rule["field"])
            with pytest.raises(DesignError) as error:
                built(put(layout, rule["field"], refused))
            assert error.value.field == rule["field"], (name, rule["field"], str(error.value))
    assert failed == {r["field"] for r in meta["rules"] if "refuses" in r}


#: A changed value of a field (file units) for the rules the contract accepts either way.
CHANGED = {"machine.release_angle": 30.0, "projectile.drag_factor": 2.0, "environment.air_density": 0.9,
           "environment.air_viscosity": 3e-5, "environment.wind_speed": 5.0, "base.mass": 50.0,
           "losses.axle_radius": 0.05, "losses.hinge_radius": 0.05}


@pytest.mark.parametrize("field", sorted(CHANGED))
def test_a_field_that_does_not_apply_changes_nothing(meta, field):
    """Where a rule says its field does not apply, changing it leaves the shot's range as it was (the
    reference path, to the bit): the page disables a field that truly does nothing."""
    fields = fields_of(meta)
    rule = next(r for r in meta["rules"] if r["field"] == field)
    assert "refuses" not in rule
    tried = 0
    for name, layout in machines().items():
        if applies(rule, layout, fields) or not name.endswith(("-none", "-constant", "-ideal")):
            continue
        tried += 1
        before, after = simulate(built(layout)), simulate(built(put(layout, field, CHANGED[field])))
        assert after.range == before.range, (name, field)
    assert tried, field


def test_each_rules_reason_names_the_value_that_decides(meta):
    """The reasons' ``{table.key}`` stand for fields the page has."""
    fields = fields_of(meta)
    for rule in meta["rules"]:
        assert rule["field"] in fields
        for condition in rule["when"]:
            for name in [condition.get("field"), *condition.get("positive", [])]:
                assert name is None or name in fields
            for name in __import__("re").findall(r"\{([a-z_]+\.[a-z_]+)\}", condition["why"]):
                assert name in fields, (rule["field"], name)


# ---- the peak loads ----------------------------------------------------------------------------

@pytest.mark.parametrize("kind", ["hinged", "fixed", "floating-arm"])
def test_the_loads_are_named_and_shown_as_the_shots_summary_rows(meta, kind):
    """Each load's label on each kind is ``analytic.summary.peak_label`` of such a machine, and its unit's
    kind that of the summary's row of it (the projectile's acceleration in g)."""
    design = {"hinged": load_design(TABLE3_FILE), "fixed": bolted(load_design(TABLE3_FILE)),
              "floating-arm": load_design(TABLE3_FLOATING)}[kind]
    rows = {row["key"]: row for row in page_client().post("/api/shot", json={"design": tables(design)}).json()["summary"]}
    assert [load["name"] for load in meta["loads"]] == list(LOADS.values())
    for load in meta["loads"]:
        assert load["labels"][kind] == peak_label(load["name"], design)
        assert load["kind"] == rows[load["name"]]["kind"], load
    assert meta["loads"][1]["labels"][kind] == ("peak hinge load" if kind == "hinged" else "peak mount load")


#: Each ``[loads] minimise`` a problem may give, and the SI unit of its peak (``analytic.result.Shot``'s docstring).
MINIMISED_UNITS = {"axle_load": "N", "hinge_load": "N", "sling_tension": "N", "projectile_acceleration": "m/s^2",
                   "arm_bending_moment": "N m"}


@pytest.mark.parametrize("load", sorted(MINIMISED_UNITS))
def test_the_optimisers_plots_name_each_minimised_load_in_its_unit(load):
    import dataclasses

    problem = dataclasses.replace(default_problem(), minimise=load, min_range=1.0)
    assert score_label(problem) == f"minus the peak {load.replace('_', ' ')} ({MINIMISED_UNITS[load]})"


def test_each_kind_of_design_field_is_converted_from_the_unit_the_page_receives(meta):
    """Gravity reaches the page in m/s^2 (a projectile's limit, written in g in files, is of the same
    kind): 1 m/s^2 = 1 / 0.3048 ft/s^2, 1 kg/m^3 = 0.3048^3 / 0.45359237 lb/ft^3 (exact definitions)."""
    units = meta["units"]
    assert units["acceleration"]["imperial"]["factor"] == pytest.approx(1 / 0.3048, rel=1e-12)
    assert units["density"]["imperial"]["factor"] == pytest.approx(0.3048**3 / 0.45359237, rel=1e-12)
    assert units["length"]["imperial"]["factor"] == pytest.approx(1 / 0.3048, rel=1e-12)


def test_the_optimisers_bounds_name_every_variable_and_limit_the_problem_takes():
    """The bounds table's rows (``around_bounds``): a label for each design variable
    (``analytic.design_space.VARIABLE_NAMES``) and for each limit the page may set (``LIMITS``)."""
    import time

    from analytic.design_space import VARIABLE_NAMES
    from workbench.optimising import LIMITS

    client = page_client()
    job = client.post("/api/jobs", json={"tool": "around_bounds", "design": table3(), "inputs": {}}).json()
    while job["state"] == "running":
        time.sleep(0.05)
        job = client.get(f"/api/jobs/{job['id']}").json()
    result = job["result"]
    assert [row["name"] for row in result["variables"]] == list(VARIABLE_NAMES)
    assert all(row["label"] for row in result["variables"])
    assert [row["name"] for row in result["limit_rows"]] == list(LIMITS) == list(result["limits"])
    assert {row["kind"] for row in result["limit_rows"]} == {"length", "force"}
