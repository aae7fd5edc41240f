// The tools panel: best pin, aim, what-if, ghosts and the cross-check, run as server jobs with progress and cancel.
import {fileValue, getValue, setValue, shownValue, unitLabel} from "./form.js";
import {followDesign, setupOptimise} from "./optimise.js";

const $ = (id) => document.getElementById(id);
const CLIENT = Math.random().toString(36).slice(2);
const POLL_MS = 100;
let current = null;
// The cross-check's verdicts (crosscheck.comparison.VERDICTS), as the table's caption says them.
const VERDICT_CAPTIONS = {
  agree: "The models agree",
  disagree: "The models differ",
  sensitive: "Too sensitive to compare: the design itself moves past a tolerance when its inputs move by parts in 1e9",
  engine_failed: "The engine could not run this design",
  engine_untrusted: "The engine could not reach the accuracy this design needs",
};

export async function runJob(state, tool, inputs, api) {
  if (current) return null;
  $("tool-error").hidden = true;
  const response = await fetch("/api/jobs", {method: "POST", headers: {"content-type": "application/json"},
    body: JSON.stringify({tool, inputs, design: state.design, client: CLIENT})});
  let job = await response.json();
  if (!response.ok) { toolError(job); return null; }
  current = job.id;
  $("progress-row").hidden = false;
  while (job.state === "running") {
    $("progress").value = job.progress;
    await new Promise((resolve) => setTimeout(resolve, POLL_MS));
    job = await (await fetch(`/api/jobs/${job.id}`)).json();
  }
  current = null;
  $("progress-row").hidden = true;
  if (job.state !== "done") { toolError(job.error); return null; }
  return job.result;
}

function toolError(error) {
  $("tool-error").hidden = false;
  $("tool-error").textContent = error.error;
}

function adoptValue(state, api, name, value) {
  setValue(state.design, name, value);
  api.loadDesign(state.design);
}

function numericFields(state) {
  return state.meta.groups.flatMap((g) => g.fields).filter((f) => f.kind);
}

export function setupTools(state, api) {
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
    const now = getValue(state.design, name);
    const best = result.solutions.reduce((a, b) => (Math.abs(b.value - now) < Math.abs(a.value - now) ? b : a));
    const kind = fields.find((f) => f.name === name).kind;
    const shownValue_ = shownValue(state.meta.units, kind, state.system, best.value);
    $("aim-result").textContent = `${name} = ${shownValue_.toPrecision(5)} ${unitLabel(state.meta.units, kind, state.system)}`
      + ` lands at ${api.show(best.range, "length")}`;
    adoptValue(state, api, name, best.value);
  });

  $("whatif").addEventListener("click", async () => {
    const name = $("whatif-field").value;
    const value = getValue(state.design, name);
    if (typeof value !== "number") return toolError({error: `${name} is not set in this design`});
    const row = document.querySelector(`.field[data-field="${name}"]`);
    const kind = row.dataset.kind;
    const [low, high] = row.span.map((v) => fileValue(state.meta.units, kind, state.system, v));
    const result = await runJob(state, "what_if", {field: name, low, high, steps: 41, load: $("whatif-load").value}, api);
    if (result) plotSweep(state, api, result, kind);
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
    // A quantity apart only because the design itself amplifies a change of parts in 1e9 is
    // "sensitive" (crosscheck.report.row_verdict), not a difference between the models.
    const rowVerdict = (r) => r.ok ? "agree"
      : (result.sensitivity?.[r.quantity] ?? -1) > (r.tolerance ?? 0) ? "sensitive" : "DIFFER";
    const rows = result.rows.map((r) => `<tr class="${r.ok ? "ok" : rowVerdict(r) === "sensitive" ? "sensitive" : "failed"}">`
      + `<td>${r.quantity}</td>`
      + `<td>${fmt(r.analytic)}</td><td>${fmt(r.engine)}</td><td>${fmt(r.difference)}</td>`
      + `<td>${fmt(r.tolerance)}</td><td>${r.unit}</td><td>${rowVerdict(r)}</td></tr>`).join("");
    $("crosscheck-table").innerHTML = `<caption data-verdict="${result.verdict}">${VERDICT_CAPTIONS[result.verdict]}`
      + `${result.error ? `: ${result.error}` : ""}</caption><tr><th>quantity</th><th>analytic</th><th>engine</th>`
      + `<th>difference</th><th>tolerance</th><th>unit</th><th></th></tr>${rows}`;
    $("crosscheck-table").hidden = false;
    // The engine's shot beside the analytic one: its machine swinging on the stage, its flight a ghost.
    state.ghosts = state.ghosts.filter((g) => !g.engine);
    state.twin = result.engine;
    if (result.engine?.history.flight_path.length) state.ghosts.push({path: result.engine.history.flight_path, engine: true});
    api.draw();
  });
}

// The tools' field choices under the design's rule: the ideal rule ignores the release angle, so it
// is not offered (an aim or sweep over it would change nothing); a choice of it moves to the
// counterweight's mass.
export function followRule(design) {
  followDesign();
  const ideal = design.machine.release_rule === "ideal";
  for (const select of [$("aim-field"), $("whatif-field")]) {
    const option = select.querySelector('option[value="machine.release_angle"]');
    if (!option) continue;
    option.disabled = ideal;
    option.title = ideal ? "the ideal rule finds the release itself" : "";
    if (ideal && select.value === option.value) select.value = "machine.counterweight_mass";
  }
}

function fmt(value) {
  if (typeof value !== "number") return value ?? "–";
  return Number(value.toPrecision(5)).toString();
}

// The sweep's range (left axis) and load (right axis) against the field; hover previews that
// machine's trajectory on the stage, click adopts the value.
function plotSweep(state, api, result, kind) {
  const canvas = $("whatif-plot");
  canvas.hidden = false;
  const ctx = canvas.getContext("2d");
  const m = 30, W = canvas.width, H = canvas.height;
  const xs = result.values;
  const finite = (a) => a.filter((v) => v !== null);
  const scale = (a) => { const f = finite(a); return [Math.min(...f, 0), Math.max(...f, 1e-9)]; };
  const [r0, r1] = scale(result.ranges), [l0, l1] = scale(result.loads);
  const X = (i) => m + (W - 2 * m) * i / (xs.length - 1);
  const curve = (a, lo, hi, color) => {
    ctx.strokeStyle = color; ctx.lineWidth = 2; ctx.beginPath();
    let drawing = false;
    a.forEach((v, i) => {
      if (v === null) { drawing = false; return; }
      const y = H - m - (H - 2 * m) * (v - lo) / (hi - lo);
      if (drawing) ctx.lineTo(X(i), y); else ctx.moveTo(X(i), y);
      drawing = true;
    });
    ctx.stroke();
  };
  const redraw = (hover) => {
    ctx.clearRect(0, 0, W, H);
    ctx.fillStyle = "#333"; ctx.font = "11px sans-serif";
    const units = state.meta.units;
    ctx.fillText(`range to ${api.show(r1, "length", 1)}`, m, 12);
    // the load's top, in its kind's unit (the server gives the projectile's acceleration in g)
    const top = Math.max(...finite(result.loads_shown), 0);
    ctx.fillText(`${result.load_label} to ${api.show(top, result.load_kind, result.load_kind === "g" ? 1 : 0)}`, W / 2, 12);
    const shown = (v) => shownValue(units, kind, state.system, v).toPrecision(4);
    ctx.fillText(`${result.field}: ${shown(xs[0])} .. ${shown(xs[xs.length - 1])} ${unitLabel(units, kind, state.system)}`, m, H - 8);
    curve(result.ranges, r0, r1, "#c0392b");
    curve(result.loads, l0, l1, "#1f618d");
    if (hover !== null) { ctx.strokeStyle = "#7d3c98"; ctx.beginPath(); ctx.moveTo(X(hover), m); ctx.lineTo(X(hover), H - m); ctx.stroke(); }
  };
  redraw(null);
  const index = (event) => {
    const x = event.offsetX * canvas.width / canvas.clientWidth;
    return Math.max(0, Math.min(xs.length - 1, Math.round((x - m) / (W - 2 * m) * (xs.length - 1))));
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
