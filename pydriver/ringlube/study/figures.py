"""The figures of a design study: the study turned into the plain arrays that
:mod:`ringlube.study.plots` draws (fits, response maps, trade-offs)."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from .bounds import constraint_bounds
from .store import Study
from .variables import display, output_units, result_display

__all__ = ["study_figures", "tradeoff_stems", "tradeoff_figures", "bore_figures", "BORE_FIGURES"]

#: the figures of a case with a distorted bore (its chosen knee re-run): ``bore_LABEL_KIND``
BORE_FIGURES = ("polar", "map", "flow")


def study_figures(study: Study, out: str | os.PathLike) -> list[Path]:
    """The study's figures, drawn from plain arrays (see :mod:`ringlube.study.plots`).

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
    from . import plots as sp

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
            panels.append(
                sp.FitPanel(
                    o,
                    units[o],
                    c.runs.outputs[ok, study.s.outputs.index(o)],
                    sf(x),
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
            files += sp.save(
                sp.map_figure(f"{o} ({label})", f"{o} [{units[o]}]", c.surfaces[o], axes, marks),
                out,
                f"map_{label}_{o}",
            )
    files += tradeoff_figures(study, out)
    files += bore_figures(study, out)
    return files


def bore_figures(study: Study, out: str | os.PathLike) -> list[Path]:
    """The figures of each case with a distorted bore (``&physics bore = 'distorted'``): its
    chosen knee re-run with the true model for its series, then the film/gap around the bore
    at the crank angles of :data:`~ringlube.plot_bore.POLAR_ANGLES`, its crank angle x sector
    map and the face flow beside the end gaps (``bore_LABEL_polar``, ``_map``, ``_flow``; none
    for a round bore or a case without a chosen knee).

    Parameters
    ----------
    study : Study
    out : path

    Returns
    -------
    list of Path

    Example
    -------
    >>> bore_figures(study, "out/s")                          # doctest: +SKIP
    """
    from .. import plot_bore as pb
    from ..solve import run
    from ..tables import INPUTS
    from . import plots as sp
    from .runs import _bases

    s, files = study.s, []
    for label, base in zip(s.labels, _bases(s)):
        c = study.cases.get(label)
        if base.value("physics", "bore") != "distorted" or c is None or c.chosen is None:
            continue
        if "knee" not in c.chosen.names:
            continue
        x = c.chosen.x[c.chosen.names.index("knee")]
        case = base
        for (group, name), v in zip(s.groups_names, x):
            whole = INPUTS[group, name].kind == "integer"
            case = case.with_(group, **{name: int(round(v)) if whole else float(v)})
        r = run(case)
        r.label = f"{label} knee" + ("" if r.converged else " (not converged)")
        for kind, make in zip(BORE_FIGURES, (pb.bore_polar_figure, pb.bore_map_figure, pb.face_flow_figure)):
            files += sp.save(make([r]), out, f"bore_{label}_{kind}")
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

    from . import plots as sp

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
        limits = [  # (a scene's point constraints bound no mean: not drawn)
            (
                "x" if bd.constraint.name == s.objectives[b] else "y",
                bd.value * shown[idx][1],
                f"{label}: {bd.constraint} (constraint)",
            )
            for label in fronts
            for bd in constraint_bounds(study, label)
            for idx in (a, b)
            if bd.constraint.name == s.objectives[idx] and bd.point == label
        ]
        files += sp.save(sp.tradeoff_figure(series, labels[b], labels[a], title, limits), out, stem)
    if len(s.objectives) >= 3:
        series = [sp.TradeoffSeries(label, fronts[label], designs[label]) for label in fronts]
        files += sp.save(sp.parallel_figure(series, labels, "objectives of the Pareto set"), out, stems[-1])
    return files
