// The stage: the machine and its shot drawn to scale on a canvas from the shot's history (m, s).

const COLORS = {arm: "#6b4226", frame: "#8a8a8a", weight: "#333", sling: "#b08d57", pouch: "#4a2c17",
  ball: "#c0392b", path: "#c0392b", ghost: "#5d6d7e", engine: "#117a65", dimension: "#1f618d", ground: "#c9b98f",
  target: "#7d6608", ahead: "#d9a39c"};
// The sling's line, px: a massless sling's, and a sling's as heavy as the projectile or heavier.
const SLING_WIDTH = [1.5, 6];
// The pouch's ring round the projectile, px: the width of a light pouch's, and of one as heavy as the projectile.
const POUCH_WIDTH = [1.5, 4.5];

// The target's level, m from the pivot: ``environment.target_height`` above the base (below it: a pit).
function targetLevel(design) {
  return (design.environment?.target_height ?? 0) - design.machine.pivot_height;
}

// Index of the last sample at or before ``t`` in the sorted ``times``.
function before(times, t) {
  let low = 0, high = times.length - 1;
  if (t <= times[0]) return 0;
  if (t >= times[high]) return high;
  while (high - low > 1) {
    const mid = (low + high) >> 1;
    if (times[mid] <= t) low = mid; else high = mid;
  }
  return low;
}

function lerp(a, b, f) { return [a[0] + (b[0] - a[0]) * f, a[1] + (b[1] - a[1]) * f]; }

function at(times, points, t) {
  const i = before(times, t);
  const j = Math.min(i + 1, times.length - 1);
  const f = j === i ? 0 : Math.max(0, Math.min(1, (t - times[i]) / (times[j] - times[i])));
  return lerp(points[i], points[j], f);
}

// The shot's duration on the stage: to landing, or to the end of its history.
export function duration(shot) {
  const h = shot.history;
  if (!h) return 0;
  if (h.flight_t.length) return h.flight_t[h.flight_t.length - 1];
  return h.t[h.t.length - 1];
}

// Where everything is at time ``t``: parts relative to the ground mark (frame_x added).
export function pose(shot, t) {
  const h = shot.history;
  const i = before(h.t, Math.min(t, h.t[h.t.length - 1]));
  const x = h.frame_x[i];
  const shift = (p) => [p[0] + x, p[1]];
  const parts = {};
  for (const [name, points] of Object.entries(h.parts)) parts[name] = shift(at(h.t, points, Math.min(t, h.t[h.t.length - 1])));
  parts.pivot = [x, 0];
  const flying = h.flight_t.length && t > h.t[h.t.length - 1];
  if (flying) parts.ball = at(h.flight_t, h.flight_path, t);
  else parts.ball = parts.projectile;
  parts.flying = flying;
  return parts;
}

// The world window (m) that frames the machine, the trajectory and the ghosts.
function fieldWindow(shot, design, ghosts) {
  const m = design.machine;
  const reach = m.arm_long + m.sling_length;
  let xmin = -reach, xmax = reach, ymax = Math.max(m.arm_long + m.sling_length, targetLevel(design));
  const ymin = Math.min(-m.pivot_height, targetLevel(design));
  for (const path of [shot.history?.flight_path ?? [], ...ghosts.map((g) => g.path)]) {
    for (const [x, y] of path) { xmin = Math.min(xmin, x); xmax = Math.max(xmax, x); ymax = Math.max(ymax, y); }
  }
  return {xmin, xmax, ymin, ymax};
}

// The world window (m) that frames the machine through its whole swing: every drawn part at every
// sample, the frame down to the base, and a tenth of the arm's length round it. One window for the
// whole swing, so that the machine moves in it and the camera stands still.
function machineWindow(shot, design) {
  const m = design.machine, h = shot.history;
  const around = 0.1 * (m.arm_long + m.arm_short);
  let xmin = -m.arm_short, xmax = m.arm_short, ymin = Math.min(-m.pivot_height, targetLevel(design)), ymax = 0;
  h.t.forEach((_, i) => {
    for (const points of Object.values(h.parts)) {
      const x = points[i][0] + h.frame_x[i], y = points[i][1];
      xmin = Math.min(xmin, x); xmax = Math.max(xmax, x); ymin = Math.min(ymin, y); ymax = Math.max(ymax, y);
    }
  });
  const foot = 0.6 * m.pivot_height;   // the frame's legs (drawMachine), or a floating arm's track
  return {xmin: Math.min(xmin, -foot) - around, xmax: Math.max(xmax, foot) + around, ymin: ymin - around,
    ymax: ymax + around};
}

// Of the flight, the part over which the default camera draws back from the machine to the field.
const PULL_BACK = 0.2;

// From window ``a`` to window ``b`` as ``f`` goes from 0 to 1: each side's size geometrically (a
// steady zoom) about the point that stays put, so that the machine shrinks into the field.
function zoom(a, b, f) {
  const axis = (a0, a1, b0, b1) => {
    const wa = a1 - a0, wb = b1 - b0, w = wa * (wb / wa) ** f;
    const ca = (a0 + a1) / 2, cb = (b0 + b1) / 2;
    const c = Math.abs(wb - wa) < 1e-12 * wa ? ca + (cb - ca) * f : ca + (cb - ca) * (w - wa) / (wb - wa);
    return [c - w / 2, c + w / 2];
  };
  const [xmin, xmax] = axis(a.xmin, a.xmax, b.xmin, b.xmax), [ymin, ymax] = axis(a.ymin, a.ymax, b.ymin, b.ymax);
  return {xmin, xmax, ymin, ymax};
}

// The default camera's window at ``t``: the machine through the swing; after release it draws back
// to the whole field over the first ``PULL_BACK`` of the flight, the ball kept in view.
function autoWindow(shot, design, ghosts, parts, t) {
  const machine = machineWindow(shot, design), field = fieldWindow(shot, design, ghosts);
  const h = shot.history, released = h.t[h.t.length - 1];
  const flight = h.flight_t.length ? h.flight_t[h.flight_t.length - 1] - released : 0;
  if (!parts.flying || !(flight > 0)) return machine;
  const f = Math.min(1, (t - released) / (PULL_BACK * flight));
  const w = zoom(machine, field, f * f * (3 - 2 * f));   // eased at both ends
  const [bx, by] = parts.ball, pad = 0.05 * (w.xmax - w.xmin);
  return {xmin: Math.min(w.xmin, bx - pad), xmax: Math.max(w.xmax, bx + pad), ymin: Math.min(w.ymin, by - pad),
    ymax: Math.max(w.ymax, by + pad)};
}

function followWindow(parts, design) {
  const m = design.machine;
  const size = 0.8 * (m.arm_long + m.sling_length);
  const cx = parts.flying ? parts.ball[0] : parts.pivot[0];
  const cy = parts.flying ? parts.ball[1] : 0;
  return {xmin: cx - size, xmax: cx + size, ymin: Math.min(-m.pivot_height, targetLevel(design), cy - size),
    ymax: cy + size};
}

// One scale for x and y (to scale), the window centred in ``box`` ({x, y, width, height}, canvas
// pixels) with a margin.
function transform(box, w, margin = 28) {
  const sx = (box.width - 2 * margin) / (w.xmax - w.xmin);
  const sy = (box.height - 2 * margin) / (w.ymax - w.ymin);
  const s = Math.min(sx, sy);
  const ox = box.x + margin + ((box.width - 2 * margin) - s * (w.xmax - w.xmin)) / 2 - s * w.xmin;
  const oy = box.y + box.height - margin - ((box.height - 2 * margin) - s * (w.ymax - w.ymin)) / 2 + s * w.ymin;
  return {s, ox, oy, box, X: (x) => ox + s * x, Y: (y) => oy - s * y};
}

function line(ctx, T, a, b, color, width) {
  ctx.strokeStyle = color; ctx.lineWidth = width;
  ctx.beginPath(); ctx.moveTo(T.X(a[0]), T.Y(a[1])); ctx.lineTo(T.X(b[0]), T.Y(b[1])); ctx.stroke();
}

function disc(ctx, T, p, radius, color, minimum = 3) {
  ctx.fillStyle = color;
  ctx.beginPath(); ctx.arc(T.X(p[0]), T.Y(p[1]), Math.max(minimum, radius * T.s), 0, 2 * Math.PI); ctx.fill();
}

function polyline(ctx, T, points, color, width, dash = []) {
  if (!points.length) return;
  ctx.strokeStyle = color; ctx.lineWidth = width; ctx.setLineDash(dash);
  ctx.beginPath();
  points.forEach(([x, y], i) => (i ? ctx.lineTo(T.X(x), T.Y(y)) : ctx.moveTo(T.X(x), T.Y(y))));
  ctx.stroke(); ctx.setLineDash([]);
}

// A floating arm's frame stays put: the axle runs on a horizontal track at its starting height,
// the counterweight on a vertical guide through the origin (x = 0).
function drawFloatingFrame(ctx, T, m) {
  const base = -m.pivot_height, reach = m.arm_short + 0.15 * m.arm_long;
  line(ctx, T, [-reach * 1.2, base], [reach * 0.6, base], COLORS.frame, 4);
  for (const x of [-reach, reach * 0.4]) line(ctx, T, [x, base], [x, 0], COLORS.frame, 3);
  line(ctx, T, [-reach * 1.1, 0], [reach * 0.5, 0], COLORS.frame, 5);          // the track
  line(ctx, T, [0, base], [0, m.arm_short * 1.1], COLORS.frame, 2);             // the guide
}

// A raised trough, part of the frame (it rolls with a rolling one, at the pivot's x ``px``): its top
// ``trough`` above the base, from under the long arm's tip at rest to half a sling past where the
// projectile lies, on legs to the base (a picture: the model's trough has no length).
function drawTrough(ctx, T, m, trough, px) {
  const base = -m.pivot_height, top = base + trough;
  const start = (m.kind === "floating-arm" ? 0 : px) - Math.sqrt(Math.max(0, m.arm_long ** 2 - top ** 2));
  const end = start + 1.5 * m.sling_length;
  line(ctx, T, [start, top], [end, top], COLORS.frame, 3);
  for (const x of [start, end]) line(ctx, T, [x, base], [x, top], COLORS.frame, 2);
}

// How heavy a part of the sling looks, 0 to 1: the square root of its mass over the projectile's (a
// light cord already shows), 1 from the projectile's mass up.
function heft(mass, design) {
  return Math.min(1, Math.sqrt(Math.max(0, mass ?? 0) / design.projectile.mass));
}

function between([low, high], fraction) { return low + (high - low) * fraction; }

// The sling from the arm's tip to ``end``, drawn thicker as its mass grows, and the pouch, if it has
// mass: a leather ring round the projectile's place (the ball drawn over it fills it while it holds it).
function drawSling(ctx, T, tip, end, design) {
  const m = design.machine;
  line(ctx, T, tip, end, COLORS.sling, between(SLING_WIDTH, heft(m.sling_mass, design)));
  if (!(m.pouch_mass > 0)) return;
  const width = between(POUCH_WIDTH, heft(m.pouch_mass, design));
  ctx.strokeStyle = COLORS.pouch; ctx.lineWidth = width;
  ctx.beginPath();
  ctx.arc(T.X(end[0]), T.Y(end[1]), Math.max(3, design.projectile.diameter / 2 * T.s) + width / 2, 0, 2 * Math.PI);
  ctx.stroke();
}

function drawMachine(ctx, T, parts, design) {
  const m = design.machine;
  const base = -m.pivot_height;
  const foot = 0.45 * m.pivot_height;
  const [px] = parts.pivot;
  if (m.kind === "floating-arm") {
    drawFloatingFrame(ctx, T, m);
  } else {
    line(ctx, T, [px - foot, base], [px, 0], COLORS.frame, 3);
    line(ctx, T, [px + foot, base], [px, 0], COLORS.frame, 3);
    line(ctx, T, [px - foot * 1.2, base], [px + foot * 1.2, base], COLORS.frame, 4);
  }
  if (design.base && design.base.mobility === "rolling") {
    for (const wx of [px - foot, px + foot]) {
      ctx.strokeStyle = "#222"; ctx.lineWidth = 2; ctx.beginPath();
      ctx.arc(T.X(wx), T.Y(base + 0.08 * m.pivot_height), 0.08 * m.pivot_height * T.s, 0, 2 * Math.PI); ctx.stroke();
    }
  }
  if (design.base && design.base.trough_height > 0) drawTrough(ctx, T, m, design.base.trough_height, px);
  const tip = parts.long_tip, short = parts.short_tip;
  line(ctx, T, [short[0], short[1]], [tip[0], tip[1]], COLORS.arm, Math.max(3, 0.04 * m.arm_long * T.s));
  line(ctx, T, short, parts.counterweight, "#555", 2);
  // A hanging counterweight's box spans most of its link; a bolted one's, most of the short arm.
  const weightSize = 0.35 * (m.counterweight_link || m.arm_short);
  ctx.fillStyle = COLORS.weight;
  const [cx, cy] = parts.counterweight;
  ctx.fillRect(T.X(cx) - weightSize * T.s, T.Y(cy) - weightSize * T.s, 2 * weightSize * T.s, 2 * weightSize * T.s);
  // After release the machine stands where it let go (the history ends there); a sling or a pouch with
  // mass stays on it (docs/derivation.md, 14.8), its end where the projectile left it.
  const weighs = m.sling_mass > 0 || m.pouch_mass > 0;
  if (!parts.flying || weighs) drawSling(ctx, T, tip, parts.projectile, design);
  disc(ctx, T, parts.pivot, 0.02 * m.arm_long, "#000");
}

// A raised target or a pit: a dashed line across the view at its level, named (``named``).
function drawTarget(ctx, T, design, named) {
  if (!design.environment?.target_height) return;
  const y = T.Y(targetLevel(design)), {x, width} = T.box;
  ctx.strokeStyle = COLORS.target; ctx.lineWidth = 1.5; ctx.setLineDash([8, 5]);
  ctx.beginPath(); ctx.moveTo(x, y); ctx.lineTo(x + width, y); ctx.stroke(); ctx.setLineDash([]);
  if (!named) return;
  ctx.fillStyle = COLORS.target; ctx.font = "12px sans-serif"; ctx.textAlign = "right";
  ctx.fillText(design.environment.target_height > 0 ? "target level" : "target level (pit)", x + width - 8, y - 5);
}

function drawDimension(ctx, T, shot, design, label) {
  if (shot.range === null) return;
  const y = targetLevel(design);   // the range is measured at the target's level
  const below = y - 14 / T.s;
  line(ctx, T, [0, below], [shot.range, below], COLORS.dimension, 1);
  line(ctx, T, [0, y], [0, below - 4 / T.s], COLORS.dimension, 1);
  line(ctx, T, [shot.range, y], [shot.range, below - 4 / T.s], COLORS.dimension, 1);
  ctx.fillStyle = COLORS.dimension; ctx.font = "13px sans-serif"; ctx.textAlign = "center";
  ctx.fillText(label.range, T.X(shot.range / 2), T.Y(below) - 4);
  const path = shot.history.flight_path;
  let apex = path[0];
  for (const p of path) if (p[1] > apex[1]) apex = p;
  if (apex) {
    line(ctx, T, [apex[0], apex[1]], [apex[0], y], COLORS.dimension, 0.5);
    ctx.fillText(label.apex, T.X(apex[0]), T.Y(apex[1]) - 8);
  }
}

// The engine's machine (the cross-check's pymunk twin) at the same time, in its colour over the
// analytic one: arm, counterweight link, sling and projectile, and the projectile's path so far.
function drawTwin(ctx, T, twin, design, t, labelled = true) {
  const parts = pose(twin, t);
  const h = twin.history;
  const flown = h.flight_t.length ? h.flight_path.filter((_, i) => h.flight_t[i] <= t) : [];
  polyline(ctx, T, [...h.parts.projectile.slice(0, before(h.t, t) + 1).map(([x, y], i) => [x + h.frame_x[i], y]),
    ...flown], COLORS.engine, 1.5, [2, 4]);
  line(ctx, T, parts.short_tip, parts.long_tip, COLORS.engine, 1.5);   // thinner: the analytic arm shows round it
  line(ctx, T, parts.short_tip, parts.counterweight, COLORS.engine, 1.5);
  if (!parts.flying) line(ctx, T, parts.long_tip, parts.ball, COLORS.engine, 1.5);
  disc(ctx, T, parts.ball, design.projectile.diameter / 2, COLORS.engine);
  if (!labelled) return;
  ctx.fillStyle = COLORS.engine; ctx.font = "12px sans-serif"; ctx.textAlign = "left";
  ctx.fillText("green: the engine's (pymunk) shot of this design", T.box.x + 8, T.box.y + T.box.height - 8);
}

// The canvas's pixels match its size on screen (one drawing pixel per device pixel), its height
// ASPECT of its width, so that lines and labels keep their size on a phone as on a desktop.
const ASPECT = 0.55;
function fitToScreen(canvas) {
  const ratio = window.devicePixelRatio || 1;
  const width = Math.round(canvas.clientWidth * ratio);
  if (width && canvas.width !== width) {
    canvas.width = width;
    canvas.height = Math.round(width * ASPECT);
  }
  canvas.getContext("2d").setTransform(1, 0, 0, 1, 0, 0);
}

// The inset's share of the stage's width, its least width (px), and its distance from the edges (px).
const INSET = {share: 0.3, least: 130, gap: 8};

// The camera's main view and its inset ("field" or "machine": the view it shows; null for none) at ``t``.
function views(shot, design, ghosts, parts, t, camera) {
  if (camera === "follow") return {main: followWindow(parts, design), inset: null};
  if (camera === "field") return {main: fieldWindow(shot, design, ghosts), inset: null};
  if (camera === "machine") return {main: machineWindow(shot, design), inset: "field"};
  const main = autoWindow(shot, design, ghosts, parts, t);
  return {main, inset: parts.flying ? "machine" : "field"};
}

// Everything at ``t`` seen through ``T``: ground, target, ghosts, the path so far, the machine and
// the ball, the engine's twin; the texts (``labelled``) only in the main view.
function drawScene(ctx, T, shot, design, t, {ghosts, label, preview, twin}, labelled) {
  const parts = pose(shot, t);
  const {x, y, width, height} = T.box;
  ctx.save();
  ctx.beginPath(); ctx.rect(x, y, width, height); ctx.clip();
  const ground = T.Y(-design.machine.pivot_height);
  ctx.fillStyle = COLORS.ground;
  ctx.fillRect(x, ground, width, y + height - ground);
  drawTarget(ctx, T, design, labelled);
  for (const ghost of ghosts) {
    polyline(ctx, T, ghost.path, ghost.engine ? COLORS.engine : COLORS.ghost, 1.5, ghost.engine ? [2, 4] : [6, 5]);
  }
  if (preview) polyline(ctx, T, preview, "#7d3c98", 1.5, [2, 3]);
  const h = shot.history;
  // The inset's field shows the flight to come, faint, while the machine swings.
  if (!labelled && !parts.flying) polyline(ctx, T, h.flight_path, COLORS.ahead, 1.5, [4, 3]);
  const flown = h.flight_t.length ? h.flight_path.filter((_, i) => h.flight_t[i] <= t) : [];
  polyline(ctx, T, [...h.parts.projectile.slice(0, before(h.t, t) + 1).map(([px, py], i) => [px + h.frame_x[i], py]),
    ...flown], COLORS.path, 2);
  drawMachine(ctx, T, parts, design);
  disc(ctx, T, parts.ball, design.projectile.diameter / 2, COLORS.ball);
  if (twin) drawTwin(ctx, T, twin, design, t, labelled);
  if (labelled && t >= duration(shot)) drawDimension(ctx, T, shot, design, label);
  ctx.restore();
}

// The inset's box in a top corner of the stage: of the two, the one the swing's parts pass through
// least in the main view ``T`` (the machine's inset, over the field: the right, as the flight rises
// from the left).
function insetBox(canvas, shows, shot, T) {
  const width = Math.max(INSET.least, INSET.share * canvas.width), height = width * ASPECT;
  const boxes = [{x: INSET.gap, y: INSET.gap, width, height},
    {x: canvas.width - width - INSET.gap, y: INSET.gap, width, height}];
  if (shows !== "field") return boxes[1];
  const h = shot.history;
  const covered = (box) => h.t.reduce((n, _, i) => n + Object.values(h.parts).filter((points) => {
    const px = T.X(points[i][0] + h.frame_x[i]), py = T.Y(points[i][1]);
    return px >= box.x && px <= box.x + box.width && py >= box.y && py <= box.y + box.height;
  }).length, 0);
  return covered(boxes[1]) < covered(boxes[0]) ? boxes[1] : boxes[0];
}

function frameInset(ctx, box) {
  ctx.fillStyle = "#eaf2f8"; ctx.fillRect(box.x, box.y, box.width, box.height);
  ctx.strokeStyle = "#5d6d7e"; ctx.lineWidth = 1.5; ctx.strokeRect(box.x, box.y, box.width, box.height);
}

function nameInset(ctx, box, name) {
  ctx.fillStyle = "#2c3e50"; ctx.font = "11px sans-serif"; ctx.textAlign = "left";
  ctx.fillText(name === "field" ? "whole field" : "machine", box.x + 5, box.y + 13);
}

// Draws ``shot`` at time ``t``; ``ghosts`` are earlier flights ({path}); ``label`` the texts of
// the range and apex in the shown units; ``twin`` the engine's shot of the same design ({history}).
// ``camera``: "auto" (the machine through the swing, then drawing back to the whole field, the other
// in an inset), "machine" (with the field in an inset), "field" or "follow".
// The canvas's ``data-view`` holds the main view's scale (px per m) and origin, ``{scale, x0, y0}``
// (a point (x, y) m is drawn at (x0 + scale x, y0 - scale y) canvas pixels), and ``data-inset`` the
// inset's box and what it shows (empty: none): what a test measures the drawing by.
export function drawStage(canvas, shot, design, t, {ghosts = [], camera = "auto", label, preview = null,
  twin = null}) {
  fitToScreen(canvas);
  const ctx = canvas.getContext("2d");
  ctx.clearRect(0, 0, canvas.width, canvas.height);
  if (!shot || !shot.history) return;
  const parts = pose(shot, t);
  const options = {ghosts, label, preview, twin};
  const view = views(shot, design, ghosts, parts, t, camera);
  const T = transform({x: 0, y: 0, width: canvas.width, height: canvas.height}, view.main);
  drawScene(ctx, T, shot, design, t, options, true);
  canvas.dataset.view = JSON.stringify({scale: T.s, x0: T.ox, y0: T.oy});
  canvas.dataset.inset = "";
  if (!view.inset) return;
  const box = insetBox(canvas, view.inset, shot, T);
  const seen = view.inset === "field" ? fieldWindow(shot, design, ghosts) : machineWindow(shot, design);
  frameInset(ctx, box);
  drawScene(ctx, transform(box, seen, 10), shot, design, t, {...options, preview: null}, false);
  nameInset(ctx, box, view.inset);
  canvas.dataset.inset = JSON.stringify({...box, shows: view.inset});
}
