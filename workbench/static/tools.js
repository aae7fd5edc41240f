// The tools panel: best pin, aim, what-if, ghosts and the cross-check, run as server jobs with progress and cancel.
import {crosscheckTable} from "./crosscheck.js";
import {defaultOf, fileValue, getValue, setValue, shownValue, unitLabel} from "./form.js";
import {followDesign, setupOptimise} from "./optimise.js";
import {drawAxis, plotMargins} from "./plots.js";
import {fieldKinds, localise} from "./units.js";

const $ = (id) => document.getElementById(id);
const CLIENT = Math.random().toString(36).slice(2);
const POLL_MS = 100;
let current = null;
// What each tool shows, redrawn in the new units when they change (``showAgain``).
const shownResults = {};
let toolState = null;

export async function runJob(state, tool, inputs, api) {
  if (current) return null;
  $("tool-error").hidden = true;
  const response = await fetch("/api/jobs", {method: "POST", headers: {"content-type": "application/json"},
    body: JSON.stringify({tool, inputs, design: state.design, client: CLIENT})});
  let job = await response.json();
  if (!response.ok) { toolError(job, state); return null; }
  current = job.id;
  $("progress-row").hidden = false;
  while (job.state === "running") {
    $("progress").value = job.progress;
    await new Promise((resolve) => setTimeout(resolve, POLL_MS));
    job = await (await fetch(`/api/jobs/${job.id}`)).json();
  }
  current = null;
  $("progress-row").hidden = true;
  if (job.state !== "done") { toolError(job.error, state); return null; }
  return job.result;
}

function toolError(error, state = toolState) {
  $("tool-error").hidden = false;
  $("tool-error").textContent = localise(error.error, state.meta.units, state.system, fieldKinds(state.meta.groups));
}

// Redraws what the tools show in ``state``'s units (after the units change).
export function showAgain() {
  for (const show of Object.values(shownResults)) show();
}

// Keeps ``show`` (a function that draws a tool's result in the page's units) as what ``name`` shows,
// redrawn after the units change; draws it now.
export function keepShown(name, show) {
  shownResults[name] = show;
  show();
}

function adoptValue(state, api, name, value) {
  setValue(state.design, name, value);
  api.loadDesign(state.design);
}

function numericFields(state) {
  return state.meta.groups.flatMap((g) => g.fields).filter((f) => f.kind);
}

// The what-if's loads (``GET /api/meta``'s ``loads``), each named as on the machine on screen and with
// the unit it is shown in.
export function labelLoads(state) {
  const select = $("whatif-load");
  const kind = getValue(state.design, "machine.kind") ?? defaultOf(state.design, "machine.kind");
  const chosen = select.value || state.meta.loads[0].name;
  select.innerHTML = state.meta.loads.map((load) => `<option value="${load.name}">${load.labels[kind]} `
    + `(${unitLabel(state.meta.units, load.kind, state.system)})</option>`).join("");
  select.value = chosen;
}

export function setupTools(state, api) {
  toolState = state;
  const fields = numericFields(state);
  const options = fields.map((f) => `<option value="${f.name}">${f.name}</option>`).join("");
  $("aim-field").innerHTML = options;
  $("aim-field").value = "machine.release_angle";
  $("whatif-field").innerHTML = options;
  $("whatif-field").value = "machine.sling_length";
  $("cancel").addEventListener("click", () => current && fetch(`/api/jobs/${current}/cancel`,
    {method: "POST", headers: {"content-type": "application/json"}, body: "{}"}));

  $("best-pin").addEventListener("click", async () => {
    const result = await runJob(state, "best_pin", {}, api);
    if (!result) return;
    if (result.ideal) {   // nothing to scan: the shot's launch angle is the velocity rule's best pin
      $("best-pin-result").textContent = result.value === null
        ? "not needed (the ideal rule): this design does not throw"
        : `not needed: the ideal rule releases at the longest throw itself; for rule velocity set the pin to `
          + `${result.value.toFixed(2)} deg (${api.show(result.range, "length")})`;
      return;
    }
    if (result.value === null) { $("best-pin-result").textContent = "no release angle throws"; return; }
    $("best-pin-result").textContent = `${result.value.toFixed(2)} deg: ${api.show(result.range, "length")}`;
    adoptValue(state, api, "machine.release_angle", result.value);
  });

  $("aim").addEventListener("click", async () => {
    const shown = Number($("aim-target").value);
    const target = fileValue(state.meta.units, "length", state.system, shown);
    const name = $("aim-field").value;
    const result = await runJob(state, "aim", {field: name, target}, api);
    if (!result) return;
    if (!result.solutions.length) {
      $("aim-result").textContent = result.reachable
        ? `out of reach: ${api.show(result.reachable[0], "length")} to ${api.show(result.reachable[1], "length")}`
        : "out of reach: nothing throws";
      return;
    }
    // Of several settings that land on the target, the one nearest the present setting.
    const now = getValue(state.design, name) ?? defaultOf(state.design, name);
    const best = result.solutions.reduce((a, b) => (Math.abs(b.value - now) < Math.abs(a.value - now) ? b : a));
    const kind = fields.find((f) => f.name === name).kind;
    const shownValue_ = shownValue(state.meta.units, kind, state.system, best.value);
    $("aim-result").textContent = `${name} = ${shownValue_.toPrecision(5)} ${unitLabel(state.meta.units, kind, state.system)}`
      + ` lands at ${api.show(best.range, "length")}`;
    adoptValue(state, api, name, best.value);
  });

  $("whatif").addEventListener("click", async () => {
    const name = $("whatif-field").value;
    const value = getValue(state.design, name) ?? defaultOf(state.design, name);
    if (typeof value !== "number") return toolError({error: `${name} is not set in this design`});
    const row = document.querySelector(`.field[data-field="${name}"]`);
    const kind = row.dataset.kind;
    const [low, high] = row.span.map((v) => fileValue(state.meta.units, kind, state.system, v));
    const result = await runJob(state, "what_if", {field: name, low, high, steps: 41, load: $("whatif-load").value}, api);
    if (!result) return;
    shownResults.whatIf = () => plotSweep(state, api, result, kind);
    shownResults.whatIf();
  });

  $("ghost").addEventListener("click", () => {
    if (!state.shot?.history?.flight_path.length) return;
    state.ghosts.push({path: state.shot.history.flight_path});
    $("ghost-count").textContent = `${state.ghosts.length} ghost${state.ghosts.length === 1 ? "" : "s"}`;
    api.draw();
  });
  $("clear-ghosts").addEventListener("click", () => {
    state.ghosts = [];
    state.twin = null;
    $("ghost-count").textContent = "0 ghosts";
    api.draw();
  });

  setupOptimise(state, api, runJob);

  $("crosscheck").addEventListener("click", async () => {
    const result = await runJob(state, "crosscheck", {}, api);
    if (!result) return;
    shownResults.crosscheck = () => crosscheckTable($("crosscheck-table"), result, state.meta.units, state.system);
    shownResults.crosscheck();
    // The engine's shot beside the analytic one: its machine swinging on the stage, its flight a ghost.
    state.ghosts = state.ghosts.filter((g) => !g.engine);
    state.twin = result.engine;
    if (result.engine?.history.flight_path.length) state.ghosts.push({path: result.engine.history.flight_path, engine: true});
    api.draw();
  });
}

// The sweep's range (left axis) and load (right axis) against the field, each axis in the shown units
// (the projectile's acceleration in g); hover previews that machine's trajectory on the stage, click
// adopts the value.
function plotSweep(state, api, result, kind) {
  const canvas = $("whatif-plot");
  canvas.hidden = false;
  const ctx = canvas.getContext("2d");
  const W = canvas.width, H = canvas.height, margin = plotMargins(canvas, true);
  const box = {left: margin.left, right: W - margin.right, top: margin.top, bottom: H - margin.bottom};
  const xs = result.values;
  const units = state.meta.units, system = state.system;
  // Each series in the shown units: the range's, the load's (the server's kind and values: g for an
  // acceleration) and the field's.
  const inUnits = (a, k) => a.map((v) => (v === null ? null : shownValue(units, k, system, v)));
  const ranges = inUnits(result.ranges, "length");
  const loads = inUnits(result.loads_shown, result.load_kind);
  const loadUnit = unitLabel(units, result.load_kind, system);
  const [x0, x1] = [xs[0], xs[xs.length - 1]].map((v) => shownValue(units, kind, system, v));
  const finite = (a) => a.filter((v) => v !== null);
  const scale = (a) => { const f = finite(a); return [Math.min(...f, 0), Math.max(...f, 1e-9)]; };
  const [r0, r1] = scale(ranges), [l0, l1] = scale(loads);
  const X = (i) => box.left + (box.right - box.left) * i / (xs.length - 1);
  const Xv = (v) => box.left + (box.right - box.left) * (v - x0) / (x1 - x0);
  const Yof = (lo, hi) => (v) => box.bottom - (box.bottom - box.top) * (v - lo) / (hi - lo);
  const curve = (a, lo, hi, color) => {
    ctx.strokeStyle = color; ctx.lineWidth = 2; ctx.beginPath();
    let drawing = false;
    a.forEach((v, i) => {
      if (v === null) { drawing = false; return; }
      const y = Yof(lo, hi)(v);
      if (drawing) ctx.lineTo(X(i), y); else ctx.moveTo(X(i), y);
      drawing = true;
    });
    ctx.stroke();
  };
  const loadName = result.load_label;
  const redraw = (hover) => {
    ctx.clearRect(0, 0, W, H);
    drawAxis(ctx, canvas, box, "bottom", {lo: x0, hi: x1, at: Xv,
      title: `${result.field} (${unitLabel(units, kind, system)})`});
    drawAxis(ctx, canvas, box, "left", {lo: r0, hi: r1, at: Yof(r0, r1), title: `range (${unitLabel(units, "length", system)})`,
      color: "#c0392b"});
    drawAxis(ctx, canvas, box, "right", {lo: l0, hi: l1, at: Yof(l0, l1), title: `${loadName} (${loadUnit})`,
      color: "#1f618d"});
    curve(ranges, r0, r1, "#c0392b");
    curve(loads, l0, l1, "#1f618d");
    if (hover !== null) {
      ctx.strokeStyle = "#7d3c98"; ctx.beginPath(); ctx.moveTo(X(hover), box.top); ctx.lineTo(X(hover), box.bottom); ctx.stroke();
    }
  };
  const m = box.left, span = box.right - box.left;
  redraw(null);
  const index = (event) => {
    const x = event.offsetX * canvas.width / canvas.clientWidth;
    return Math.max(0, Math.min(xs.length - 1, Math.round((x - m) / span * (xs.length - 1))));
  };
  let previewed = -1;
  const preview = async (i) => {
    redraw(i);
    if (i === previewed) return;
    previewed = i;
    const design = structuredClone(state.design);
    setValue(design, result.field, xs[i]);
    const response = await fetch("/api/shot", {method: "POST", headers: {"content-type": "application/json"},
      body: JSON.stringify({design, ...state.meta.sampling})});
    if (previewed !== i) return;
    const shot = await response.json();
    state.preview = response.ok && shot.history ? shot.history.flight_path : null;
    api.draw();
  };
  // A mouse previews by hovering and adopts by clicking. A finger cannot hover: its first tap on a
  // value previews it, a second tap on the same value adopts it (a tap elsewhere previews that).
  let touch = false;
  canvas.onpointerdown = (event) => { touch = event.pointerType !== "mouse"; };
  canvas.onpointermove = (event) => { if (event.pointerType === "mouse") preview(index(event)); };
  canvas.onpointerleave = (event) => {
    if (event.pointerType !== "mouse") return;
    previewed = -1; state.preview = null; redraw(null); api.draw();
  };
  canvas.onclick = (event) => {
    const i = index(event);
    if (touch && i !== previewed) { preview(i); return; }
    previewed = -1; state.preview = null;
    adoptValue(state, api, result.field, xs[i]);
  };
  $("whatif-hint").hidden = false;
}
