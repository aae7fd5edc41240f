// The cross-check's table in the user's units: each quantity's two values, their difference over its
// tolerance, the unit they are shown in and the verdict on the quantity.
import {kindOfUnit, localise} from "./units.js";

// The cross-check's verdicts (crosscheck.comparison.VERDICTS), as the table's caption says them.
const VERDICT_CAPTIONS = {
  agree: "The models agree",
  disagree: "The models differ",
  sensitive: "Too sensitive to compare: the design itself moves past a tolerance when its inputs move by parts in 1e9",
  engine_failed: "The engine could not run this design",
  engine_untrusted: "The engine could not reach the accuracy this design needs",
};
const DEGREES = 180 / Math.PI;

// A row's verdict: a quantity apart only because the design itself amplifies a change of parts in 1e9
// is "sensitive" (crosscheck.report.row_verdict), not a difference between the models.
function rowVerdict(row, sensitivity) {
  if (row.ok) return "agree";
  return (sensitivity?.[row.quantity] ?? -1) > (row.tolerance ?? 0) ? "sensitive" : "DIFFER";
}

// How a row's numbers are shown in ``system``: the factor from its SI unit and the unit's label
// (radians as degrees, as design files write angles).
function shownUnit(unit, units, system) {
  if (unit === "rad") return {factor: DEGREES, label: "deg"};
  const kind = kindOfUnit(unit);
  return kind && units[kind] ? units[kind][system] : {factor: 1, label: unit};
}

// Four significant figures; a small value with a power of ten, two figures (a phone's column holds it).
function figures(value, factor) {
  if (typeof value !== "number") return value ?? "–";
  const shown = value * factor;
  if (shown !== 0 && Math.abs(shown) < 1e-2) return shown.toExponential(1);
  return Number(shown.toPrecision(4)).toString();
}

// Fills ``table`` with ``result`` (``POST /api/jobs`` crosscheck's answer) in ``system``'s units.
export function crosscheckTable(table, result, units, system) {
  const rows = result.rows.map((r) => {
    const verdict = rowVerdict(r, result.sensitivity);
    const {factor, label} = shownUnit(r.unit, units, system);
    const difference = r.difference === null ? "–"
      : `${figures(r.difference, factor)}<br><span class="tolerance">± ${figures(r.tolerance, factor)}</span>`;
    const cells = [r.quantity.replaceAll("_", " "), label, figures(r.analytic, factor), figures(r.engine, factor),
      difference, verdict];
    const kind = r.ok ? "ok" : verdict === "sensitive" ? "sensitive" : "failed";
    return `<tr class="${kind}">${cells.map((c, i) => `<td${i > 1 && i < 5 ? " class=\"number\"" : ""}>${c}</td>`).join("")}</tr>`;
  }).join("");
  const error = result.error ? `: ${localise(result.error, units, system)}` : "";
  table.innerHTML = `<caption data-verdict="${result.verdict}">${VERDICT_CAPTIONS[result.verdict]}${error}</caption>`
    + "<tr><th>quantity</th><th>unit</th><th>analytic</th><th>engine</th><th>difference ± tolerance</th>"
    + `<th>verdict</th></tr>${rows}`;
  table.hidden = false;
}
