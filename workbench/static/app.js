// The workbench page: the design form, live shots (latest wins), the stage's playback, readouts, files and links.
import {followChoices, settle, useRules} from "./applies.js";
import {buildForm, defaultOf, fileValue, fillForm, round, setValue, showError, shownValue, unitLabel} from "./form.js";
import {drawStage, duration} from "./stage.js";
import {labelLoads, setupTools, showAgain} from "./tools.js";
import {setupFiring} from "./firing.js";
import {followDesign} from "./optimise.js";
import {fieldKinds, localise} from "./units.js";

const $ = (id) => document.getElementById(id);
export const state = {meta: null, presets: [], design: null, system: "metric", shot: null, ghosts: [],
  t: 0, playing: false, speed: 0.1, camera: "auto", preview: null, twin: null};

// ---- units -------------------------------------------------------------------------------------
export function show(value, kind, digits = 2) {
  if (value === null || value === undefined) return "–";
  const shown = shownValue(state.meta.units, kind, state.system, value);
  return `${shown.toFixed(digits)} ${unitLabel(state.meta.units, kind, state.system)}`;
}

// ---- shots: one request in flight, the latest design next (never a backlog) --------------------
// The shot with its motion (the compiled path, a few ms on the server) updates the readouts and
// redraws the stage together, while a slider moves.
export const timings = [];
export const latencies = [];
let version = 0, shownVersion = 0;

// ``extra``: () => more keys of the request body.
function channel(url, onAnswer, extra = () => ({})) {
  let inFlight = false, pending = false;
  const send = () => {
    if (inFlight) { pending = true; return null; }
    inFlight = true; pending = false;
    const mine = version, started = performance.now();
    return fetch(url, {method: "POST", headers: {"content-type": "application/json"},
      body: JSON.stringify({design: state.design, ...extra()})})
      .then(async (response) => onAnswer(response, await response.json(), mine, started))
      .catch((error) => fieldError({error: `no answer from the server: ${error}`, field: ""}))
      .finally(() => { inFlight = false; if (pending) send(); });
  };
  return send;
}

const sendShot = channel("/api/shot", (response, data, mine, started) => {
  if (mine < shownVersion) return;
  if (response.ok) {
    showError($("fields"), null, "");
    $("design-error").hidden = true;
    shownVersion = mine;
    document.body.dataset.shownVersion = String(mine);   // equal to requestedVersion: the shot drawn is current
    adopt(data);
    timings.push(performance.now() - started);
  } else if (mine === version) {
    fieldError(data);
  }
}, () => state.meta.sampling);   // the history spaced for drawing (the server says why)

export function requestShot() {
  version += 1;
  document.body.dataset.requestedVersion = String(version);
  sendShot();
}

export function fieldError(data) {
  const message = said(data.error);
  const shownAtField = showError($("fields"), data.field, message);
  $("design-error").hidden = shownAtField;
  $("design-error").textContent = message;
}

// A message of the server's (SI) in the shown units.
function said(text) {
  return localise(text, state.meta.units, state.system, fieldKinds(state.meta.groups));
}

function adopt(shot) {
  state.shot = shot;
  state.t = state.playing ? 0 : duration(shot);
  readouts(shot);
  draw();
  // From the input that changed the design to this shot drawn (the latency the bench reports).
  if (state.inputAt !== undefined) latencies.push(performance.now() - state.inputAt);
  document.body.dataset.shots = String(Number(document.body.dataset.shots || 0) + 1);
}

// ---- readouts ----------------------------------------------------------------------------------
// Decimals shown by the kind of a row's unit (two for the rest): what a builder reads at a glance.
const DIGITS = {force: 1, moment: 1, energy: 1, angle: 1, time: 3, percent: 1, g: 1};

// A summary row's value in the page's units, with its note. The rows (names, values, units, order)
// are the server's, as ``python -m analytic simulate`` prints them (``analytic.summary``).
function rowText(row) {
  const digits = DIGITS[row.kind] ?? 2;
  if (!Array.isArray(row.value)) return `${show(row.value, row.kind, digits)}${row.note}`;
  const [x, y] = row.value.map((v) => shownValue(state.meta.units, row.kind, state.system, v).toFixed(digits));
  return `(${x}, ${y}) ${unitLabel(state.meta.units, row.kind, state.system)}${row.note}`;
}

// A margin's verdict (``analytic.summary.Row.verdict``): green where it holds, red where it breaks.
const VERDICT = {true: ' class="holds"', false: ' class="breaks"'};

function rowsHtml(rows) {
  const escape = (text) => text.replace(/[&<>"]/g, (c) => `&#${c.charCodeAt(0)};`);
  return rows.map((row) => `<dt class="level-${row.level}" data-key="${row.key}">${escape(row.label)}</dt>`
    + `<dd${VERDICT[row.verdict] ?? ""}>${escape(rowText(row))}</dd>`).join("");
}

function readouts(s) {
  $("range").textContent = s.range === null ? "–" : show(s.range, "length");
  $("status").textContent = s.status;
  $("status").className = s.status === "ok" ? "ok" : "failed";
  $("message").textContent = said(s.message);
  // At a glance the brief rows; every row under "all numbers" (the range and status are above).
  $("numbers").innerHTML = rowsHtml(s.summary.filter((row) => row.brief));
  $("all-numbers").innerHTML = rowsHtml(s.summary);
  $("warnings").innerHTML = "";
  for (const w of s.warnings) { const li = document.createElement("li"); li.textContent = said(w); $("warnings").append(li); }
  energyBar(s);
}

// The energy bar's colours, by part (``workbench.shot.energy_parts``' names).
const ENERGY_COLORS = {projectile: "#c0392b", drag: "#e59866", sling: "#b08d57", kept: "#6b4226",
  axle: "#7f8c8d", hinge: "#95a5a6", base: "#bdc3c7", guide: "#839192", track: "#a6acaf", swing_drag: "#f0b27a"};

// Where the energy the counterweight and arm released went: the parts the server lists (the
// projectile, the air in flight, the sling and the pouch, the arm's and counterweight's motion, and
// every loss the design has), each as its share.
function energyBar(s) {
  const e = s.history?.energy;
  const bar = $("energy");
  bar.innerHTML = "";
  if (!e || !e.released) return;
  for (const {name, label, joules} of e.parts) {
    if (!(joules > 0)) continue;
    const share = 100 * joules / e.released;
    const piece = document.createElement("span");
    piece.dataset.part = name;
    piece.style.width = `${share}%`; piece.style.background = ENERGY_COLORS[name] ?? "#aab7b8";
    piece.title = `${label}: ${show(joules, "energy", 1)} (${share.toFixed(1)} %)`;
    piece.textContent = share > 12 ? label : "";
    bar.append(piece);
  }
}

// ---- stage and playback --------------------------------------------------------------------------
export function draw() {
  if (!state.shot) return;
  const end = duration(state.shot);
  $("scrubber").value = end ? Math.round(1000 * state.t / end) : 1000;
  $("clock").textContent = `${state.t.toFixed(3)} s`;
  const label = {range: show(state.shot.range, "length"), apex: `apex ${show(state.shot.apex_height, "length")}`};
  drawStage($("stage"), state.shot, state.design, state.t,
    {ghosts: state.ghosts, camera: state.camera, label, preview: state.preview, twin: state.twin});
}

let last = null;
function frame(now) {
  if (state.playing && state.shot) {
    if (last !== null) state.t += state.speed * (now - last) / 1000;
    if (state.t >= duration(state.shot)) { state.t = duration(state.shot); setPlaying(false); }
    draw();
  }
  last = state.playing ? now : null;
  requestAnimationFrame(frame);
}

function setPlaying(playing) {
  state.playing = playing;
  $("play").textContent = playing ? "Pause" : "Play";
}

// ---- designs: presets, files, links -----------------------------------------------------------------
export function loadDesign(design, system = null) {
  state.design = structuredClone(design);
  state.twin = null;   // the engine's shot was of the design before
  if (system) setSystem(system);
  refill();
  followDesign();   // the optimiser's bounds follow the new design
  requestShot();
}

// The form shown anew: the design's values in the shown units, and only the fields that apply.
function refill() {
  fillForm($("fields"), state.design, state.meta.units, state.system);
  followChoices($("fields"), state.design, [$("aim-field"), $("whatif-field")]);
  labelLoads(state);
}

function setSystem(system) {
  // The tools' boxes (a target, a mass) keep the quantity typed, now in the new units.
  for (const input of document.querySelectorAll("input[data-kind]")) {
    if (input.value === "" || system === state.system) continue;
    const file = fileValue(state.meta.units, input.dataset.kind, state.system, Number(input.value));
    input.value = Number(shownValue(state.meta.units, input.dataset.kind, system, file).toPrecision(4));
  }
  state.system = system;
  $("units").value = system;
  localStorage.setItem("workbench.units", system);
  for (const span of document.querySelectorAll(".unit[data-kind]")) {
    span.textContent = unitLabel(state.meta.units, span.dataset.kind, system);
  }
}

function onField(name, value) {
  state.inputAt = performance.now();
  state.twin = null;
  if (name === "machine.kind") return changeKind(value);
  if (name === "machine.release_rule") return changeRule(value);
  setValue(state.design, name, value);
  // A choice may leave other fields without effect, or bring them back (applies.js).
  if (typeof value === "string" && state.meta.groups.some((g) => g.fields.some((f) => f.name === name && f.choices))) {
    settle(state.design);
    refill();
  } else {
    followChoices($("fields"), state.design, [$("aim-field"), $("whatif-field")]);
  }
  requestShot();
}

// The ideal rule ignores the release angle: its row is disabled (the value kept for another rule).
// Leaving the ideal rule for the velocity rule with no release angle set takes the last shot's
// launch angle, the pin that throws as far.
function changeRule(rule) {
  const m = state.design.machine;
  m.release_rule = rule;
  if (rule === "velocity" && m.release_angle === undefined && state.shot?.launch_angle != null) {
    m.release_angle = round(state.shot.launch_angle);
  }
  refill();
  followDesign();   // the optimiser's variables follow the rule (the ideal rule has no release angle)
  requestShot();
}

// Only a hinged machine has a link and a hinge, only a floating arm a guide and a track: another kind
// sets their values aside (the link's row hidden, the others disabled with the reason), and
// switching back restores them (the link: the last one, or a third of the short arm).
function changeKind(kind) {
  const m = state.design.machine;
  if (kind === defaultOf(state.design, "machine.kind")) delete m.kind;   // as a design file leaves it out
  else m.kind = kind;
  settle(state.design);
  refill();
  requestShot();
}

async function download() {
  const response = await fetch("/api/toml", {method: "POST", headers: {"content-type": "application/json"},
    body: JSON.stringify({design: state.design})});
  if (!response.ok) return fieldError(await response.json());
  const link = document.createElement("a");
  link.href = URL.createObjectURL(await response.blob());
  link.download = `${state.design.name || "design"}.toml`;
  link.click();
  URL.revokeObjectURL(link.href);
}

async function upload(file) {
  const response = await fetch("/api/read", {method: "POST", headers: {"content-type": "application/json"},
    body: JSON.stringify({toml: await file.text()})});
  const data = await response.json();
  if (!response.ok) return fieldError(data);
  loadDesign(data.design);
}

function shareLink() {
  const url = new URL(location.href);
  url.hash = `design=${encodeURIComponent(JSON.stringify(state.design))}`;
  $("share-link").hidden = false;
  $("share-link").value = url.href;
  $("share-link").select();
  navigator.clipboard?.writeText(url.href).catch(() => {});
}

function designFromLink() {
  const match = location.hash.match(/^#design=(.*)$/);
  if (!match) return null;
  try { return JSON.parse(decodeURIComponent(match[1])); } catch { return null; }
}

// ---- start -------------------------------------------------------------------------------------------
// The server's answer to a GET, or an error with its message.
async function fetched(url) {
  const response = await fetch(url);
  const data = await response.json().catch(() => ({}));
  if (!response.ok) throw new Error(`${url}: ${data.error ?? `HTTP ${response.status}`}`);
  return data;
}

async function start() {
  let meta, presets;
  try {
    [meta, presets] = await Promise.all([fetched("/api/meta"), fetched("/api/presets")]);
  } catch (error) {   // said on the page, never left as a script error behind a blank form
    $("design-error").hidden = false;
    $("design-error").textContent = `the page could not start (reload to try again): ${error.message}`;
    return;
  }
  state.meta = meta; state.presets = presets;
  buildForm($("fields"), meta.groups, onField);
  useRules(meta.rules);
  $("preset").innerHTML = presets.map((p) => `<option value="${p.name}">${p.title}</option>`).join("");
  $("preset").addEventListener("change", (e) => {
    const preset = presets.find((p) => p.name === e.target.value);
    loadDesign(preset.design);
  });
  $("units").addEventListener("change", (e) => {
    setSystem(e.target.value);
    refill();
    if (state.shot) { readouts(state.shot); draw(); }
    showAgain();
  });
  $("play").addEventListener("click", () => {
    if (!state.playing && state.t >= duration(state.shot)) state.t = 0;
    setPlaying(!state.playing);
  });
  $("scrubber").addEventListener("input", (e) => {
    setPlaying(false); state.t = duration(state.shot) * e.target.value / 1000; draw();
  });
  $("speed").addEventListener("change", (e) => { state.speed = Number(e.target.value); });
  $("camera").addEventListener("change", (e) => { state.camera = e.target.value; draw(); });
  $("download").addEventListener("click", download);
  $("upload").addEventListener("change", (e) => e.target.files[0] && upload(e.target.files[0]));
  $("share").addEventListener("click", shareLink);
  setSystem(localStorage.getItem("workbench.units") === "imperial" ? "imperial" : "metric");
  setupTools(state, {loadDesign, requestShot, draw, show, fieldError, round});
  setupFiring(state, {loadDesign, show});
  loadDesign(designFromLink() ?? presets[0].design);
  requestAnimationFrame(frame);
  document.body.dataset.ready = "true";
}

start();
window.workbench = {state, timings, latencies, draw};
