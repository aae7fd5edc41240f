// The design form: one row per field (slider and number box in the shown units), grouped as the server lists them.

// Each field as the server describes it (``GET /api/meta``'s groups, by name; filled by ``buildForm``):
// its ``default`` (or ``default_from``, the field whose value it takes), its slider's ``span`` where
// the span does not follow from its value, and its ``zero_span`` at zero (``workbench.fields``).
const FIELDS = {};
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

// What ``name`` is where ``design`` leaves it out, file units (undefined: no default).
export function defaultOf(design, name) {
  const field = FIELDS[name];
  if (!field) return undefined;
  if (field.default_from) return getValue(design, field.default_from) ?? defaultOf(design, field.default_from);
  return field.default;
}

// A span's end: a number, or a field's value (``"-table.key"``: minus it).
function end(design, bound) {
  if (typeof bound === "number") return bound;
  return bound.startsWith("-") ? -getValue(design, bound.slice(1)) : getValue(design, bound);
}

function span(name, value, design) {
  const field = FIELDS[name] ?? {};
  if (field.span) return field.span.map((bound) => end(design, bound));
  if (value > 0) return [value / SPREAD, value * SPREAD];
  return (field.zero_span ?? [0, 1]).map((bound) => end(design, bound));
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
      FIELDS[field.name] = field;
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
// (which rows apply to it: applies.js). A field the design leaves out shows its default, greyed (the
// number box's placeholder, the row marked ``unset``), its slider there.
export function fillForm(form, design, units, system) {
  for (const row of form.querySelectorAll(".field")) {
    const name = row.dataset.field;
    const value = getValue(design, name);
    const unset = value === undefined || value === null;
    const fallback = defaultOf(design, name);
    row.classList.toggle("unset", unset && fallback !== undefined);
    if (!row.dataset.kind) {
      row.querySelector("select").value = value ?? fallback ?? row.querySelector("select").options[0].value;
      continue;
    }
    const kind = row.dataset.kind;
    const number = row.querySelector("input[type=number]");
    const slider = row.querySelector(".slider");
    row.querySelector(".unit").textContent = unitLabel(units, kind, system);
    const shown = unset ? fallback : value;
    number.value = unset ? "" : round(shownValue(units, kind, system, value));
    number.placeholder = unset && fallback !== undefined ? String(round(shownValue(units, kind, system, fallback))) : "";
    const [low, high] = span(name, shown ?? 0, design).map((v) => shownValue(units, kind, system, v));
    row.span = [low, high];
    slider.value = shown === undefined ? 0 : Math.round((shownValue(units, kind, system, shown) - low) / (high - low) * STEPS);
    row.onSlide = () => {
      row.classList.remove("unset");
      const shown = low + (high - low) * slider.value / STEPS;
      number.value = round(shown);
      row.onChange(name, fileValue(units, kind, system, Number(number.value)));
    };
    row.onType = (text) => {
      row.classList.toggle("unset", text.trim() === "" && fallback !== undefined);
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
