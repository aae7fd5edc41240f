// The firing-table tool: every setting of one field that lands on each target, a row a target and a
// column a projectile mass, run as a server job (tools.firing); a click on a setting adopts it.
import {fileValue, setValue, shownValue, unitLabel} from "./form.js";
import {keepShown, runJob} from "./tools.js";

const $ = (id) => document.getElementById(id);

export function setupFiring(state, api) {
  const fields = state.meta.groups.flatMap((g) => g.fields).filter((f) => f.kind);
  $("firing-field").innerHTML = fields.map((f) => `<option value="${f.name}">${f.name}</option>`).join("");
  $("firing-field").value = "machine.release_angle";
  $("firing").addEventListener("click", async () => {
    const units = state.meta.units;
    const length = (id) => fileValue(units, "length", state.system, Number($(id).value));
    const mass = (id) => fileValue(units, "mass", state.system, Number($(id).value));
    const targets = [length("firing-from"), length("firing-to"), Number($("firing-steps").value)];
    const masses = $("firing-masses").checked
      ? [mass("firing-mass-from"), mass("firing-mass-to"), Number($("firing-mass-steps").value)] : null;
    const name = $("firing-field").value;
    const result = await runJob(state, "firing_table", {field: name, targets, masses}, api);
    const kind = fields.find((f) => f.name === name).kind;
    if (result) keepShown("firing", () => firingTable(state, api, result, kind));
  });
}

// Targets down, masses across; each cell its settings (shown units), each a button that adopts it.
function firingTable(state, api, result, kind) {
  const units = state.meta.units;
  const masses = [...new Set(result.rows.map((r) => r.projectile_mass))];
  const targets = [...new Set(result.rows.map((r) => r.target))];
  const unit = unitLabel(units, kind, state.system);
  const table = $("firing-table");
  table.innerHTML = `<caption>${result.field} (${unit}) to land on each target</caption>`
    + `<tr><th>target</th>${masses.map((m) => `<th>${api.show(m, "mass", 3)}</th>`).join("")}</tr>`;
  for (const target of targets) {
    const row = document.createElement("tr");
    row.innerHTML = `<th>${api.show(target, "length", 1)}</th>`;
    for (const m of masses) {
      const cell = document.createElement("td");
      const entry = result.rows.find((r) => r.target === target && r.projectile_mass === m);
      if (!entry.values.length) cell.textContent = "out of reach";
      for (const value of entry.values) {
        const button = document.createElement("button");
        button.type = "button";
        button.textContent = shownValue(units, kind, state.system, value).toFixed(kind === "angle" ? 1 : 3);
        button.title = `adopt ${result.field} = ${button.textContent} ${unit} (and this projectile mass)`;
        button.addEventListener("click", () => {
          setValue(state.design, "projectile.mass", m);
          setValue(state.design, result.field, value);
          api.loadDesign(state.design);
        });
        cell.append(button);
      }
      row.append(cell);
    }
    table.append(row);
  }
  table.hidden = false;
}
