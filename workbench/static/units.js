// The page's texts in the user's units: the server's messages (SI, as the library writes them) with each
// number of a unit the shown system changes converted, and a value in SI units shown in a kind's unit.

// The SI units the library's messages write (analytic.units.SYSTEMS, the design contract's reasons),
// each with its kind in the page's unit table (``GET /api/meta``), longest first so that "N m" is not
// read as "N". Degrees, seconds and pure numbers are the same in every system.
const SI_UNITS = [["kg m^2", "moment of inertia"], ["kg/m^3", "density"], ["m/s^2", "acceleration"],
  ["m/s", "speed"], ["N m", "moment"], ["Pa s", "viscosity"], ["kg", "mass"], ["N", "force"], ["J", "energy"],
  ["m", "length"]];
const SI_KINDS = Object.fromEntries(SI_UNITS);
const escape = (text) => text.replace(/[.*+?^${}()|[\]\\/]/g, "\\$&");
const ALTERNATIVES = SI_UNITS.map(([unit]) => escape(unit)).join("|");
const NUMBER = String.raw`-?\d+(?:\.\d+)?(?:e[+-]?\d+)?`;
// A number and its SI unit, the unit ending the word (not the "m" of "mm" or of "more").
const QUANTITY = new RegExp(String.raw`(${NUMBER}) ?(${ALTERNATIVES})(?![\w^/²³])`, "g");
// A unit named alone in brackets: "(m)".
const BRACKETED = new RegExp(String.raw`\((${ALTERNATIVES})\)`, "g");
// The design contract's "table.field = value: reason" (a value typed in the form reaches the server in
// file units).
const FIELD_VALUE = new RegExp(String.raw`^([a-z_]+\.[a-z_]+) = (${NUMBER}):`);

// Whether ``system`` shows ``kind`` in another unit than the files' (SI).
function converts(units, kind, system) {
  return Boolean(units[kind]) && units[kind][system].factor !== 1;
}

// As many significant figures as ``text`` had (3 to 6): a converted number reads as precisely as the first.
function figures(text) {
  const digits = text.replace(/e.*$/i, "").replace(/[-.]/g, "").replace(/^0+/, "").length;
  return Math.min(6, Math.max(3, digits));
}

export function converted(units, kind, system, value, precision = 4) {
  return Number((value * units[kind][system].factor).toPrecision(precision)).toString();
}

// ``text`` (a message of the server's, SI) in ``system``'s units; ``kinds`` maps a design field's name
// to its kind, for the value a "field = value:" message echoes. Metric texts come back as they were.
export function localise(text, units, system, kinds = {}) {
  if (typeof text !== "string" || system === "metric") return text;
  let out = text.replace(FIELD_VALUE, (whole, field, value) => {
    const kind = kinds[field];
    if (!kind || !converts(units, kind, system)) return whole;
    return `${field} = ${converted(units, kind, system, Number(value), figures(value))} ${units[kind][system].label}:`;
  });
  out = out.replace(QUANTITY, (whole, value, unit) => {
    const kind = SI_KINDS[unit];
    if (!converts(units, kind, system)) return whole;
    return `${converted(units, kind, system, Number(value), figures(value))} ${units[kind][system].label}`;
  });
  return out.replace(BRACKETED, (whole, unit) => {
    const kind = SI_KINDS[unit];
    return converts(units, kind, system) ? `(${units[kind][system].label})` : whole;
  });
}

// The kind of each numeric design field, by its name (``GET /api/meta``'s groups).
export function fieldKinds(groups) {
  return Object.fromEntries(groups.flatMap((g) => g.fields).filter((f) => f.kind).map((f) => [f.name, f.kind]));
}

// The kind of a quantity in the SI unit ``unit`` (the cross-check's rows), or null for one that every
// system shows alike (s, rad, a count).
export function kindOfUnit(unit) {
  return SI_KINDS[unit] ?? null;
}
