// Only what applies: the fields a design's choices leave without effect (analytic/design.py's rules),
// disabled with the reason (or hidden), and the values the design contract refuses there set aside
// until the choice comes back.

// Why the release angle's row is disabled under the ideal rule (the value is kept for another rule).
export const IDEAL_NOTE = "the ideal rule finds the release itself";

const kind = (d) => d.machine.kind ?? "hinged";
const drag = (d) => d.projectile.drag ?? "none";
const rolling = (d) => d.base?.mobility === "rolling";
const NO_DRAG = "no drag law (drag = none): the air does not act on the projectile";
const NOT_HINGED = (d) => `a ${kind(d)} machine has no hinge: its counterweight is rigid on the arm`;
const NOT_FLOATING = (d) => `only a floating-arm machine has a guide and a track; a ${kind(d)} machine has neither`;
const positive = (v) => typeof v === "number" && v > 0;

// Each rule: the field; whether it applies to a design; why it does not (text, or a function of the
// design); ``refused``: the design contract refuses a value there when it does not apply (which
// values: ``refuses``; any by default), so the page sets it aside; ``hidden``: the row is hidden
// rather than disabled; ``restore``: the value it takes back when nothing was set aside.
export const RULES = [
  {field: "machine.counterweight_link", applies: (d) => kind(d) === "hinged", hidden: true, refused: true, refuses: positive,
    why: (d) => `a ${kind(d)} machine has no link: its counterweight is rigid on the arm`,
    restore: (d) => d.machine.arm_short / 3},
  {field: "machine.release_angle", applies: (d) => d.machine.release_rule !== "ideal", why: IDEAL_NOTE},
  {field: "projectile.drag_coefficient", applies: (d) => drag(d) === "constant", refused: true,
    why: (d) => `only the constant drag law uses a coefficient (drag = ${drag(d)})`},
  {field: "projectile.drag_factor", applies: (d) => drag(d) !== "none", why: NO_DRAG},
  {field: "environment.air_density", applies: (d) => drag(d) !== "none", why: NO_DRAG},
  {field: "environment.air_viscosity", applies: (d) => drag(d) === "smooth-sphere" || drag(d) === "golf-ball",
    why: (d) => (drag(d) === "none" ? NO_DRAG
      : "the constant drag law does not depend on the Reynolds number, so not on the air's viscosity")},
  {field: "environment.wind_speed", applies: (d) => drag(d) !== "none",
    why: "no drag law (drag = none): the wind does not act on the projectile"},
  {field: "base.mobility", applies: (d) => kind(d) !== "floating-arm", refused: true, refuses: (v) => v === "rolling",
    why: "a floating-arm machine's axle already rides its track: its frame cannot roll"},
  {field: "base.mass", applies: rolling, why: "only a rolling frame's mass moves (a fixed frame is bolted down)"},
  {field: "losses.axle_radius", applies: (d) => positive(d.losses?.axle_friction) || positive(d.losses?.axle_static_friction),
    why: "no axle friction: the radius only sets its torque"},
  {field: "losses.hinge_friction", applies: (d) => kind(d) === "hinged", refused: true, refuses: positive, why: NOT_HINGED},
  {field: "losses.hinge_static_friction", applies: (d) => kind(d) === "hinged", refused: true, refuses: positive,
    why: NOT_HINGED},
  {field: "losses.hinge_radius", applies: (d) => kind(d) === "hinged"
    && (positive(d.losses?.hinge_friction) || positive(d.losses?.hinge_static_friction)),
  why: (d) => (kind(d) === "hinged" ? "no hinge friction: the radius only sets its torque" : NOT_HINGED(d))},
  ...["guide_friction", "track_friction", "guide_static_friction", "track_static_friction"].map((key) => (
    {field: `losses.${key}`, applies: (d) => kind(d) === "floating-arm", refused: true, refuses: positive,
      why: NOT_FLOATING})),
];

function get(design, name) {
  const [table, key] = name.split(".");
  return design[table]?.[key];
}

function put(design, name, value) {
  const [table, key] = name.split(".");
  design[table] = design[table] || {};
  if (value === undefined) delete design[table][key];
  else design[table][key] = value;
}

// The values set aside, by field: kept for when their choice comes back.
const setAside = {};

// Sets aside from ``design`` each value the design contract refuses under its choices, and puts back
// each value set aside whose choice has come back (or the rule's own value, when none was).
export function settle(design) {
  for (const rule of RULES.filter((r) => r.refused)) {
    const value = get(design, rule.field);
    const refuses = rule.refuses ?? ((v) => v !== undefined && v !== null);
    if (!rule.applies(design)) {
      if (refuses(value)) { setAside[rule.field] = value; put(design, rule.field, undefined); }
    } else if (!refuses(value)) {
      const back = setAside[rule.field] ?? rule.restore?.(design);
      if (back !== undefined) put(design, rule.field, back);
      delete setAside[rule.field];
    }
  }
}

function reason(rule, design) {
  return typeof rule.why === "function" ? rule.why(design) : rule.why;
}

// Marks each rule's row in ``form`` (hidden, or disabled with its reason), and the field choices of the
// tools (``selects``: aim and what-if), whose options for a field that does not apply are disabled
// (a choice of one moves to the counterweight's mass).
export function followChoices(form, design, selects = []) {
  for (const rule of RULES) {
    const row = form.querySelector(`.field[data-field="${rule.field}"]`);
    if (!row) continue;
    const applies = rule.applies(design);
    const why = applies ? "" : reason(rule, design);
    if (rule.hidden) row.hidden = !applies;
    for (const input of row.querySelectorAll("input, select")) input.disabled = !applies;
    row.classList.toggle("inapplicable", !applies);
    let note = row.querySelector(".note");
    if (!note) {
      note = document.createElement("p");
      note.className = "note";
      row.querySelector(".error").before(note);
    }
    note.hidden = applies;
    note.textContent = why;
    for (const select of selects) {
      const option = select.querySelector(`option[value="${rule.field}"]`);
      if (!option) continue;
      option.disabled = !applies;
      option.title = why;
      if (!applies && select.value === rule.field) select.value = "machine.counterweight_mass";
    }
  }
}
