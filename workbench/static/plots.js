// The tools' plots' axes: a line, round-numbered ticks and a title with its unit on each, in type the
// same size on screen whatever the canvas's size.

// The type's size on screen, CSS px: the page's small print (style.css's .hint is 12 px).
export const TYPE_PX = 13;

// The font of ``canvas`` that shows as ``TYPE_PX`` on screen (its drawing pixels per CSS pixel).
export function readableFont(canvas, px = TYPE_PX) {
  const ratio = canvas.clientWidth ? canvas.width / canvas.clientWidth : 1;
  return `${Math.round(px * ratio)}px sans-serif`;
}

// The margins (canvas px) a plot keeps for its ticks and titles: left, right, top, bottom.
export function plotMargins(canvas, rightAxis = false) {
  const em = parseInt(readableFont(canvas), 10);
  return {left: 4.2 * em, right: rightAxis ? 4.2 * em : em, top: 1.8 * em, bottom: 3 * em};
}

// Round tick values from ``lo`` to ``hi``: about ``count`` of 1, 2 or 5 times a power of ten.
export function ticks(lo, hi, count = 4) {
  if (!(hi > lo)) return [lo];
  const raw = (hi - lo) / count, power = 10 ** Math.floor(Math.log10(raw));
  const steps = [1, 2, 5, 10].map((m) => m * power);
  const step = steps.reduce((a, b) => (Math.abs((hi - lo) / b - count) < Math.abs((hi - lo) / a - count) ? b : a));
  const out = [];
  for (let v = Math.ceil(lo / step) * step; v <= hi + step * 1e-9; v += step) out.push(Number(v.toPrecision(12)));
  return out;
}

function short(value) {
  return Math.abs(value) >= 1e7 ? value.toExponential(1) : Number(value.toPrecision(4)).toString();
}

// Draws an axis on ``side`` ("bottom", "left", "right") of ``box`` ({left, right, top, bottom}, canvas px):
// ``lo``..``hi`` (shown units) mapped by ``at`` to a canvas coordinate, ``title`` with its unit.
export function drawAxis(ctx, canvas, box, side, {lo, hi, at, title, color = "#333"}) {
  const font = readableFont(canvas), em = parseInt(font, 10);
  ctx.save();
  ctx.strokeStyle = "#999"; ctx.lineWidth = 1; ctx.fillStyle = color; ctx.font = font;
  ctx.beginPath();
  if (side === "bottom") { ctx.moveTo(box.left, box.bottom); ctx.lineTo(box.right, box.bottom); }
  else { const x = side === "left" ? box.left : box.right; ctx.moveTo(x, box.top); ctx.lineTo(x, box.bottom); }
  ctx.stroke();
  for (const value of ticks(lo, hi)) {
    const p = at(value);
    ctx.beginPath();
    if (side === "bottom") {
      ctx.moveTo(p, box.bottom); ctx.lineTo(p, box.bottom + em / 3); ctx.stroke();
      ctx.textAlign = "center"; ctx.fillText(short(value), p, box.bottom + 1.2 * em);
    } else {
      const x = side === "left" ? box.left : box.right, out = side === "left" ? -1 : 1;
      ctx.moveTo(x, p); ctx.lineTo(x + out * em / 3, p); ctx.stroke();
      ctx.textAlign = side === "left" ? "right" : "left";
      ctx.fillText(short(value), x + out * em / 2, p + em / 3);
    }
  }
  if (side === "bottom") { ctx.textAlign = "center"; ctx.fillText(title, (box.left + box.right) / 2, box.bottom + 2.5 * em); }
  else { ctx.textAlign = side === "left" ? "left" : "right"; ctx.fillText(title, side === "left" ? 2 : canvas.width - 2, 0.9 * em); }
  ctx.restore();
}
