"""The text summary of a design study (what ``ringlube optimise`` prints at the end)."""

from __future__ import annotations

import numpy as np

from .bounds import point_violations, unconverged_reference
from .check import candidates_text
from .format import (
    NOT_CONVERGED,
    _feasible_text,
    _lift_mark,
    _values,
    branch_risks,
    design_points,
    format_design,
    surrogate_error,
    with_unit,
)
from .store import Study
from .variables import output_units

__all__ = ["summary"]


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
        + (f" (and {study.checks_executed} of the checks)" if study.checks_executed else "")
    ]
    if s.constraints:
        lines.append(f"constraints: {'; '.join(s.constraints)} (feasibility below by the true model)")
    for label, c in study.cases.items():
        lines.append(f"[{label}]")
        if unconverged_reference(study, label):
            lines.append(f"  warning: {unconverged_reference(study, label)}")
        lines.append(_failed_line(c))
        for o in s.objectives:
            sf = c.surfaces.get(o)
            if sf:
                lines.append(
                    f"  surface {o:12s} R2 {sf.r2:.4f}  adj {sf.r2_adj:.4f}  "
                    f"{s.folds}-fold CV rmse {with_unit(f'{sf.cv_rmse:.4g}', units[o])} "
                    f"({sf.cv_rel:.2%})"
                )
        fr = c.front
        if fr is not None:
            lines.append(
                f"  Pareto set: {len(fr.f)} designs from {s.repeats} NSGA-II repeats; "
                f"hypervolume of a single repeat / merged: mean {fr.hv_ratio_mean:.3f}, "
                f"min {fr.hv_ratio_min:.3f}"
            )
        how = candidates_text(study, label)
        if how:
            lines.append(f"  {how}")
        for ch in (c.chosen, c.reference):
            if ch is None:
                continue
            elsewhere = None
            if s.constraints and ch.points and label != "scene":  # (its own point's: above)
                own = f"at {label}:"
                found = point_violations(study, ch.points)
                elsewhere = [[v for v in d if not v.startswith(own)] for d in found]
            for i, (n, x, ft, fs, e, ok) in enumerate(
                zip(ch.names, ch.x, ch.f_true, ch.f_surrogate, ch.errors, ch.converged)
            ):
                cols = [study.s.outputs.index(o) for o in s.objectives]
                if e:
                    lines.append(f"  {n:18s} {format_design(study, x)} -> failed: {e}")
                    continue
                lift = _lift_mark(study, ft)
                lines.append(
                    f"  {n:18s} {format_design(study, x)} -> "
                    + ("" if ok else f"{NOT_CONVERGED}: ")
                    + (f"{lift}: " if lift else "")
                    + "".join(f"{m}: " for m in branch_risks(study, ft))
                    + _values(s.objectives, ft[cols])
                    + "  (surrogate error "
                    + ", ".join(surrogate_error(study.s.outputs[j], fs[j], ft[j]) for j in cols)
                    + ")"
                    + (f"; {_feasible_text(study, label, ft, design_points(ch, i))}" if s.constraints else "")
                    + (
                        f"; at the other points INFEASIBLE ({'; '.join(elsewhere[i])})"
                        if elsewhere and elsewhere[i]
                        else ""
                    )
                )
        dom = c.dominating
        if dom is not None and len(dom.sample):
            k = len(set(dom.sample.tolist()))
            lines.append(
                f"  warning: {k} of the {dom.compared} good samples {'dominates' if k == 1 else 'dominate'} "
                f"a chosen design ({', '.join(dict.fromkeys(dom.chosen))}) by the true "
                "model: the surfaces misplaced the front there (report.md names them)"
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
