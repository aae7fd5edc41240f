// The design form: one row per field (slider and number box in the shown units), grouped as the server lists them.

// Slider spans, in file units, for fields whose span does not follow from their value (the server's
// ``span`` of each such field, ``workbench.fields.SPANS``; filled by ``buildForm``).
const FIXED_SPANS = {};
// A positive value's slider spans value / SPREAD to value * SPREAD.
const SPREAD = 3;
const STEPS = 400;

export function shownValue(units, kind, system, value) {
  return value * units[kind][system].factor;
}

export function fileValue(units, kind, system, shown) {
  return shown / units[kind][system].factor;
}

export function unitLabel(units, kind, system) {
  return units[kind][system].label;
}

function span(name, value, design) {
  if (FIXED_SPANS[name]) return FIXED_SPANS[name];
  if (name === "machine.arm_cg") return [-design.machine.arm_short, design.machine.arm_long];
  // No sling or pouch mass yet: up to the projectile's (a sling as heavy as what it throws).
  if ((name === "machine.sling_mass" || name === "machine.pouch_mass") && !(value > 0)) {
    return [0, design.projectile.mass];
  }
  if (value > 0) return [value / SPREAD, value * SPREAD];
  if (name.endsWith("_radius")) return [0, 0.1];
  return [0, 1];
}

export function getValue(design, name) {
  const [table, key] = name.split(".");
  return design[table] ? design[table][key] : undefined;
}

export function setValue(design, name, value) {
  const [table, key] = name.split(".");
  design[table] = design[table] || {};
  if (value === undefined) delete design[table][key];
  else design[table][key] = value;
}

// Builds the rows; ``onChange(name, value)`` gets file units (undefined: the field left empty).
export function buildForm(form, groups, onChange) {
  form.textContent = "";
  for (const group of groups) {
    const box = document.createElement("details");
    box.open = group.table === "machine" || group.table === "projectile";
    box.innerHTML = `<summary>${group.title}</summary>`;
    for (const field of group.fields) {
      if (field.span) FIXED_SPANS[field.name] = field.span;
      box.append(fieldRow(field, onChange));
    }
    form.append(box);
  }
}

function fieldRow(field, onChange) {
  const row = document.createElement("div");
  row.className = "field";
  row.dataset.field = field.name;
  const id = `f-${field.name.replace(".", "-")}`;
  const help = `<details class="help"><summary aria-label="about ${field.key}">?</summary>${field.help}</details>`;
  if (field.choices) {
    const options = field.choices.map((c) => `<option value="${c}">${c}</option>`).join("");
    row.innerHTML = `<label for="${id}">${field.key.replaceAll("_", " ")}</label>${help}
      <select id="${id}" name="${field.name}">${options}</select><p class="note" hidden></p><p class="error" hidden></p>`;
    row.querySelector("select").addEventListener("change", (e) => onChange(field.name, e.target.value));
    return row;
  }
  row.dataset.kind = field.kind;
  row.innerHTML = `<label for="${id}">${field.key.replaceAll("_", " ")}</label>${help}
    <input type="range" class="slider" min="0" max="${STEPS}" aria-label="${field.key} slider">
    <input type="number" id="${id}" name="${field.name}" step="any">
    <span class="unit"></span><p class="note" hidden></p><p class="error" hidden></p>`;
  row.querySelector(".slider").addEventListener("input", () => row.onSlide());
  row.querySelector("input[type=number]").addEventListener("input", (e) => row.onType(e.target.value));
  row.onChange = onChange;
  return row;
}

// Shows ``design`` in the form in ``system``'s units, and sets each slider's span around its value
// (which rows apply to it: applies.js).
export function fillForm(form, design, units, system) {
  for (const row of form.querySelectorAll(".field")) {
    const name = row.dataset.field;
    const value = getValue(design, name);
    if (!row.dataset.kind) {
      row.querySelector("select").value = value ?? row.querySelector("select").options[0].value;
      continue;
    }
    const kind = row.dataset.kind;
    const number = row.querySelector("input[type=number]");
    const slider = row.querySelector(".slider");
    row.querySelector(".unit").textContent = unitLabel(units, kind, system);
    number.value = value === undefined || value === null ? "" : round(shownValue(units, kind, system, value));
    const [low, high] = span(name, value ?? 0, design).map((v) => shownValue(units, kind, system, v));
    row.span = [low, high];
    slider.value = value === undefined || value === null ? 0 : Math.round((number.value - low) / (high - low) * STEPS);
    row.onSlide = () => {
      const shown = low + (high - low) * slider.value / STEPS;
      number.value = round(shown);
      row.onChange(name, fileValue(units, kind, system, Number(number.value)));
    };
    row.onType = (text) => {
      if (text.trim() === "") return row.onChange(name, undefined);
      const shown = Number(text);
      row.onChange(name, Number.isFinite(shown) ? fileValue(units, kind, system, shown) : text);
    };
  }
}

// Six significant figures: what a builder reads, without a float's tail.
export function round(value) {
  return Number(Number(value).toPrecision(6));
}

export function showError(form, field, message) {
  for (const row of form.querySelectorAll(".field")) {
    const error = row.querySelector(".error");
    const mine = row.dataset.field === field;
    error.hidden = !mine;
    error.textContent = mine ? message : "";
    for (const input of row.querySelectorAll("input, select")) input.toggleAttribute("aria-invalid", mine);
    if (mine) row.closest("details").open = true;
  }
  return [...form.querySelectorAll(".field")].some((row) => row.dataset.field === field);
}
