// The optimiser's panel: around the design on screen (its bounds and limits shown and editable in the
// page's units) or the paper's problem, the optimum and the front of range against peak axle load.
import {defaultOf, fileValue, getValue, setValue, shownValue, unitLabel} from "./form.js";
import {drawAxis, plotMargins, readableFont} from "./plots.js";

const $ = (id) => document.getElementById(id);

// The user's own bounds and limits (file units: m, deg, N), kept until another design is loaded;
// the rest are the server's defaults around the design on screen.
let edits = {}, limitEdits = {}, defaults = null, last = null;

export function setupOptimise(state, api, runJob) {
  const units = () => state.meta.units;
  const shown = (kind, v) => api.round(shownValue(units(), kind, state.system, v));
  const refresh = async () => {
    if (!$("optimise-bounds").open || $("optimise-problem").value !== "around") return;
    const result = await runJob(state, "around_bounds", {}, api);
    if (result) { defaults = result; renderBounds(); }
  };
  const renderBounds = () => {
    if (!defaults) return;
    const rows = defaults.variables.filter((v) => !v.fixed).map((v) => {
      const [low, high] = edits[v.name] ?? [v.lower, v.upper];
      return `<tr data-name="${v.name}" data-kind="${v.kind}"><td>${v.label}</td><td>${shown(v.kind, v.value)}</td>`
        + `<td><input type="number" step="any" aria-label="${v.name} lower" value="${shown(v.kind, low)}"></td>`
        + `<td><input type="number" step="any" aria-label="${v.name} upper" value="${shown(v.kind, high)}"></td>`
        + `<td>${unitLabel(units(), v.kind, state.system)}</td></tr>`;
    }).join("");
    const limits = defaults.limit_rows.map(({name, label, kind}) => {
      const value = name in limitEdits ? limitEdits[name] : defaults.limits[name];
      return `<tr data-limit="${name}" data-kind="${kind}"><td colspan="2">${label}</td><td colspan="2">`
        + `<input type="number" step="any" min="0" aria-label="${name}" placeholder="none" `
        + `value="${value === null ? "" : shown(kind, value)}"></td><td>${unitLabel(units(), kind, state.system)}</td></tr>`;
    }).join("");
    $("bounds-table").innerHTML = "<tr><th>variable</th><th>now</th><th>from</th><th>to</th><th></th></tr>"
      + rows + `<tr><th colspan="5">limits (the design's own size unless changed)</th></tr>` + limits;
  };
  $("bounds-table").addEventListener("change", (event) => {
    const row = event.target.closest("tr");
    const kind = row.dataset.kind;
    const value = event.target.value === "" ? null : fileValue(units(), kind, state.system, Number(event.target.value));
    if (row.dataset.limit) { limitEdits[row.dataset.limit] = value; return; }
    const [low, high] = [...row.querySelectorAll("input")].map((input) => fileValue(units(), kind, state.system, Number(input.value)));
    edits[row.dataset.name] = [low, high];
  });
  $("optimise-bounds").addEventListener("toggle", refresh);
  $("bounds-reset").addEventListener("click", () => { edits = {}; limitEdits = {}; renderBounds(); });
  $("optimise-problem").addEventListener("change", () => {
    const paper = $("optimise-problem").value === "paper";
    $("optimise-bounds").hidden = paper;
    $("paper-note").hidden = !paper;
    refresh();
  });
  // Field edits move the centre: the defaults follow (the user's own bounds stay).
  let timer = null;
  $("fields").addEventListener("change", () => { clearTimeout(timer); timer = setTimeout(refresh, 300); });
  $("units").addEventListener("change", () => {
    renderBounds();
    if (last) render(state, api, last);
  });

  for (const [button, front] of [["optimise", false], ["front", true]]) {
    $(button).addEventListener("click", async () => {
      const problem = $("optimise-problem").value;
      const generations = Math.round(Number($("optimise-generations").value));
      const inputs = {front, problem, generations};
      if (problem === "around") { inputs.bounds = edits; inputs.limits = limitEdits; }
      const result = await runJob(state, "optimise", inputs, api);
      if (!result) return;
      last = {...result, front};
      render(state, api, last);
    });
  }
}

// Another design loaded (a preset, a file, an adopted optimum): the bounds centre on it afresh.
export function followDesign() {
  edits = {}; limitEdits = {}; defaults = null;
  if ($("optimise-bounds")?.open) $("optimise-bounds").dispatchEvent(new Event("toggle"));
}

function render(state, api, result) {
  optimiseTable(state, api, result);
  if (result.front) frontPlot(state, api, result);
  else $("front-plot").hidden = true;
}

// Adopt: around the design, only the optimised fields change; the paper's problem's machine is taken whole.
function adopt(state, api, point) {
  if (!point.changes) { api.loadDesign(point.design); return; }
  const design = structuredClone(state.design);
  for (const [name, value] of Object.entries(point.changes)) setValue(design, name, value);
  api.loadDesign(design);
}

// The axle load as the tables name it (``GET /api/meta``'s ``loads``).
function axleLoadLabel(state) {
  const kind = getValue(state.design, "machine.kind") ?? defaultOf(state.design, "machine.kind");
  return state.meta.loads.find((l) => l.name === "peak_axle_load").labels[kind];
}

function describeDesign(state, api, design) {
  const m = design.machine;
  const length = (v) => api.show(v, "length");
  return `arm ${length(m.arm_long)} + ${length(m.arm_short)}, sling ${length(m.sling_length)}`
    + (m.release_angle === undefined ? "" : `, release ${m.release_angle.toFixed(1)} deg`);
}

// Each optimum: its axle-load cap, range and peak axle load, its arm and sling, and a button that adopts it;
// the caption says which problem, and what the design on screen does.
function optimiseTable(state, api, result) {
  const table = $("optimise-table");
  const start = result.start;
  const problem = result.problem === "paper" ? "the paper's problem (its table-top machine, adopted whole)"
    : `around the design on screen`;
  const now = start.range === null ? `does not throw (${start.status})`
    : `throws ${api.show(start.range, "length")} at peak axle load ${api.show(start.peak_axle_load, "force", 0)}`;
  const breaks = start.violates.length ? `; it breaks: ${start.violates.join(", ")}` : "";
  table.innerHTML = `<caption>Optimised ${problem}. The design on screen ${now}${breaks}.</caption>`
    + "<tr><th>axle load cap</th><th>range</th><th>peak axle load</th><th>design</th><th></th></tr>";
  result.points.forEach((point, i) => {
    const row = document.createElement("tr");
    row.innerHTML = `<td>${point.axle_limit === null ? "none" : api.show(point.axle_limit, "force", 0)}</td>`
      + `<td>${api.show(point.range, "length")}</td><td>${api.show(point.peak_axle_load, "force", 0)}</td>`
      + `<td>${describeDesign(state, api, point.design)}</td>`
      + `<td><button type="button" data-testid="adopt-${i}">Adopt</button></td>`;
    row.querySelector("button").addEventListener("click", () => adopt(state, api, point));
    table.append(row);
  });
  table.hidden = false;
}

// The front of range against peak axle load: a point per optimum and the design on screen (a grey
// diamond), nearest point to a click (or a second tap: the first picks it) adopted. Each point's
// place, in the canvas's CSS pixels, is in its ``data-points`` (what a click must hit), the
// design on screen's in ``data-start``.
const PICK_RADIUS = 24;   // canvas pixels: a fingertip
function frontPlot(state, api, result) {
  const canvas = $("front-plot");
  canvas.hidden = false;
  const ctx = canvas.getContext("2d");
  const W = canvas.width, H = canvas.height, margin = plotMargins(canvas);
  const box = {left: margin.left, right: W - margin.right, top: margin.top, bottom: H - margin.bottom};
  const units = state.meta.units, system = state.system;
  // Each point's load and range in the shown units, as the axes read.
  const load = (p) => shownValue(units, "force", system, p.peak_axle_load);
  const reach = (p) => shownValue(units, "length", system, p.range);
  const shown = result.points.filter((p) => p.range !== null && p.peak_axle_load !== null);
  const start = result.problem === "paper" || result.start.range === null ? null : result.start;
  const all = start ? [...shown, start] : shown;
  const loads = all.map(load), ranges = all.map(reach);
  const span = (a) => { const lo = Math.min(...a), hi = Math.max(...a); const pad = 0.08 * (hi - lo || hi || 1); return [lo - pad, hi + pad]; };
  const [x0, x1] = span(loads), [y0, y1] = span(ranges);
  const X = (v) => box.left + (box.right - box.left) * (v - x0) / (x1 - x0);
  const Y = (v) => box.bottom - (box.bottom - box.top) * (v - y0) / (y1 - y0);
  const at = shown.map((p) => [X(load(p)), Y(reach(p))]);
  const loadName = axleLoadLabel(state);
  const describe = (p) => `range ${api.show(p.range, "length")} at ${loadName} ${api.show(p.peak_axle_load, "force", 0)}`
    + (p.axle_limit === null ? " (no cap)" : ` (cap ${api.show(p.axle_limit, "force", 0)})`);
  const redraw = (picked) => {
    ctx.clearRect(0, 0, W, H);
    drawAxis(ctx, canvas, box, "bottom", {lo: x0, hi: x1, at: X,
      title: `${loadName} (${unitLabel(units, "force", system)})`});
    drawAxis(ctx, canvas, box, "left", {lo: y0, hi: y1, at: Y, title: `range (${unitLabel(units, "length", system)})`,
      color: "#c0392b"});
    const order = at.map((_, i) => i).sort((a, b) => loads[a] - loads[b]);
    ctx.strokeStyle = "#c0392b"; ctx.lineWidth = 1.5; ctx.beginPath();
    order.forEach((i, k) => (k ? ctx.lineTo(...at[i]) : ctx.moveTo(...at[i])));
    ctx.stroke();
    at.forEach(([x, y], i) => {
      ctx.fillStyle = i === picked ? "#7d3c98" : "#c0392b";
      ctx.beginPath(); ctx.arc(x, y, i === picked ? 8 : 6, 0, 2 * Math.PI); ctx.fill();
    });
    if (start) {
      const [x, y] = [X(load(start)), Y(reach(start))];
      ctx.fillStyle = "#555"; ctx.font = readableFont(canvas); ctx.beginPath();
      ctx.moveTo(x, y - 7); ctx.lineTo(x + 7, y); ctx.lineTo(x, y + 7); ctx.lineTo(x - 7, y); ctx.closePath(); ctx.fill();
      ctx.textAlign = x > (box.left + box.right) / 2 ? "right" : "left";
      ctx.fillText("on screen", x + (x > (box.left + box.right) / 2 ? -10 : 10), y + 4);
    }
  };
  redraw(-1);
  const scale = () => canvas.clientWidth / canvas.width;
  canvas.dataset.points = JSON.stringify(at.map(([x, y]) => [x * scale(), y * scale()]));
  canvas.dataset.start = start ? JSON.stringify([X(load(start)) * scale(), Y(reach(start)) * scale()]) : "";
  const nearest = (event) => {
    const x = event.offsetX / scale(), y = event.offsetY / scale();
    let best = -1, distance = PICK_RADIUS;
    at.forEach(([px, py], i) => { const d = Math.hypot(px - x, py - y); if (d <= distance) { best = i; distance = d; } });
    return best;
  };
  const pick = (i) => {
    redraw(i);
    $("front-pick").hidden = i < 0;
    if (i >= 0) $("front-pick").textContent = `${describe(shown[i])}: click to adopt`;
  };
  let touch = false, picked = -1;
  canvas.onpointerdown = (event) => { touch = event.pointerType !== "mouse"; };
  canvas.onpointermove = (event) => { if (event.pointerType === "mouse") { picked = nearest(event); pick(picked); } };
  canvas.onclick = (event) => {
    const i = nearest(event);
    if (i < 0) return;
    if (touch && i !== picked) { picked = i; pick(i); return; }   // a finger's first tap picks
    picked = -1;
    redraw(i);
    $("front-pick").hidden = false;
    $("front-pick").textContent = `adopted: ${describe(shown[i])}`;
    adopt(state, api, shown[i]);
  };
}
