"""A calibration's report: its JSON, its text, its plot, the fitted designs.

JSON (``calibrate --json``, and ``calibration.json`` beside the report)::

    {"parameters": {NAME: {"value", "uncertainty", "unit", "start", "lower", "upper", "at_bound"}},
     "shots": [{"design", "measured", "predicted", "residual", "uncertainty",
                "weighted_residual", "status", "quantities": {QUANTITY: {"measured",
                "uncertainty", "predicted", "residual", "weighted_residual", "unit"}}}],
     "chi_square", "degrees_of_freedom", "reduced_chi_square", "p_value",
     "correlation", "uncertainty_definition", "converged", "message", "warnings",
     "evaluations", "shots_simulated", "shots_failed", "seconds",
     "predictions": [{"field", "value", "range", "range_sd"}]}

A shot's ``measured``, ``predicted`` and ``residual`` (predicted - measured,
m) are its range's (``null`` for a shot that measures a track instead); every
measured quantity, range included, is in its ``quantities`` with its own. A
shot with a track has its ``"track"`` (``analytic.calibrate.track_report``). Values are
in file units (m, s, deg); a quantity a shot did not reach is ``null``, as is
the uncertainty of a parameter the data cannot fix. ``predictions`` (``--predict``,
``analytic.calibrate.predict``) are SI: the setting in the field's SI unit (radians
for an angle), the range and its one standard deviation in m, ``null`` where the
design does not throw.

The plot, where the shots differ in one design field (their settings) or
predictions are asked for, shows the range against that field: the measured
ranges with their error bars, the fitted curve with its one-sd band, and the
predictions; otherwise measured against predicted. A panel for each other
quantity measured, and the weighted residuals, follow.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from analytic.calibrate.fit import Calibration, Prediction
from analytic.calibrate.spec import QUANTITIES
from analytic.calibrate.track_report import TRACK_PLOT_FILE, track_bars, track_json, track_lines, tracks_figure
from analytic.fields import axis_label, field

#: What the uncertainties are, in the JSON and the report.
UNCERTAINTY_DEFINITION = ("one standard deviation, sqrt of the diagonal of (J^T J)^-1 with J the Jacobian of the "
                          "residuals weighted by the stated uncertainties, not scaled by the reduced chi-square")
#: The files ``write`` puts in the output folder (the fitted designs go in ``FITTED_FOLDER``).
REPORT_FILE, JSON_FILE, PLOT_FILE, FITTED_FOLDER = "report.txt", "calibration.json", "calibration.png", "fitted"


def _number(value) -> float | None:
    return None if value is None or not math.isfinite(value) else float(value)


def _quantity(measurement, prediction: Prediction) -> dict:
    predicted = prediction.values[measurement.quantity] if prediction.ok else None
    residual = None if predicted is None else predicted - measurement.value
    return {"measured": measurement.value, "uncertainty": measurement.uncertainty, "predicted": predicted,
            "residual": residual,
            "weighted_residual": None if residual is None else residual / measurement.uncertainty,
            "unit": measurement.unit}


def to_json(result: Calibration, predictions=()) -> dict:
    """The ``calibrate --json`` object (module docstring); ``predictions``: ``RangePrediction``s."""
    spec = result.spec
    parameters = {p.name: {"value": float(result.values[j]), "uncertainty": _number(result.uncertainties[j]),
                           "unit": p.unit, "start": p.start, "lower": p.lower, "upper": p.upper,
                           "at_bound": bool(result.at_bound[j])}
                  for j, p in enumerate(spec.parameters)}
    shots = []
    for k, (shot, prediction) in enumerate(zip(spec.shots, result.fitted, strict=True)):
        quantities = {m.quantity: _quantity(m, prediction) for m in shot.measurements}
        of_range = quantities.get("range", dict.fromkeys(("measured", "predicted", "residual", "uncertainty",
                                                          "weighted_residual")))
        shots.append({"design": shot.design_file, "measured": of_range["measured"],
                      "predicted": of_range["predicted"], "residual": of_range["residual"],
                      "uncertainty": of_range["uncertainty"], "weighted_residual": of_range["weighted_residual"],
                      "status": prediction.status, "quantities": quantities})
        if shot.track is not None:
            shots[-1]["track"] = track_json(result, k)
    correlation = [[_number(c) for c in row] for row in result.correlation.tolist()]
    return {"parameters": parameters, "shots": shots, "chi_square": result.chi_square,
            "degrees_of_freedom": result.degrees_of_freedom, "reduced_chi_square": result.reduced_chi_square,
            "p_value": result.p_value, "correlation": correlation,
            "uncertainty_definition": UNCERTAINTY_DEFINITION, "converged": result.converged,
            "message": result.message, "warnings": list(result.warnings), "evaluations": result.evaluations,
            "shots_simulated": result.shots, "shots_failed": result.failed_shots, "seconds": result.seconds,
            "predictions": [p.to_json() for p in predictions]}


def _format(value: float | None, digits: int = 4) -> str:
    return "-" if value is None or not math.isfinite(value) else f"{value:.{digits}f}"


def format_report(result: Calibration, system: str = "metric", predictions=()) -> str:
    """The result as text: parameters, fit quality, every shot's measurements, predictions, warnings;
    lengths and masses in ``system``'s units (``analytic.units.display``)."""
    from analytic.units import display

    spec = result.spec
    lines = [(f"calibration {spec.path.name}: {len(spec.parameters)} parameter(s), {len(spec.shots)} shot(s), "
              f"{spec.measurements} measurement(s)"), "", "parameters (value +- one standard deviation):"]
    width = max(len(p.name) for p in spec.parameters)
    for j, p in enumerate(spec.parameters):
        sd = result.uncertainties[j]
        flags = (" [at bound]" if result.at_bound[j] else "") + (" [not fixed by the data]"
                                                                  if result.singular[j] else "")
        scale, unit = display(1.0, p.unit, system)
        lines.append(f"  {p.name:<{width}}  {result.values[j] * scale:.6g} +- "
                     f"{_format(sd * scale, 6) if math.isfinite(sd) else '?'} {unit}".rstrip()
                     + f"   (start {p.start * scale:g}, bounds {p.lower * scale:g} .. {p.upper * scale:g}){flags}")
    if len(spec.parameters) > 1:
        lines.append("  correlation:")
        for j, p in enumerate(spec.parameters):
            lines.append(f"    {p.name:<{width}}  " + "  ".join(f"{c:+.3f}" if math.isfinite(c) else "   -  "
                                                                 for c in result.correlation[j]))
    reduced = result.reduced_chi_square
    lines += ["", f"chi-square {result.chi_square:.4g} with {result.degrees_of_freedom} degree(s) of freedom"
              + ("" if reduced is None else f" (reduced {reduced:.3g}, p = {result.p_value:.3g})")
              + ("; no degrees of freedom: as many parameters as measurements, so the chi-square cannot "
                 "judge the model" if result.degrees_of_freedom == 0 else ""),
              f"uncertainties: {UNCERTAINTY_DEFINITION}",
              (f"{result.evaluations} evaluations, {result.shots} shots (fast path; {result.failed_shots} "
               f"did not throw) in {result.seconds:.1f} s; {result.message}"),
              "", "shots (residual = predicted - measured):"]
    for k, (shot, start, fitted) in enumerate(zip(spec.shots, result.initial, result.fitted, strict=True)):
        lines.append(f"  {shot.label} {shot.design_file}: {fitted.status}")
        lines += track_lines(result, k, system)
        for m in shot.measurements:
            q = _quantity(m, fitted)
            before = start.values[m.quantity] if start.ok else None
            scale, unit = display(1.0, m.unit, system)

            def shown(value: float | None) -> str:
                return _format(None if value is None else value * scale)

            lines.append(f"    {m.quantity:<14} measured {m.value * scale:.4f} +- {m.uncertainty * scale:.4g} "
                         f"{unit:<3}  predicted {shown(q['predicted'])} {unit} (at start {shown(before)})  "
                         f"residual {shown(q['residual'])} {unit} ({_format(q['weighted_residual'], 2)} sd)")
    if predictions:
        scale, unit = display(1.0, "m", system)
        lines += ["", "predicted range (one standard deviation from the fit's covariance, delta method):"]
        for p in predictions:
            at = "{} = {:g} {}".format(p.field, *display(p.value, field(p.field).unit, system)).rstrip()
            lines.append(f"  {at}: " + (f"{p.range * scale:.2f} +- {p.range_sd * scale:.2f} {unit}"
                                        if p.range_sd is not None
                                        else f"{p.range * scale:.2f} {unit} (uncertainty undefined)"
                                        if p.range is not None else f"no throw ({p.message})"))
    if result.warnings:
        lines += ["", "warnings:"] + [f"  {w}" for w in result.warnings]
    return "\n".join(lines)


def calibration_figure(result: Calibration, predictions=(), system: str = "metric"):
    """The plot (module docstring): range against the varied field where there is one, measured
    against predicted for each other quantity (error bars: one standard deviation; at the start
    open, at the fit filled), and every weighted residual; shown in ``system``'s units
    (``analytic.plot_units.in_units``), the data SI."""
    from analytic.plot_units import in_units

    from matplotlib.figure import Figure

    from analytic.calibrate.predict import varied_field

    spec = result.spec
    target = field(predictions[0].field) if predictions else varied_field(spec)
    measured = [q for q in QUANTITIES if any(m.quantity == q for s in spec.shots for m in s.measurements)]
    if target is not None and "range" not in measured:   # tracks alone: the predicted range's panel first
        measured = ["range"] + measured
    fig = Figure(figsize=(min(4.8 * (len(measured) + 1), 14.0), 4.8), layout="constrained")
    axes = fig.subplots(1, len(measured) + 1, squeeze=False)[0]
    fitted_at = ", ".join(f"{p.name} = {v:.4g} {p.unit}".rstrip()
                          for p, v in zip(spec.parameters, result.values, strict=True))
    fig.suptitle(f"{spec.path.name}: fitted {fitted_at}", fontsize=10)
    if target is not None:
        _range_against(axes[0], result, target, predictions, system)
    for ax, quantity in zip(axes[1:] if target is not None else axes, measured[1:] if target is not None
                            else measured, strict=False):
        unit = QUANTITIES[quantity][1]
        xs, sds, starts, fits, numbers = [], [], [], [], []
        for shot, start, fitted in zip(spec.shots, result.initial, result.fitted, strict=True):
            for m in shot.measurements:
                if m.quantity == quantity:
                    numbers.append(shot.number)
                    xs.append(m.value)
                    sds.append(m.uncertainty)
                    starts.append(start.values[quantity] if start.ok else math.nan)
                    fits.append(fitted.values[quantity] if fitted.ok else math.nan)
        xs, sds = np.array(xs), np.array(sds)
        starts, fits = np.array(starts, dtype=float), np.array(fits, dtype=float)
        ax.errorbar(xs, fits, xerr=sds, fmt="o", color="tab:blue", ms=5, capsize=3, label="fitted")
        ax.plot(xs, starts, "o", mfc="none", color="tab:grey", ms=6, label="at start")
        for number, x, y in zip(numbers, xs, fits, strict=True):
            if math.isfinite(y):
                ax.annotate(str(number), (x, y), textcoords="offset points", xytext=(5, 5), fontsize=7)
        values = np.concatenate([xs - sds, xs + sds, starts[np.isfinite(starts)], fits[np.isfinite(fits)]])
        low, high = float(values.min()), float(values.max())
        pad = 0.05 * (high - low) or 0.05 * abs(high) or 1.0
        ax.plot([low - pad, high + pad], [low - pad, high + pad], "k-", lw=0.8, label="predicted = measured")
        ax.set(xlabel=f"measured {quantity.replace('_', ' ')} ({unit})",
               ylabel=f"predicted {quantity.replace('_', ' ')} ({unit})", title=quantity.replace("_", " "))
        ax.legend(fontsize=8)
        ax.grid(alpha=0.3)
    ax = axes[-1]
    labels, weighted = track_bars(result)
    positions = np.arange(len(labels))
    ax.axhspan(-1, 1, color="tab:green", alpha=0.12, label="within one sd")
    ax.bar(positions, weighted, color="tab:blue")
    ax.axhline(0.0, color="k", lw=0.8)
    ax.set_xticks(positions, labels, rotation=60, fontsize=7, ha="right")
    ax.set(xlabel="shot: quantity", ylabel="(predicted - measured) / uncertainty",
           title=f"weighted residuals (chi2 = {result.chi_square:.3g})")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3, axis="y")
    return in_units(fig, system)


def _range_against(ax, result: Calibration, target, predictions, system: str = "metric") -> None:
    """Measured ranges against ``target``'s setting, the fitted curve and its one-sd band, the predictions
    (each labelled in ``system``'s units, on the side of the panel with room, off the curve)."""
    from analytic.calibrate.predict import fitted_curve
    from analytic.units import display

    curve = [c for c in fitted_curve(result, target, [p.value for p in predictions]) if c.range is not None]
    xs = np.array([c.value for c in curve])
    ys = np.array([c.range for c in curve])
    sds = np.array([c.range_sd if c.range_sd is not None else math.nan for c in curve])
    ax.fill_between(xs, ys - sds, ys + sds, color="tab:blue", alpha=0.2, lw=0, label="fit +- one sd")
    ax.plot(xs, ys, "-", color="tab:blue", lw=1.5, label="fitted model")
    for shot in result.spec.shots:
        for m in shot.measurements:
            if m.quantity == "range":
                ax.errorbar(target.get(shot.design), m.value, yerr=m.uncertainty, fmt="o", color="k", ms=5,
                            capsize=3, label="measured" if shot.number == 1 else None)
    for i, p in enumerate(q for q in predictions if q.range is not None):
        ax.errorbar(p.value, p.range, yerr=p.range_sd or 0.0, fmt="D", color="tab:red", ms=7, capsize=4,
                    label="predicted" if i == 0 else None)
        (shown, unit), sd = display(p.range, "m", system), display(p.range_sd or math.nan, "m", system)[0]
        left = p.value > 0.5 * (xs[0] + xs[-1])
        rising = np.interp(p.value, xs, np.gradient(ys, xs)) > 0.0
        above = left == rising   # above the curve where it runs lower beside the label
        ax.annotate(f"{shown:.2f} +- {sd:.2f} {unit}", (p.value, p.range), textcoords="offset points",
                    xytext=(-6 if left else 6, 6 if above else -12), ha="right" if left else "left",
                    fontsize=8, color="tab:red")
    ax.set(xlabel=target.label, ylabel="range (m)", title=f"range against {target.key.replace('_', ' ')}")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)


def write(result: Calibration, out: str | Path, predictions=(), system: str = "metric") -> list[Path]:
    """Write the report and the plot (in ``system``'s units), the JSON (SI, file units) and each
    distinct setting's design at the fitted parameters (``FITTED_FOLDER/<setting>.toml``,
    ``analytic.calibrate.fitted_file``) into ``out``; the paths written."""
    import json

    from analytic.calibrate.fitted_file import fitted_text, setting_name
    from analytic.plot import save_figure

    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    written = [out / REPORT_FILE, out / JSON_FILE, out / PLOT_FILE]
    written[0].write_text(format_report(result, system, predictions) + "\n")
    written[1].write_text(json.dumps(to_json(result, predictions), indent=2) + "\n")
    save_figure(calibration_figure(result, predictions, system), written[2])
    if any(shot.track is not None for shot in result.spec.shots):
        written.append(out / TRACK_PLOT_FILE)
        save_figure(tracks_figure(result, system), written[-1])
    folder = out / FITTED_FOLDER
    folder.mkdir(exist_ok=True)
    names: dict[str, tuple] = {}   # file name -> the design file and settings it was written for
    for shot in result.spec.shots:
        name, setting = setting_name(shot), (shot.design_file, tuple(shot.settings.items()))
        if names.get(name) == setting:
            continue   # the same design at the same setting: one file
        if name in names:   # another design file of the same name, or settings that print alike
            name = f"{name}-shot{shot.number}"
        names[name] = setting
        path = folder / f"{name}.toml"
        path.write_text(fitted_text(result, shot))
        written.append(path)
    return written
