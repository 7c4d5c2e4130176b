"""The report of a finished design study: ``report.md`` (settings, runs, fits, Pareto
sets, chosen designs, how sure the answer is, figures), and every output file written at once
(:func:`write_outputs`: the figures of :mod:`ringlube.study.figures`, the Pareto CSV files of
:mod:`ringlube.study.pareto` and the report).

Every number carries its unit (:mod:`ringlube.study.format`).
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from ..outputs import check_output, write_text
from .bounds import constraint_bounds, point_violations, unconverged_reference
from .check import FRONT_CHECKS, candidates_text, dominating_samples, ties
from .figures import BORE_FIGURES, study_figures, tradeoff_stems
from .format import (
    BRANCH_RISK,
    LIFTED,
    LIFTED_COLUMN,
    NOT_CONVERGED,
    _feasible_text,
    _lift_mark,
    branch_risks,
    design_points,
    lift_share,
    result_display,
    surrogate_error,
    with_unit,
)
from .pareto import write_pareto_csv
from .settings import StudySettings
from .state_checks import Checked
from .store import Study
from .variables import display, output_units

__all__ = [
    "write_report",
    "dominating_lines",
    "how_sure_lines",
    "branch_risk_lines",
    "every_point_lines",
    "write_outputs",
    "output_names",
    "study_inputs",
]


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
    for i, (n, x, ft, fs, e, ok) in enumerate(
        zip(ch.names, ch.x, ch.f_true, ch.f_surrogate, ch.errors, ch.converged)
    ):
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
        marks += branch_risks(study, ft)
        rows.append(
            f"| {n}{''.join(f' ({m})' for m in marks)} | {xs} | "
            + " | ".join(f"{v * k:.4g}" for v, (_, k) in zip(ft, shown))
            + " | "
            + ", ".join(
                f"{s.objectives[k]} {surrogate_error(s.objectives[k], fs[j], ft[j])}"
                for k, j in enumerate(cols)
            )
            + " |"
            + (f" {_feasible_text(study, label, ft, design_points(ch, i))} |" if cons else "")
        )
    return rows


#: Dominating samples shown per chosen design in ``report.md`` (all are in the study file).
DOMINATING_SHOWN = 5


def dominating_lines(study: Study, label: str) -> list[str]:
    """The paragraph of ``report.md`` that says, for a case, which good samples of its design
    of experiments (true model) dominate one of its chosen designs: one sentence and a table
    (sample, its design, its objectives beside the chosen design's), or one sentence saying
    none does ([] without chosen designs). From the case's stored comparison
    (:attr:`~ringlube.study.state.CaseState.dominating`; made from the runs if absent).

    Parameters
    ----------
    study : Study
    label : str
        Case label or ``scene``.

    Returns
    -------
    list of str
        Markdown lines.

    Example
    -------
    >>> dominating_lines(study, "cold")[0]                    # doctest: +SKIP
    'None of the 1019 good samples of the design of experiments ... dominates a chosen design ...'
    """
    s, c = study.s, study.cases[label]
    if c.chosen is None:
        return []
    d = c.dominating if c.dominating is not None else dominating_samples(study, label)
    how = (
        "no worse in every objective and better in at least one, differences of at most "
        f"{d.rtol:.1%} of the larger value counting as ties"
    )
    why = (
        "(run by the true model: converged, on the liner"
        + (", within the constraints" if s.constraints else "")
        + ")"
    )
    good = f"good samples of the design of experiments {why}"
    L = []
    if not len(d.sample):
        L.append(
            f"None of the {d.compared} {good} dominates a chosen design ({how})."
            if d.compared > 1
            else f"The one good sample of the design of experiments {why} does not dominate a chosen "
            f"design ({how})."
            if d.compared
            else "No sample of the design of experiments is good by the true model: the chosen "
            "designs were compared with none."
        )
    else:
        named = list(dict.fromkeys(d.chosen))
        per = "; ".join(
            f"{n} by {len(d.rows_of(n))} samples"
            if len(d.rows_of(n)) > DOMINATING_SHOWN
            else f"{n} by sample{'s' if len(d.rows_of(n)) > 1 else ''} "
            + ", ".join(str(k) for k in d.sample[d.rows_of(n)])
            for n in named
        )
        k = len(set(d.sample.tolist()))
        L.append(
            f"**{k} of the {d.compared} {good} {'dominates' if k == 1 else 'dominate'} a chosen design** "
            f"({how}, marked '(tie)' below): {per}. The surfaces misplaced the front there: the "
            "true model already found a better design than the chosen one."
        )
        heads = [display(v, u, lo, hi) for v, u, lo, hi in zip(s.variables, s.units, s.lower, s.upper)]
        shown = [result_display(o) for o in s.objectives]
        L += [
            "",
            "| chosen design | sample | "
            + " | ".join(h for h, _ in heads)
            + " | "
            + " | ".join(f"{o} [{u}] sample / chosen" for o, (u, _) in zip(s.objectives, shown))
            + " |",
            "|" + "---|" * (2 + len(heads) + len(shown)),
        ]
        cols = study.objective_columns()
        more = []
        for n in named:
            rows = d.rows_of(n)
            first = c.chosen.names.index(n.split(", ")[0])
            g = np.atleast_2d(c.chosen.f_true)[first, cols]
            for r in rows[:DOMINATING_SHOWN]:
                L.append(
                    f"| {n} | {d.sample[r]} | "
                    + " | ".join(f"{xi * k:.4g}" for xi, (_, k) in zip(d.x[r], heads))
                    + " | "
                    + " | ".join(
                        f"{a * k:.4g} / {b * k:.4g}" + (" (tie)" if tie else "")
                        for a, b, tie, (_, k) in zip(d.f[r], g, ties(d.f[r], g, d.rtol), shown)
                    )
                    + " |"
                )
            if len(rows) > DOMINATING_SHOWN:
                more.append(f"{n}: the first {DOMINATING_SHOWN} of {len(rows)}")
        L += [
            "",
            "Samples are rows of the study file's `samples/x` and `cases/"
            + label
            + "/runs/outputs` (from 0); those not dominated by another good sample come first"
            + (f" ({'; '.join(more)}; all in `cases/{label}/dominating`)" if more else "")
            + ".",
        ]
    if d.not_compared:
        L.append(
            "Not compared (their re-simulation gave no value of an objective): "
            + ", ".join(d.not_compared)
            + "."
        )
    return L


def every_point_lines(study: Study) -> list[str]:
    """The section of ``report.md`` that says which chosen designs (and the reference)
    satisfy every operating point's constraints, and which only their own point's (a study of
    several points with constraints; [] otherwise).

    Parameters
    ----------
    study : Study

    Returns
    -------
    list of str
        Markdown lines.

    Example
    -------
    >>> every_point_lines(study)[1]                          # doctest: +SKIP
    '## Constraints at every operating point'
    """
    s = study.s
    if len(s.labels) < 2 or not s.constraints:
        return []
    L = [
        "",
        "## Constraints at every operating point",
        "",
        "A case's designs were chosen against the constraints of its own point; here each chosen "
        "design (and the reference) is also run at the other operating points and checked against "
        "their constraints (true model; a run that failed or did not converge there counts as "
        "not computed). The scene's designs were chosen against every point's constraints.",
        "",
        "| case | design | its own point's constraints | every point's constraints |",
        "|---|---|---|---|",
    ]
    every, own_only = [], []
    for label, c in study.cases.items():
        for ch in (c.chosen, c.reference):
            if ch is None:
                continue
            if ch.points is None:
                for n in ch.names:
                    L.append(f"| {label} | {n} | - | not run at the other points |")
                continue
            bad = point_violations(study, ch.points)
            for i, (n, ft) in enumerate(zip(ch.names, ch.f_true)):
                own = _feasible_text(study, label, ft, design_points(ch, i))
                if ch.errors[i]:
                    own = "failed"
                all_ok = not bad[i] and own == "feasible"
                L.append(
                    f"| {label} | {n} | {own} | "
                    + ("all satisfied" if all_ok else "INFEASIBLE " + "; ".join(bad[i] or ["(its own)"]))
                    + " |"
                )
                if ch is c.chosen:
                    (every if all_ok else own_only if own == "feasible" else []).append(f"{label} {n}")
    L += [
        "",
        "Chosen designs that satisfy every point's constraints: " + (", ".join(every) or "none") + ".",
        "Chosen designs that satisfy only their own point's: " + (", ".join(own_only) or "none") + ".",
    ]
    return L


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
    from .. import __version__

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
            "true-model value at the same point (times its factor). A constraint without `at` "
            "holds at every operating point, one `at LABEL` at that point only; the scene's "
            "designs are bound at every point by that point's constraints (`at scene`: their "
            "weighted mean).",
            "",
            "| constraint | case | binds the values | bound |",
            "|---|---|---|---|",
        ]
        for label in study.cases:
            for bd in constraint_bounds(study, label):
                unit, scale = result_display(bd.constraint.name)
                where = "its own" if bd.point == label else f"at {bd.point}"
                if bd.point == "scene":
                    where = "their weighted mean"
                late = bd.constraint.uses_reference and unconverged_reference(study, bd.point)
                mark = " (its reference did NOT CONVERGE)" if late else ""
                L.append(
                    f"| `{bd.constraint}` | {label} | {where} | {bd.constraint.sense} "
                    f"{with_unit(f'{bd.value * scale:.4g}', unit)}{mark} |"
                )
        L.append("")
        warned = [unconverged_reference(study, label) for label in study.cases]
        L += [f"Warning: {w}." for w in warned if w] + ([""] if any(warned) else [])
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
                    f"{with_unit(f'{sf.cv_rmse * k:.4g}', unit)} | {sf.cv_rel:.2%} |"
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
        f"The surrogate's extremes and knee and the designs of the merged Pareto set farthest "
        f"apart in objectives (up to {FRONT_CHECKS} per case) are re-simulated with the true "
        "model; the chosen designs are the extremes of each objective and the knee (nearest "
        "the ideal point in objectives normalised over the set) of the Pareto set, by the true "
        "model, of those that are good by it: converged, on the liner"
        + (", within the constraints" if s.constraints else "")
        + " (with none good, the surrogate's own, marked). A surface that fits a result poorly "
        "(blowby, flutter events) can put its knee on a design the true model rejects; the "
        "true model chooses here"
        + (". Below them the reference design of the study deck" if s.reference is not None else "")
        + ". Results from the true model; surrogate error = (surface - true) / |true|. "
        f"A design marked '{NOT_CONVERGED}' did not reach a periodic cycle: its numbers are "
        f"the last cycle's and confirm nothing. A design marked '{LIFTED}' lifted the ring off "
        "the liner for the share of the cycle given (`liner_lift_share`: the film carried no "
        "load at those crank steps, which the model bounds by `h0_ceiling`): its numbers rest "
        "on that lift-off and it is not a design to choose. The Pareto CSV files mark the "
        f"designs the surfaces predict to lift off (column '{LIFTED_COLUMN}'). A design marked "
        f"'{BRANCH_RISK}' came within a threshold of a change of state (lifting off the liner, "
        'the face sealing or blowing: `lift_margin`, `seal_margin`, "How sure" below): a small '
        "change of the inputs or the numerics may put it in the other state, with other numbers.",
    ]
    for label, c in study.cases.items():
        if c.chosen is None:
            continue
        L += ["", f"### {label}", ""]
        how = candidates_text(study, label)
        L += [how, ""] if how else []
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
        L += ["", *dominating_lines(study, label)]
    L += every_point_lines(study)
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
        if any(f.stem.startswith("bore_") for f in figures):  # (docs/bore.md)
            L += [
                "`bore_CASE_*`: the chosen knee of a case with a distorted bore, re-run with the true "
                "model: the film/gap of each sector around the bore at chosen crank angles (a light gap "
                "bulges out), its crank angle x sector map, and the gas through the faces beside the end "
                "gaps.",
                "",
            ]
        L += [f"![{f.stem}]({f.name})" for f in figures]
    return write_text(out / "report.md", "\n".join(L) + "\n", [study.path, *study_inputs(s)])


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


def _reordered(base: np.ndarray, varied: np.ndarray) -> bool:
    """Whether two designs ranked strictly one way by ``base`` are ranked strictly the other
    way by ``varied`` (ties, e.g. no oil at all for every design, reorder nothing)."""
    b, v = (
        np.asarray(base)[:, None] - np.asarray(base)[None, :],
        np.asarray(varied)[:, None] - np.asarray(varied)[None, :],
    )
    return bool(np.any((b < 0) & (v > 0)))


def _order(names: list[str], values: np.ndarray) -> str:
    """The designs from the least value to the largest, ``=`` between equal values."""
    idx = _ranking(values)
    out = names[idx[0]]
    for a, b in zip(idx, idx[1:]):
        out += (" = " if values[b] == values[a] else " < ") + names[b]
    return out


def _change(value: float, base: float, digits: int) -> str:
    """(value - base) / |base| as a signed percentage; where base is 0 (a count such as
    flutter_events), the same ``+0%`` or both values; NaN (a failed run) as ``-``."""
    if not (np.isfinite(value) and np.isfinite(base)):
        return "-"
    if base == 0:
        return f"{0:+.{digits}%}" if value == 0 else f"{value:.4g} against 0"
    return f"{(value - base) / abs(base):+.{digits}%}"


def branch_risk_lines(study: Study, sures: list) -> list[str]:
    """The "Branch risk" part of "How sure": each margin's threshold and why, and the chosen
    designs (and the reference) whose margin is below it at the study's preset or took the
    other sign at 'accurate' (the other state).

    Parameters
    ----------
    study : Study
    sures : list of (str, Sure)
        The cases' re-runs (:func:`ringlube.study.sure.how_sure`).

    Returns
    -------
    list of str
        Markdown lines.

    Example
    -------
    >>> branch_risk_lines(study, [])[1]                      # doctest: +SKIP
    '### Branch risk'
    """
    from ..tables import MARGINS, SCALARS

    s = study.s
    names = [o for o in MARGINS if o in s.outputs]
    if not names:
        return []
    L = [
        "",
        "### Branch risk",
        "",
        'How close each design\'s run came to a change of state (docs/model.md, "Branch risk"): '
        "a margin below its threshold marks the design "
        f"'{BRANCH_RISK}'; a margin of the other sign at 'accurate' means the finer numerics "
        "took the other state.",
        "",
    ]
    L += [
        f"- `{o}` ({SCALARS[o].long_name}): threshold {MARGINS[o].threshold:g}, {MARGINS[o].reason}."
        for o in names
    ]
    found = []
    for label, su in sures:
        for n, nom, acc in zip(su.names, su.nominal, su.accurate):
            for o in names:
                j = s.outputs.index(o)
                small = abs(nom[j]) < MARGINS[o].threshold
                flipped = np.isfinite(acc[j]) and (nom[j] > 0) != (acc[j] > 0)
                if small or flipped:
                    found.append(
                        f"| {label} | {n} | `{o}` | {nom[j]:+.4f} | {acc[j]:+.4f} | "
                        + ("yes" if flipped else "no")
                        + " |"
                    )
    L.append("")
    if found:
        L += ["| case | design | margin | study preset | 'accurate' | other state at 'accurate' |"]
        L += ["|---|---|---|---|---|---|", *found]
    else:
        L.append(
            "Every chosen design's margins are above their thresholds and keep their sign at 'accurate'."
        )
    return L


def how_sure_lines(study: Study) -> list[str]:
    """The "How sure is this answer" section of ``report.md``.

    Five parts: the film model's numerical error at the preset used (the chosen designs
    re-run at preset ``'accurate'``), whether each case is calibrated (a ``&calibration``
    file), which chosen designs sit on a bound of the design box, which came close to a change
    of state (:func:`branch_risk_lines`), and a one-at-a-time
    sensitivity of the chosen designs to the uncertain inputs
    (:data:`ringlube.study.sure.UNCERTAIN`) with whether the ranking of the designs changes.

    Parameters
    ----------
    study : Study
        With :func:`ringlube.study.sure.how_sure` done.

    Returns
    -------
    list of str
        Markdown lines.

    Example
    -------
    >>> "## How sure is this answer" in how_sure_lines(study)   # doctest: +SKIP
    True
    """
    from ..case import Case

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
        for n, v, a in zip(su.names, su.nominal, su.accurate):
            L.append(f"| {label} | {n} | " + " | ".join(_change(v[j], a[j], 2) for j in cols) + " |")
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
    L += branch_risk_lines(study, sures)
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
        for i, (inp, fac) in enumerate(zip(su.inputs, su.factors)):
            lo, hi, nom = su.low[i], su.high[i], su.nominal
            for d, n in enumerate(su.names):
                L.append(
                    f"| `{inp}` | {fac:g} | {n} | "
                    + " | ".join(
                        f"{_change(lo[d, j], nom[d, j], 1)}, {_change(hi[d, j], nom[d, j], 1)}" for j in cols
                    )
                    + " |"
                )
            for o in s.objectives:
                j = s.outputs.index(o)
                for side, v in (("/", su.low[i]), ("x", su.high[i])):
                    if _reordered(su.nominal[:, j], v[:, j]):
                        changed.append(f"by {o} with {inp} {side} {fac:g}: {_order(su.names, v[:, j])}")
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
    inputs = [study.path, *study_inputs(study.s)]
    names = output_names(study.s)
    for name in names:  # every file the study reads is refused as an output, before writing any
        check_output(out / name, inputs, "--out")
    files = []
    if figures:
        files += study_figures(study, out)
    files += write_pareto_csv(study, out)
    files.append(write_report(study, out, [f for f in files if f.suffix == ".png"]))
    # outputs of earlier settings would be stale (the scene's after scene = .false.); figures
    # not drawn this time are kept unless their case has no results now
    gone = [label for label in [*study.s.labels, "scene"] if not _has_results(study, label)]
    written = {f.name for f in files}
    for name in names:
        old = out / name
        figure = name.endswith((".png", ".pdf"))
        stale = not figure or figures or any(name.startswith((f"fit_{g}.", f"map_{g}_")) for g in gone)
        if stale and name not in written and old.is_file() and not old.is_symlink():
            old.unlink()
    return files


def _has_results(study: Study, label: str) -> bool:
    c = study.cases.get(label)
    return c is not None and bool(c.surfaces)


def study_inputs(s: StudySettings) -> list[Path]:
    """Every file a study reads: the study deck, the base decks and the files they read
    (calibration, pressure traces).

    Parameters
    ----------
    s : StudySettings

    Returns
    -------
    list of Path

    Example
    -------
    >>> [p.name for p in study_inputs(StudySettings("s", ["/a/b.nml"], ["b"], [1.0], [], [], [], []))]
    ['b.nml']
    """
    files = [s.source, *s.cases, *s.inputs]
    return [Path(p) for p in dict.fromkeys(f for f in files if f)]


def output_names(s: StudySettings) -> list[str]:
    """The names of every file a study may write in its output folder (besides its study file
    ``NAME.h5``): the report, the Pareto CSV files and the figures of every case and the scene.

    Parameters
    ----------
    s : StudySettings

    Returns
    -------
    list of str

    Example
    -------
    >>> output_names(StudySettings("s", [], ["cold"], [1.0], [], [], [], ["energy_loss"]))[:3]
    ['report.md', 'pareto_cold.csv', 'pareto_scene.csv']
    """
    labels = [*s.labels, "scene"]
    stems = [f"fit_{label}" for label in labels]
    stems += [f"map_{label}_{o}" for label in labels for o in s.objectives]
    stems += tradeoff_stems(list(s.objectives))
    stems += [f"bore_{label}_{kind}" for label in s.labels for kind in BORE_FIGURES]  # a distorted bore
    return [
        "report.md",
        *(f"pareto_{label}.csv" for label in labels),
        *(f"{stem}.{fmt}" for stem in stems for fmt in ("png", "pdf")),
    ]
