// Only what applies: the fields a design's choices leave without effect, by the server's rules
// (``GET /api/meta``'s ``rules``: workbench/applies.py, after analytic/design.py's), disabled with the
// reason (or hidden), and the values the design contract refuses there set aside until the choice
// comes back.
import {defaultOf, getValue, setValue} from "./form.js";

// The server's rules (``useRules``).
let RULES = [];

export function useRules(rules) {
  RULES = rules;
}

const positive = (v) => typeof v === "number" && v > 0;
// A field's value in ``design``, or its default where the design leaves it out.
const valueOf = (design, name) => getValue(design, name) ?? defaultOf(design, name);

function holds(condition, design) {
  if (condition.positive) return condition.positive.some((name) => positive(valueOf(design, name)));
  const value = valueOf(design, condition.field);
  return condition.in ? condition.in.includes(value) : !condition.not_in.includes(value);
}

// The first condition of ``rule`` that ``design`` fails (null: the field applies).
function failing(rule, design) {
  return rule.when.find((condition) => !holds(condition, design)) ?? null;
}

// Why: the condition's text, each ``{table.key}`` the design's value of that field.
function reason(condition, design) {
  return condition.why.replace(/\{([a-z_]+\.[a-z_]+)\}/g, (_, name) => String(valueOf(design, name)));
}

// Which values the design contract refuses where the rule's field does not apply.
function refuses(rule, value) {
  if (rule.refuses === "positive") return positive(value);
  if (Array.isArray(rule.refuses)) return rule.refuses.includes(value);
  return value !== undefined && value !== null;
}

// The values set aside, by field: kept for when their choice comes back.
const setAside = {};

// Sets aside from ``design`` each value the design contract refuses under its choices, and puts back
// each value set aside whose choice has come back (or the rule's own value, when none was).
export function settle(design) {
  for (const rule of RULES.filter((r) => r.refuses)) {
    const value = getValue(design, rule.field);
    if (failing(rule, design)) {
      if (refuses(rule, value)) { setAside[rule.field] = value; setValue(design, rule.field, undefined); }
    } else if (!refuses(rule, value)) {
      const [from, factor] = rule.restore ?? [];
      const back = setAside[rule.field] ?? (from === undefined ? undefined : valueOf(design, from) * factor);
      if (back !== undefined) setValue(design, rule.field, back);
      delete setAside[rule.field];
    }
  }
}

// Marks each rule's row in ``form`` (hidden, or disabled with its reason), and the field choices of the
// tools (``selects``: aim and what-if), whose options for a field that does not apply are disabled
// (a choice of one moves to the counterweight's mass).
export function followChoices(form, design, selects = []) {
  for (const rule of RULES) {
    const row = form.querySelector(`.field[data-field="${rule.field}"]`);
    if (!row) continue;
    const failed = failing(rule, design);
    const applies = failed === null;
    const why = applies ? "" : reason(failed, design);
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
