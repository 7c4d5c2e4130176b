"""What a finished design study says: a text summary, ``report.md``, Pareto CSV files and
the figures (drawn by :mod:`ringlube.study_plots` from plain arrays taken from the study).

Every number carries its unit; designs are shown in the units of :func:`display`
(lengths in mm or µm, tension in the base decks' ``&ring tension_unit``).
"""

from __future__ import annotations

import csv
import os
from pathlib import Path

import numpy as np

from .outputs import atomic_path, write_text
from .study_store import Checked, Study
from .study_variables import display, output_units

#: How a re-checked design whose true-model run did not converge is marked (its numbers are
#: the last cycle's, not a verified periodic result).
NOT_CONVERGED = "NOT CONVERGED, not verified"
#: Mark of a design whose true-model run lifted the ring off the liner at some crank steps
#: (``liner_lift_share`` > 0: the film carried no load there and the results at those steps
#: rest on the lift-off model, issue 16): reported, never ranked as a good design.
LIFTED = "LIFTED OFF the liner, not a good design"
#: Pareto CSV column marking designs the surfaces predict to lift off the liner.
LIFTED_COLUMN = "lifted off the liner (surrogate)"

__all__ = [
    "LIFTED",
    "LIFTED_COLUMN",
    "NOT_CONVERGED",
    "summary",
    "write_report",
    "write_pareto_csv",
    "format_design",
    "result_display",
    "how_sure_lines",
    "study_figures",
    "tradeoff_stems",
    "tradeoff_figures",
    "write_outputs",
]


def format_design(study: Study, x) -> str:
    """A design as text in display units, e.g. ``width 1.004 mm, tension 8 N/m``.

    Parameters
    ----------
    study : Study
    x : array_like
        One value per variable (SI).

    Returns
    -------
    str

    Example
    -------
    >>> format_design(study, [1.004e-3, 9.31e-6, -38.3e-6, 8.0])    # doctest: +SKIP
    'width 1.004 mm, crown height 9.31 µm, crown offset -38.3 µm, tension 8 N/m'
    """
    s = study.s
    parts = []
    for v, u, lo, hi, xi in zip(s.variables, s.units, s.lower, s.upper, x):
        label, scale = display(v, u, lo, hi)
        name, _, unit = label.partition(" [")
        parts.append(f"{name} {xi * scale:.4g}" + (f" {unit[:-1]}" if unit else ""))
    return ", ".join(parts)


def result_display(name: str) -> tuple[str, float]:
    """Unit a result is shown in and the factor from its stored unit: lengths (stored in
    metres, e.g. ``min_film``) in µm, every other result in its own unit.

    Parameters
    ----------
    name : str
        A result (:func:`~ringlube.study_variables.output_units`).

    Returns
    -------
    unit : str
    scale : float

    Example
    -------
    >>> result_display("min_film"), result_display("energy_loss")
    (('µm', 1000000.0), ('J', 1.0))
    """
    unit = output_units()[name]
    return ("µm", 1e6) if unit == "m" else (unit, 1.0)


def _values(names, values) -> str:
    out = []
    for o, v in zip(names, values):
        unit, k = result_display(o)
        out.append(f"{o} {v * k:.4g} {unit}")
    return ", ".join(out)


def _failed_line(c) -> str:
    r = c.runs
    n_failed = int(r.failed.sum())
    line = (
        f"  true-model runs: {int(r.done.sum())} done, "
        f"{int((r.done & ~r.converged & ~r.failed).sum())} not converged, "
        f"{n_failed} failed (invalid designs); {r.wall_s:.1f} s"
    )
    if n_failed:
        i = int(np.flatnonzero(r.failed)[0])
        line += f"\n  first failed: sample {i}: {r.errors[i]}"
    return line


def summary(study: Study) -> str:
    """The study in a few lines per case, every number with its unit.

    Parameters
    ----------
    study : Study

    Returns
    -------
    str

    Example
    -------
    >>> print(summary(study))                                # doctest: +SKIP
    """
    s = study.s
    units = output_units()
    lines = [
        f"study '{s.name}': {s.samples} samples ({s.sampler}) x {len(s.labels)} cases; "
        f"true-model runs executed now: {study.runs_executed}"
    ]
    if s.constraints:
        lines.append(f"constraints: {'; '.join(s.constraints)} (feasibility below by the true model)")
    for label, c in study.cases.items():
        lines.append(f"[{label}]")
        lines.append(_failed_line(c))
        for o in s.objectives:
            sf = c.surfaces.get(o)
            if sf:
                lines.append(
                    f"  surface {o:12s} R2 {sf.r2:.4f}  adj {sf.r2_adj:.4f}  "
                    f"{s.folds}-fold CV rmse {sf.cv_rmse:.4g} {units[o]} "
                    f"({sf.cv_rel:.2%})"
                )
        fr = c.front
        if fr is not None:
            lines.append(
                f"  Pareto set: {len(fr.f)} designs from {s.repeats} NSGA-II repeats; "
                f"hypervolume of a single repeat / merged: mean {fr.hv_ratio_mean:.3f}, "
                f"min {fr.hv_ratio_min:.3f}"
            )
        for ch in (c.chosen, c.reference):
            if ch is None:
                continue
            for n, x, ft, err, e, ok in zip(ch.names, ch.x, ch.f_true, ch.rel_error, ch.errors, ch.converged):
                cols = [study.s.outputs.index(o) for o in s.objectives]
                if e:
                    lines.append(f"  {n:18s} {format_design(study, x)} -> failed: {e}")
                    continue
                lift = _lift_mark(study, ft)
                lines.append(
                    f"  {n:18s} {format_design(study, x)} -> "
                    + ("" if ok else f"{NOT_CONVERGED}: ")
                    + (f"{lift}: " if lift else "")
                    + _values(s.objectives, ft[cols])
                    + "  (surrogate error "
                    + ", ".join(f"{err[j]:+.1%}" for j in cols)
                    + ")"
                    + (f"; {_feasible_text(study, label, ft)}" if s.constraints else "")
                )
        d = c.direct
        if d is not None:
            lines.append(
                f"  direct NSGA-II: {d.runs} true-model runs ({d.failed} failed, "
                f"{d.unconverged} not converged, {d.lifted} lifted off the liner: never in its "
                "front) in "
                f"{d.wall_s:.1f} s; hypervolume direct {d.hv_direct:.3f} vs surrogate "
                f"front {d.hv_surrogate:.3f} (normalised, common reference); IGD "
                f"surrogate->direct {d.igd_surrogate_to_direct:.3f}, direct->surrogate "
                f"{d.igd_direct_to_surrogate:.3f} (normalised objectives)"
            )
    return "\n".join(lines)


def _predict(study: Study, label: str, x: np.ndarray) -> np.ndarray:
    from .surrogate import QuadraticSurface

    s, c = study.s, study.cases[label]
    return np.column_stack(
        [
            QuadraticSurface(np.array(s.lower), np.array(s.upper), np.asarray(c.surfaces[o].coef))(x)
            for o in study.s.outputs
        ]
    )


def write_pareto_csv(study: Study, out: str | os.PathLike) -> list[Path]:
    """Write each case's Pareto set as ``OUT/pareto_LABEL.csv``.

    Columns: the variables (SI), then every result as the surfaces predict it; the header
    gives each column's unit, e.g. ``width [m]``, ``energy_loss [J]``. The last column,
    :data:`LIFTED_COLUMN`, is ``yes`` where the surfaces predict the ring to lift off the
    liner (``liner_lift_share`` above its surface's cross-validation error), else ``no``.

    Parameters
    ----------
    study : Study
    out : path

    Returns
    -------
    list of Path

    Example
    -------
    >>> write_pareto_csv(study, "out/s")                     # doctest: +SKIP
    """
    s, units = study.s, output_units()
    files = []
    for label, c in study.cases.items():
        if c.front is None:
            continue
        pred = _predict(study, label, c.front.x)
        for j, o in enumerate(s.objectives):  # the GA's own values of its objectives
            pred[:, study.s.outputs.index(o)] = c.front.f[:, j]
        path = Path(out) / f"pareto_{label}.csv"
        with atomic_path(path, [study.path]) as tmp, open(tmp, "w", newline="") as fh:
            w = csv.writer(fh)
            w.writerow(
                [f"{v} [{u}]" if u else v for v, u in zip(s.variables, s.units)]
                + [f"{o} [{units[o]}] (surrogate)" for o in study.s.outputs]
                + [LIFTED_COLUMN]
            )
            lifted = _predicted_lift(study, label, pred)
            for x, y, up in zip(c.front.x, pred, lifted):
                w.writerow([repr(float(v)) for v in (*x, *y)] + ["yes" if up else "no"])
        files.append(path)
    return files


def _predicted_lift(study: Study, label: str, pred: np.ndarray) -> np.ndarray:
    """Designs whose predicted ``liner_lift_share`` exceeds its surface's CV error (a
    quadratic surface of a share that is mostly 0 is not exactly 0 anywhere)."""
    outputs = list(study.s.outputs)
    if "liner_lift_share" not in outputs:
        return np.zeros(len(pred), bool)
    sf = study.cases[label].surfaces.get("liner_lift_share")
    noise = float(sf.cv_rmse) if sf is not None and np.isfinite(sf.cv_rmse) else 0.0
    return pred[:, outputs.index("liner_lift_share")] > max(noise, 0.0)


def lift_share(study: Study, values: np.ndarray) -> float:
    """The ``liner_lift_share`` [%] among a design's results (0 if the study does not record
    it or the value is not a number).

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> st = SimpleNamespace(s=SimpleNamespace(outputs=["energy_loss", "liner_lift_share"]))
    >>> lift_share(st, np.array([1.5, 2.5])), lift_share(st, np.array([1.5, np.nan]))
    (2.5, 0.0)
    """
    outputs = list(study.s.outputs)
    if "liner_lift_share" not in outputs:
        return 0.0
    v = float(values[outputs.index("liner_lift_share")])
    return v if np.isfinite(v) and v > 0 else 0.0


def _lift_mark(study: Study, values: np.ndarray) -> str:
    """'' or the lift-off mark with the share of the cycle lifted."""
    share = lift_share(study, values)
    return f"{LIFTED} ({share:.3g} % of the cycle)" if share > 0 else ""


def _feasible_text(study: Study, label: str, ft: np.ndarray) -> str:
    """'feasible' or which constraints the true results violate."""
    from .study import constraint_bounds

    bad = []
    for k, j, b in constraint_bounds(study, label):
        unit, scale = result_display(k.name)
        if not np.isfinite(ft[j]) or k.violation(ft[j], b) > 0:
            rel = ">" if k.sense == "<=" else "<"
            bad.append(f"{k.name} {ft[j] * scale:.6g} {rel} {b * scale:.6g} {unit}")
    return "feasible" if not bad else "INFEASIBLE: " + "; ".join(bad)


def _design_table(study: Study, ch: Checked, label: str = "") -> list[str]:
    s = study.s
    heads = [display(v, u, lo, hi)[0] for v, u, lo, hi in zip(s.variables, s.units, s.lower, s.upper)]
    scales = [display(v, u, lo, hi)[1] for v, u, lo, hi in zip(s.variables, s.units, s.lower, s.upper)]
    shown = [result_display(o) for o in s.outputs]
    cons = bool(s.constraints)
    rows = [
        "| design | "
        + " | ".join(heads)
        + " | "
        + " | ".join(f"{o} [{u}]" for o, (u, _) in zip(s.outputs, shown))
        + " | surrogate error |"
        + (" constraints (true model) |" if cons else ""),
        "|" + "---|" * (2 + len(heads) + len(s.outputs) + cons),
    ]
    cols = [s.outputs.index(o) for o in s.objectives]
    for n, x, ft, err, e, ok in zip(ch.names, ch.x, ch.f_true, ch.rel_error, ch.errors, ch.converged):
        xs = " | ".join(f"{xi * k:.4g}" for xi, k in zip(x, scales))
        if e:
            rows.append(
                f"| {n} | {xs} | "
                + " | ".join("failed" for _ in s.outputs)
                + f" | {e} |"
                + (" failed |" if cons else "")
            )
            continue
        marks = ([] if ok else [NOT_CONVERGED]) + ([_lift_mark(study, ft)] if lift_share(study, ft) else [])
        rows.append(
            f"| {n}{''.join(f' ({m})' for m in marks)} | {xs} | "
            + " | ".join(f"{v * k:.4g}" for v, (_, k) in zip(ft, shown))
            + " | "
            + ", ".join(f"{s.objectives[k]} {err[j]:+.1%}" for k, j in enumerate(cols))
            + " |"
            + (f" {_feasible_text(study, label, ft)} |" if cons else "")
        )
    return rows


def write_report(study: Study, out: str | os.PathLike, figures: list[Path] | None = None) -> Path:
    """Write ``OUT/report.md``: settings, runs, fits, Pareto sets, chosen designs, figures.

    Parameters
    ----------
    study : Study
    out : path
    figures : list of Path, optional
        PNG files to link.

    Returns
    -------
    Path

    Example
    -------
    >>> write_report(study, "out/s")                         # doctest: +SKIP
    """
    from . import __version__

    s, units = study.s, output_units()
    out = Path(out)
    L = [
        f"# Design study `{s.name}`",
        "",
        f"Study deck `{s.source}`; study file `{study.path.name}`; ringlube {__version__}. "
        f"{s.samples} {s.sampler} samples per case, objectives (minimised): "
        f"{', '.join(f'{o} [{units[o]}]' for o in s.objectives)}; quadratic surfaces, "
        f"NSGA-II {s.population} x {s.generations} x {s.repeats} repeats, seed {s.seed}.",
        "",
    ]
    if s.constraints:
        L += [
            "## Constraints",
            "",
            "Every design of the Pareto sets satisfies these on the fitted surfaces (pymoo's "
            "constraint handling, `G <= 0`); the chosen designs are re-simulated and marked "
            "feasible or not by the true model. `reference` is the reference design's "
            "true-model value on the same case.",
            "",
            "| constraint | case | bound |",
            "|---|---|---|",
        ]
        from .study import constraint_bounds

        for label in study.cases:
            for k, _, b in constraint_bounds(study, label):
                unit, scale = result_display(k.name)
                L.append(f"| `{k}` | {label} | {k.sense} {b * scale:.4g} {unit} |")
        L.append("")
    L += ["## Design variables", ""]
    has_ref = s.reference is not None
    L += [
        "| variable | unit | lower | upper |" + (" reference |" if has_ref else ""),
        "|---|---|---|---|" + ("---|" if has_ref else ""),
    ]
    for i, (v, u, lo, hi) in enumerate(zip(s.variables, s.units, s.lower, s.upper)):
        label, k = display(v, u, lo, hi)
        unit = label.partition(" [")[2][:-1] or "-"
        ref = f" {s.reference[i] * k:.4g} |" if has_ref else ""
        L.append(f"| `{v}` | {unit} | {lo * k:.4g} | {hi * k:.4g} |{ref}")
    L += [
        "",
        "## Cases and true-model runs",
        "",
        "| case | base deck | weight | done | not converged | failed (invalid designs) | run time [s] |",
        "|---|---|---|---|---|---|---|",
    ]
    for label, c in study.cases.items():
        r = c.runs
        deck = f"`{s.cases[s.labels.index(label)]}`" if label in s.labels else "weighted mean of the cases"
        weight = s.weights[s.labels.index(label)] if label in s.labels else "-"
        L.append(
            f"| {label} | {deck} | {weight} | {int(r.done.sum())} | "
            f"{int((r.done & ~r.converged & ~r.failed).sum())} | {int(r.failed.sum())} | "
            f"{r.wall_s:.1f} |"
        )
    for label, c in study.cases.items():
        bad = np.flatnonzero(c.runs.failed)
        if len(bad) and label in s.labels:
            L += [
                "",
                f"Failed designs of `{label}` (first {min(5, len(bad))} of {len(bad)}; "
                "all in the study file, `cases/{label}/runs/errors`):",
                "",
            ]
            L += [f"- sample {i}: {c.runs.errors[i]}" for i in bad[:5]]
    L += [
        "",
        "## Surfaces",
        "",
        "| case | result | R² | adjusted R² | CV RMSE | CV RMSE / mean |",
        "|---|---|---|---|---|---|",
    ]
    for label, c in study.cases.items():
        for o in [*s.objectives, *(k.name for k in s.parsed_constraints if k.name not in s.objectives)]:
            sf = c.surfaces.get(o)
            if sf:
                unit, k = result_display(o)
                L.append(
                    f"| {label} | {o} | {sf.r2:.4f} | {sf.r2_adj:.4f} | "
                    f"{sf.cv_rmse * k:.4g} {unit} | {sf.cv_rel:.2%} |"
                )
    L += [
        "",
        "## Pareto sets",
        "",
        "| case | designs | hypervolume of a repeat / merged (mean, min) | CSV |",
        "|---|---|---|---|",
    ]
    for label, c in study.cases.items():
        if c.front is not None:
            L.append(
                f"| {label} | {len(c.front.f)} | {c.front.hv_ratio_mean:.3f}, "
                f"{c.front.hv_ratio_min:.3f} | [pareto_{label}.csv](pareto_{label}.csv) |"
            )
    L += [
        "",
        "## Chosen designs, re-simulated with the true model",
        "",
        "The extremes of each objective on the merged Pareto set and its knee (nearest the "
        "ideal point in normalised objectives)"
        + (", and the reference design of the study deck" if s.reference is not None else "")
        + ". Results from the true model; surrogate error = (surface - true) / |true|. "
        f"A design marked '{NOT_CONVERGED}' did not reach a periodic cycle: its numbers are "
        f"the last cycle's and confirm nothing. A design marked '{LIFTED}' lifted the ring off "
        "the liner for the share of the cycle given (`liner_lift_share`: the film carried no "
        "load at those crank steps, which the model bounds by `h0_ceiling`): its numbers rest "
        "on that lift-off and it is not a design to choose. The Pareto CSV files mark the "
        f"designs the surfaces predict to lift off (column '{LIFTED_COLUMN}').",
    ]
    for label, c in study.cases.items():
        if c.chosen is None:
            continue
        L += ["", f"### {label}", ""]
        L += _design_table(study, c.chosen, label)
        if c.reference is not None:
            L += _design_table(study, c.reference, label)[2:]
            inside = all(lo <= v <= hi for v, lo, hi in zip(s.reference, s.lower, s.upper))
            if not inside:
                L += [
                    "",
                    "The reference design lies outside the design box: its surrogate "
                    "values are extrapolated.",
                ]
    L += how_sure_lines(study)
    direct = [(label, c.direct) for label, c in study.cases.items() if c.direct is not None]
    if direct:
        L += [
            "",
            "## NSGA-II on the true model (--direct)",
            "",
            "A run that failed or did not converge violates the direct NSGA-II's first constraint: "
            "it is ranked below every converged design and never in its front; so does, by its "
            "share of the cycle, a run that lifted the ring off the liner (`liner_lift_share` > 0)"
            + ("; the study's constraints follow on the true results." if s.constraints else "."),
            "",
            "| case | runs | failed | not converged | lifted off the liner | wall time [s] | "
            "hypervolume direct / surrogate | IGD surrogate->direct, direct->surrogate |",
            "|---|---|---|---|---|---|---|---|",
        ]
        for label, d in direct:
            L.append(
                f"| {label} | {d.runs} | {d.failed} | {d.unconverged} | {d.lifted} | {d.wall_s:.1f} | "
                f"{d.hv_direct:.3f} / {d.hv_surrogate:.3f} | "
                f"{d.igd_surrogate_to_direct:.3f}, {d.igd_direct_to_surrogate:.3f} |"
            )
    if figures:
        L += ["", "## Figures", ""]
        L += [f"![{f.stem}]({f.name})" for f in figures]
    return write_text(out / "report.md", "\n".join(L) + "\n", [study.path])


def _on_bounds(study: Study, x: np.ndarray, rtol: float = 1e-3) -> list[str]:
    """The variables of design ``x`` within ``rtol`` of the box's width from a bound."""
    s, out = study.s, []
    for v, u, lo, hi, xi in zip(s.variables, s.units, s.lower, s.upper, x):
        label, k = display(v, u, lo, hi)
        unit = label.partition(" [")[2][:-1]
        for side, b in (("lower", lo), ("upper", hi)):
            if abs(xi - b) <= rtol * (hi - lo):
                out.append(f"{v} at its {side} bound ({b * k:.4g} {unit})".replace(" )", ")"))
    return out


def _ranking(values: np.ndarray) -> list[int]:
    return [int(i) for i in np.argsort(values, kind="stable")]


def how_sure_lines(study: Study) -> list[str]:
    """The "How sure is this answer" section of ``report.md``.

    Four parts: the film model's numerical error at the preset used (the chosen designs
    re-run at preset ``'accurate'``), whether each case is calibrated (a ``&calibration``
    file), which chosen designs sit on a bound of the design box, and a one-at-a-time
    sensitivity of the chosen designs to the uncertain inputs
    (:data:`ringlube.study.UNCERTAIN`) with whether the ranking of the designs changes.

    Parameters
    ----------
    study : Study
        With :func:`ringlube.study.how_sure` done.

    Returns
    -------
    list of str
        Markdown lines.

    Example
    -------
    >>> "## How sure is this answer" in how_sure_lines(study)   # doctest: +SKIP
    True
    """
    from .case import Case

    s = study.s
    shown = [o for o in s.outputs if o in s.objectives or o in {k.name for k in s.parsed_constraints}]
    cols = [s.outputs.index(o) for o in shown]
    L = ["", "## How sure is this answer", ""]
    sures = [(label, c.sure) for label, c in study.cases.items() if c.sure is not None]
    if not sures:
        return L + ["Not assessed (the study stopped before its designs were re-simulated)."]
    preset = sures[0][1].preset
    L += [
        "### Numerical error of the film model",
        "",
        f"The study ran at `&numerics preset = '{preset}'`. The chosen designs re-run at preset "
        "'accurate' (explicit `&numerics` values of the base decks kept) differ by "
        "(study - accurate) / |accurate|:",
        "",
        "| case | design | " + " | ".join(shown) + " |",
        "|" + "---|" * (2 + len(shown)),
    ]
    for label, su in sures:
        with np.errstate(divide="ignore", invalid="ignore"):
            rel = (su.nominal - su.accurate) / np.abs(su.accurate)
        for n, r in zip(su.names, rel):
            L.append(f"| {label} | {n} | " + " | ".join(f"{r[j]:+.2%}" for j in cols) + " |")
    if "accurate" in preset:
        L += ["", "The study already ran at preset 'accurate': these differences are zero by construction."]
    L += ["", "### Calibration", ""]
    for label, deck in zip(s.labels, s.cases):
        cal = Case.from_namelist(deck).get("calibration", "file")
        L.append(
            f"- {label}: calibrated (`&calibration file = '{cal}'`)"
            if cal
            else f"- {label}: **not calibrated** (no `&calibration` file): zeta_kappa_sigma and "
            "pressure_scale are the deck's or the kernel's defaults, not fitted to a measurement"
        )
    L += ["", "### Designs on a bound of the design box", ""]
    on = []
    for label, c in study.cases.items():
        if c.chosen is not None:
            for n, x in zip(c.chosen.names, c.chosen.x):
                where = _on_bounds(study, x)
                if where:
                    on.append(f"- {label}, {n}: {', '.join(where)}")
    L += on or ["None: every chosen design lies more than 0.1 % of the box's width inside each bound."]
    if on:
        L += ["", "A design on a bound may improve beyond it: widen the box if that is allowed."]
    L += ["", "### Sensitivity to the uncertain inputs", ""]
    for label, su in sures:
        if not su.inputs:
            L += [f"{label}: no uncertain input applies.", ""]
            continue
        L += [
            f"{label}: each input divided and multiplied by its factor, one at a time; change of "
            "each result relative to the nominal re-simulation.",
            "",
            "| input | factor | design | " + " | ".join(f"{o} (/, x)" for o in shown) + " |",
            "|" + "---|" * (3 + len(shown)),
        ]
        changed = []
        with np.errstate(divide="ignore", invalid="ignore"):
            for i, (inp, fac) in enumerate(zip(su.inputs, su.factors)):
                lo = (su.low[i] - su.nominal) / np.abs(su.nominal)
                hi = (su.high[i] - su.nominal) / np.abs(su.nominal)
                for d, n in enumerate(su.names):
                    L.append(
                        f"| `{inp}` | {fac:g} | {n} | "
                        + " | ".join(f"{lo[d, j]:+.1%}, {hi[d, j]:+.1%}" for j in cols)
                        + " |"
                    )
                for o in s.objectives:
                    j = s.outputs.index(o)
                    base = _ranking(su.nominal[:, j])
                    for side, v in (("/", su.low[i]), ("x", su.high[i])):
                        if _ranking(v[:, j]) != base:
                            order = " < ".join(su.names[q] for q in _ranking(v[:, j]))
                            changed.append(f"by {o} with {inp} {side} {fac:g}: {order}")
        L.append("")
        if changed:
            L += [f"The ranking of the designs of {label} **changes**:"] + [f"- {c}" for c in changed]
        else:
            L.append(
                f"The ranking of the designs of {label} by each objective is the same under every variation."
            )
        L.append("")
    return L


def write_outputs(study: Study, out: str | os.PathLike, figures: bool = True) -> list[Path]:
    """Write the report, the Pareto CSV files and (optionally) the figures.

    Parameters
    ----------
    study : Study
        A finished study.
    out : path
        Output folder.
    figures : bool
        Also the figures (PNG and PDF).

    Returns
    -------
    list of Path
        Files written.

    Example
    -------
    >>> write_outputs(study, "out/s")                          # doctest: +SKIP
    """
    out = Path(out)
    files = []
    if figures:
        files += study_figures(study, out)
    files += write_pareto_csv(study, out)
    files.append(write_report(study, out, [f for f in files if f.suffix == ".png"]))
    return files


def study_figures(study: Study, out: str | os.PathLike) -> list[Path]:
    """The study's figures, drawn from plain arrays (see :mod:`ringlube.study_plots`).

    Parameters
    ----------
    study : Study
    out : path

    Returns
    -------
    list of Path

    Example
    -------
    >>> study_figures(study, "out/s")                          # doctest: +SKIP
    """
    from . import study_plots as sp
    from .surrogate import QuadraticSurface

    s, out = study.s, Path(out)
    units = output_units()
    axes = [
        sp.Axis(*display(v, u, lo, hi), lo, hi)
        for v, u, lo, hi in zip(s.variables, s.units, s.lower, s.upper)
    ]
    files = []
    marks_all = {}
    for label, c in study.cases.items():
        if not c.surfaces:
            continue
        ok = c.runs.usable()
        x = study.x[ok]
        panels: list = []
        for o in s.objectives:
            sf = c.surfaces[o]
            f = QuadraticSurface(np.array(s.lower), np.array(s.upper), np.asarray(sf.coef))
            panels.append(
                sp.FitPanel(
                    o,
                    units[o],
                    c.runs.outputs[ok, study.s.outputs.index(o)],
                    f(x),
                    sf.r2,
                    sf.r2_adj,
                    sf.cv_rel,
                )
            )
        files += sp.save(sp.fit_figure(label, panels, s.folds), out, f"fit_{label}")
        marks = []
        for key, style in (("chosen", "chosen"), ("reference", "reference")):
            ch = getattr(c, key)
            if ch is not None:
                marks += [sp.Mark(n, xi, style) for n, xi in zip(ch.names, ch.x)]
        marks_all[label] = marks
        for o in s.objectives:
            f = QuadraticSurface(np.array(s.lower), np.array(s.upper), np.asarray(c.surfaces[o].coef))
            files += sp.save(
                sp.map_figure(f"{o} ({label})", f"{o} [{units[o]}]", f, axes, marks), out, f"map_{label}_{o}"
            )
    files += tradeoff_figures(study, out)
    return files


def tradeoff_stems(objectives: list[str]) -> list[str]:
    """File names (without suffix) of the trade-off figures of a study's objectives: one
    ``tradeoff_A_vs_B`` per pair (B on the horizontal axis), and ``tradeoff_parallel`` for
    three or more objectives.

    Parameters
    ----------
    objectives : list of str

    Returns
    -------
    list of str

    Example
    -------
    >>> tradeoff_stems(["energy_loss", "oil_to_chamber"])
    ['tradeoff_energy_loss_vs_oil_to_chamber']
    >>> len(tradeoff_stems(["a", "b", "c"]))
    4
    """
    import itertools

    stems = [f"tradeoff_{a}_vs_{b}" for a, b in itertools.combinations(objectives, 2)]
    return stems + (["tradeoff_parallel"] if len(objectives) >= 3 else [])


def tradeoff_figures(study: Study, out: str | os.PathLike) -> list[Path]:
    """The trade-off figures of the objectives the study minimised (:func:`tradeoff_stems`):
    the Pareto sets as the GA found them on the surfaces, the chosen and reference designs
    as re-simulated by the true model.

    Parameters
    ----------
    study : Study
    out : path

    Returns
    -------
    list of Path

    Example
    -------
    >>> tradeoff_figures(study, "out/s")                         # doctest: +SKIP
    """
    import itertools

    from . import study_plots as sp
    from .study import constraint_bounds

    s = study.s
    cols = [s.outputs.index(o) for o in s.objectives]
    shown = [result_display(o) for o in s.objectives]
    labels = [f"{o.replace('_', ' ')} [{u}]" for o, (u, _) in zip(s.objectives, shown)]
    scale = np.array([k for _, k in shown])
    fronts, designs = {}, {}
    for label, c in study.cases.items():
        if c.front is None:
            continue
        fronts[label] = np.asarray(c.front.f) * scale
        designs[label] = [
            (n, ft[cols] * scale, style)
            for ch, style in ((c.chosen, "chosen"), (c.reference, "reference"))
            if ch is not None
            for n, ft in zip(ch.names, ch.f_true)
            if np.isfinite(ft[cols]).all()
        ]
    if not fronts:
        return []
    files = []
    stems = tradeoff_stems(list(s.objectives))
    for (a, b), stem in zip(itertools.combinations(range(len(s.objectives)), 2), stems):
        series = [
            sp.TradeoffSeries(
                label, fronts[label][:, [b, a]], [(n, v[b], v[a], st) for n, v, st in designs[label]]
            )
            for label in fronts
        ]
        title = f"trade-off: {s.objectives[a]} against {s.objectives[b]} (both minimised)"
        limits = [
            ("x" if k.name == s.objectives[b] else "y", bound * shown[idx][1], f"{label}: {k} (constraint)")
            for label in fronts
            for k, _, bound in constraint_bounds(study, label)
            for idx in (a, b)
            if k.name == s.objectives[idx]
        ]
        files += sp.save(sp.tradeoff_figure(series, labels[b], labels[a], title, limits), out, stem)
    if len(s.objectives) >= 3:
        series = [sp.TradeoffSeries(label, fronts[label], designs[label]) for label in fronts]
        files += sp.save(sp.parallel_figure(series, labels, "objectives of the Pareto set"), out, stems[-1])
    return files
