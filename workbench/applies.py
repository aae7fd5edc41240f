"""Only what applies: which design fields a design's choices leave without effect, and why (served to the page).

Each rule names a field and the conditions under which it has an effect
(all must hold; the first that fails gives the reason the page shows at
the field). The page reads them from ``GET /api/meta`` (``rules``) and
evaluates them on the design it holds, a field left out taking its
default (``workbench.fields.field_default``). Where the design contract
(``analytic.design``) refuses a value under a choice, the rule says which
values (``refuses``: ``"positive"``, ``"set"`` or a list of values), so
that the page sets such a value aside until the choice comes back, and
``restore`` gives the value a field takes back when none was set aside:
``[field, factor]``, that field's value times the factor.

A condition is ``{"field", "in": [values]}``, ``{"field", "not_in": [values]}``
or ``{"positive": [fields]}`` (any of them above zero), with ``why``, a text
in which ``{table.key}`` stands for that field's value.
"""

from __future__ import annotations

from typing import Any

from analytic.design import SLIDES

#: The drag laws that depend on the Reynolds number, so on the air's viscosity (``analytic.aero``).
REYNOLDS_LAWS = ("smooth-sphere", "golf-ball")
#: Why the release angle does nothing under the ideal rule (its value is kept for another rule).
IDEAL_NOTE = "the ideal rule finds the release itself"
NO_DRAG = "no drag law (drag = none): the air does not act on the projectile"
NOT_HINGED = "a {machine.kind} machine has no hinge: its counterweight is rigid on the arm"
NOT_FLOATING = "only a floating-arm machine has a guide and a track; a {machine.kind} machine has neither"
#: A hinged machine's link, when it comes back with nothing set aside: a third of its short arm.
LINK_OF_SHORT_ARM = 1 / 3


def _is(field: str, values: tuple[str, ...], why: str) -> dict[str, Any]:
    return {"field": field, "in": list(values), "why": why}


def _not(field: str, values: tuple[str, ...], why: str) -> dict[str, Any]:
    return {"field": field, "not_in": list(values), "why": why}


def _any_positive(fields: tuple[str, ...], why: str) -> dict[str, Any]:
    return {"positive": list(fields), "why": why}


HINGED = _is("machine.kind", ("hinged",), NOT_HINGED)
FLOATING = _is("machine.kind", ("floating-arm",), NOT_FLOATING)
DRAGS = _not("projectile.drag", ("none",), NO_DRAG)

#: The rules, in the form's order.
RULES = (
    {"field": "machine.counterweight_link", "hidden": True, "refuses": "positive",
     "restore": ["machine.arm_short", LINK_OF_SHORT_ARM],
     "when": [_is("machine.kind", ("hinged",), "a {machine.kind} machine has no link: its counterweight is rigid "
                                               "on the arm")]},
    {"field": "machine.release_angle", "when": [_not("machine.release_rule", ("ideal",), IDEAL_NOTE)]},
    {"field": "projectile.drag_coefficient", "refuses": "set",
     "when": [_is("projectile.drag", ("constant",),
                  "only the constant drag law uses a coefficient (drag = {projectile.drag})")]},
    {"field": "projectile.drag_factor", "when": [DRAGS]},
    {"field": "environment.air_density", "when": [DRAGS]},
    {"field": "environment.air_viscosity",
     "when": [DRAGS, _is("projectile.drag", REYNOLDS_LAWS, "the constant drag law does not depend on the Reynolds "
                                                           "number, so not on the air's viscosity")]},
    {"field": "environment.wind_speed",
     "when": [_not("projectile.drag", ("none",), "no drag law (drag = none): the wind does not act on the projectile")]},
    {"field": "base.mobility", "refuses": ["rolling"],
     "when": [_not("machine.kind", ("floating-arm",), "a floating-arm machine's axle already rides its track: its "
                                                       "frame cannot roll")]},
    {"field": "base.mass",
     "when": [_is("base.mobility", ("rolling",), "only a rolling frame's mass moves (a fixed frame is bolted down)")]},
    {"field": "losses.axle_radius",
     "when": [_any_positive(("losses.axle_friction", "losses.axle_static_friction"),
                            "no axle friction: the radius only sets its torque")]},
    {"field": "losses.hinge_friction", "refuses": "positive", "when": [HINGED]},
    {"field": "losses.hinge_static_friction", "refuses": "positive", "when": [HINGED]},
    {"field": "losses.hinge_radius",
     "when": [HINGED, _any_positive(("losses.hinge_friction", "losses.hinge_static_friction"),
                                    "no hinge friction: the radius only sets its torque")]},
    *({"field": f"losses.{slide}{kind}_friction", "refuses": "positive", "when": [FLOATING]}
      for slide in SLIDES for kind in ("", "_static")),
)


def rules_table() -> list[dict[str, Any]]:
    """The rules as ``GET /api/meta`` gives them (``rules``)."""
    return [dict(rule) for rule in RULES]
