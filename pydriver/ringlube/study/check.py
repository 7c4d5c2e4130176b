"""The chosen designs (and the reference design) of a study re-simulated with the true model.

The surfaces choose the candidates, the true model chooses among them: the surrogate's own
extremes and knee and the designs of its merged Pareto set farthest apart in objectives, up
to :data:`FRONT_CHECKS` per case, are re-simulated (:func:`candidate_designs`), and the
chosen designs are the extremes and the knee of those that are good by the true model
(:func:`pick_designs`: converged, on the liner, within the constraints). A surface that fits
a stepped result poorly (blowby, flutter) then moves no chosen design onto a design the true
model rejects, as long as one of the candidates is good.

The surfaces can still misplace the front: the study's own samples, already run with the true
model, are compared with each chosen design (:func:`dominating_samples`), and those that
dominate one are kept and reported.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from ..executor import Executor
from . import runs
from .bounds import feasibility
from .format import format_design, lift_share
from .optimise import choose_designs, extremes_and_knee, nondominated
from .runs import _bases
from .state_checks import Checked, Dominating
from .store import Study
from .surfaces import predict

__all__ = [
    "FRONT_CHECKS",
    "DOMINANCE_RTOL",
    "candidate_designs",
    "candidates_text",
    "check_designs",
    "dominates",
    "dominating_samples",
    "good_designs",
    "pick_designs",
    "run_at_every_point",
    "sample_designs",
    "ties",
]

#: Designs of the merged Pareto set re-simulated per case to choose from (the surrogate's
#: extremes and knee among them).
FRONT_CHECKS = 32

#: Relative difference of two true-model values of an objective below which they count as a
#: tie when a sample is compared with a chosen design (:func:`dominates`): the kernel's default
#: periodicity tolerance (``&numerics cycle_tol``), below which a converged cycle's results are
#: not known.
DOMINANCE_RTOL = 1e-3


def candidate_designs(study: Study, n: int = FRONT_CHECKS) -> dict[str, tuple[list[str], np.ndarray]]:
    """The designs of each case's merged Pareto set to re-simulate: the surrogate's extremes
    and knee (:func:`~ringlube.study.optimise.choose_designs`), then the front's designs
    farthest from those already taken in normalised objectives, up to ``n`` in all.

    Parameters
    ----------
    study : Study
        With fronts.
    n : int
        Designs per case at most.

    Returns
    -------
    dict of str to (names, x)
        Per case: ``['surrogate min OBJ', ..., 'surrogate knee', 'front 1', ...]`` and the
        designs (rows).

    Example
    -------
    >>> candidate_designs(study)["cold"][0][-1]                 # doctest: +SKIP
    'front 28'
    """
    out = {}
    for label, (names, xs) in choose_designs(study).items():
        front = study.cases[label].front
        fx, ff = np.asarray(front.x), np.asarray(front.f)
        z = (ff - ff.min(0)) / np.maximum(ff.max(0) - ff.min(0), 1e-300)
        taken = [int(np.flatnonzero((fx == x).all(axis=1))[0]) for x in xs]
        d = np.min(np.linalg.norm(z[:, None, :] - z[None, taken, :], axis=2), axis=1)
        extra: list[int] = []
        while len(names) + len(extra) < n and d.max() > 0:
            k = int(np.argmax(d))
            extra.append(k)
            d = np.minimum(d, np.linalg.norm(z - z[k], axis=1))
        out[label] = (
            [f"surrogate {m}" for m in names] + [f"front {i + 1}" for i in range(len(extra))],
            np.vstack([xs, fx[extra]]) if extra else np.asarray(xs),
        )
    return out


def good_designs(study: Study, label: str, ch: Checked) -> np.ndarray:
    """Which re-simulated designs are good by the true model: converged, no failure, finite
    objectives, not lifted off the liner (``liner_lift_share`` 0) and within the constraints.

    Parameters
    ----------
    study : Study
    label : str
    ch : Checked

    Returns
    -------
    ndarray of bool

    Example
    -------
    >>> good_designs(study, "cold", study.cases["cold"].candidates)   # doctest: +SKIP
    array([ True, False,  True, ...])
    """
    f = np.atleast_2d(ch.f_true)
    ok = np.asarray(ch.converged, bool) & np.isfinite(f[:, study.objective_columns()]).all(axis=1)
    ok &= feasibility(study, label, f, ch.points)
    ok &= np.array([lift_share(study, ft) == 0 for ft in f], bool)
    return ok


def sample_designs(study: Study, label: str) -> Checked:
    """The samples of a case (its design of experiments, as run by the true model) as a
    :class:`Checked`, so that :func:`good_designs` judges them by the candidates' rules: a
    sample not run, failed or not converged counts as not converged; the scene's samples carry
    their results at every point (its point constraints). Rows are the samples' indices.

    Parameters
    ----------
    study : Study
        With samples run.
    label : str
        Case label or ``scene``.

    Returns
    -------
    Checked
        Named ``sample 0``, ``sample 1``, ...; no surrogate values (NaN).

    Example
    -------
    >>> good_designs(study, "cold", sample_designs(study, "cold")).sum()   # doctest: +SKIP
    1019
    """
    r = study.cases[label].runs
    f = np.atleast_2d(r.outputs)
    points = None
    if label not in study.s.labels:  # the scene: each point's own runs of the same samples
        points = {p: np.atleast_2d(study.cases[p].runs.outputs) for p in study.s.labels}
    return Checked(
        [f"sample {i}" for i in range(len(f))],
        np.asarray(study.x),
        f,
        np.full(f.shape, np.nan),
        np.asarray(r.done, bool) & np.asarray(r.converged, bool) & ~np.asarray(r.failed, bool),
        list(r.errors),
        points,
    )


def ties(f: np.ndarray, g: np.ndarray, rtol: float = DOMINANCE_RTOL) -> np.ndarray:
    """Which values of ``f`` tie with ``g``'s (broadcast): they differ by no more than ``rtol``
    times the larger magnitude (a value that is not a number ties with nothing).

    Parameters
    ----------
    f, g : array_like
    rtol : float

    Returns
    -------
    ndarray of bool

    Example
    -------
    >>> ties(np.array([[2.043, 0.1663]]), np.array([2.041, 0.2295])).tolist()
    [[True, False]]
    """
    f, g = np.asarray(f, float), np.asarray(g, float)
    with np.errstate(invalid="ignore"):
        return np.abs(f - g) <= rtol * np.maximum(np.abs(f), np.abs(g))


def dominates(f: np.ndarray, g: np.ndarray, rtol: float = DOMINANCE_RTOL) -> np.ndarray:
    """Which rows of ``f`` dominate the design ``g`` (objectives minimised): no worse in every
    objective and better in at least one, where two values that differ by no more than
    ``rtol`` times the larger magnitude are a tie (:func:`ties`: neither better nor worse). A row or a ``g``
    with a value that is not a number dominates nothing.

    Parameters
    ----------
    f : ndarray, shape (k, m)
    g : ndarray, shape (m,)
    rtol : float

    Returns
    -------
    ndarray of bool, shape (k,)

    Example
    -------
    >>> f = np.array([[1.0, 1.0], [1.0, 2.0], [0.9995, 2.0], [0.5, 3.0]])
    >>> dominates(f, np.array([1.0, 2.0])).tolist()
    [True, False, False, False]
    """
    f, g = np.atleast_2d(np.asarray(f, float)), np.asarray(g, float)
    if not np.isfinite(g).all():
        return np.zeros(len(f), bool)
    tie = ties(f, g, rtol)
    with np.errstate(invalid="ignore"):
        better, worse = (f < g) & ~tie, (f > g) & ~tie
    return np.isfinite(f).all(axis=1) & ~worse.any(axis=1) & better.any(axis=1)


def dominating_samples(study: Study, label: str, rtol: float = DOMINANCE_RTOL) -> Dominating:
    """The good samples of a case (:func:`sample_designs` judged by :func:`good_designs`:
    converged, on the liner, within the constraints, by the true model) that dominate one of
    its chosen designs in the study's objectives (:func:`dominates`), per chosen design (those
    chosen twice, at one design, together) those not dominated by another good sample first,
    then by sample index.

    The chosen designs are the true model's best among designs of the surrogate's front; the
    surfaces may have put that front elsewhere than the true model's, and a sample the study
    already ran that beats a chosen design says so.

    Parameters
    ----------
    study : Study
        With chosen designs.
    label : str
        Case label or ``scene``.
    rtol : float
        Relative tolerance of a tie.

    Returns
    -------
    Dominating

    Example
    -------
    >>> dominating_samples(study, "r12000").chosen              # doctest: +SKIP
    ['min energy_loss', 'knee']
    """
    c = study.cases[label]
    cols = study.objective_columns()
    good = np.flatnonzero(good_designs(study, label, sample_designs(study, label)))
    fg = np.atleast_2d(np.asarray(c.runs.outputs))[good][:, cols]
    front = np.zeros(len(good), bool)
    if len(good):
        front[np.asarray(nondominated(fg), int)] = True
    chosen, sample, not_compared = [], [], []
    seen: list[tuple[int, list[str]]] = []  # each distinct chosen design: its first row, its names
    for i, (n, x) in enumerate(zip(c.chosen.names, c.chosen.x)):
        same = [names for k, names in seen if np.array_equal(c.chosen.x[k], x)]
        if same:
            same[0].append(n)
        else:
            seen.append((i, [n]))
    for i, names in seen:
        g = np.atleast_2d(c.chosen.f_true)[i, cols]
        if not np.isfinite(g).all():
            not_compared.append(", ".join(names))
            continue
        rows = np.flatnonzero(dominates(fg, g, rtol))
        rows = sorted(rows, key=lambda k: (not front[k], good[k]))
        chosen += [", ".join(names)] * len(rows)
        sample += [int(good[k]) for k in rows]
    sample_a = np.array(sample, int)
    return Dominating(
        chosen,
        sample_a,
        np.asarray(study.x)[sample_a].reshape(len(sample_a), len(study.s.variables)),
        np.atleast_2d(np.asarray(c.runs.outputs))[sample_a][:, cols].reshape(len(sample_a), len(cols)),
        len(good),
        rtol,
        not_compared,
    )


def pick_designs(study: Study, label: str, cand: Checked) -> Checked:
    """The chosen designs of a case from its re-simulated candidates: the extremes of each
    objective and the knee (nearest the ideal point in objectives normalised over the set)
    of the Pareto set, by the true model, of the good candidates (:func:`good_designs`);
    with no good candidate, the surrogate's own choices (the candidates' first rows).

    Parameters
    ----------
    study : Study
    label : str
    cand : Checked
        The candidates as :func:`check_designs` re-simulated them.

    Returns
    -------
    Checked
        Named ``min OBJ`` ... and ``knee``.

    Example
    -------
    >>> pick_designs(study, "cold", study.cases["cold"].candidates).names  # doctest: +SKIP
    ['min energy_loss', 'min mixed_share', 'min ring_mass', 'knee']
    """
    objectives = list(study.s.objectives)
    names = [f"min {o}" for o in objectives] + ["knee"]
    good = np.flatnonzero(good_designs(study, label, cand))
    if len(good) == 0:
        rows = list(range(len(names)))
    else:
        f = np.atleast_2d(cand.f_true)[good][:, study.objective_columns()]
        keep = np.asarray(nondominated(f), int)
        rows = [int(good[keep[i]]) for i in extremes_and_knee(f[keep])]
    return dataclasses.replace(cand.rows(rows), names=names)


def candidates_text(study: Study, label: str) -> str:
    """How the chosen designs of a case were chosen, in one sentence: the candidates
    re-simulated, how many were good by the true model and why the others were not, and
    whether the surrogate's own knee is the chosen one ('' without candidates).

    Parameters
    ----------
    study : Study
    label : str
        Case label or ``scene``.

    Returns
    -------
    str

    Example
    -------
    >>> candidates_text(study, "cold")                           # doctest: +SKIP
    '32 designs of the Pareto set re-simulated ...: 30 good, 2 lifted off the liner. ...'
    """
    c = study.cases[label]
    cand = c.candidates
    if cand is None or c.chosen is None:
        return ""
    f = np.atleast_2d(cand.f_true)
    good = good_designs(study, label, cand)
    failed = np.array([bool(e) for e in cand.errors])
    ran = ~failed
    why = {
        "failed": failed,
        "not converged": ran & ~np.asarray(cand.converged, bool),
        "lifted off the liner": ran & np.array([lift_share(study, ft) > 0 for ft in f]),
        "outside the constraints": ran & ~feasibility(study, label, f, cand.points),
    }
    counts = [f"{int(good.sum())} good"] + [f"{int(m.sum())} {k}" for k, m in why.items() if m.any()]
    text = (
        f"{len(cand.names)} designs of the Pareto set re-simulated with the true model (the "
        "surrogate's extremes and knee, and the front's designs farthest apart in objectives): "
        + ", ".join(counts)
        + (
            " (a design may count twice)."
            if sum(int(m.sum()) for m in why.values()) + good.sum() > len(f)
            else "."
        )
    )
    if not good.any():
        return text + " None is good by the true model: the chosen designs are the surrogate's own."
    i = cand.names.index("surrogate knee")
    if np.array_equal(cand.x[i], c.chosen.x[c.chosen.names.index("knee")]):
        return text + " The surrogate's own knee is the chosen knee."
    reasons = [k for k, m in why.items() if m[i]] or ["another good design is nearer the ideal point"]
    return (
        text + f" The surrogate's own knee ({format_design(study, cand.x[i])}) is not the chosen "
        f"knee: {', '.join(reasons)}."
    )


def check_designs(study: Study, ex: Executor, which: tuple[str, ...] = ("chosen", "reference")) -> None:
    """Re-simulate the candidates (:func:`candidate_designs`) and the reference design with
    the true model, and choose the designs among the candidates (:func:`pick_designs`).

    For the scene, each design runs on every base deck and the results are weighted (the
    results at each point are kept too, :attr:`Checked.points`). With several operating
    points and constraints, each case's chosen designs are also run at the other points
    (:func:`run_at_every_point`) and the reference's results at every point are gathered, so the
    report can say which designs satisfy every point's constraints.

    Parameters
    ----------
    study : Study
        With fronts (with surfaces only for ``which=("reference",)``).
    ex : Executor
    which : tuple of str
        ``chosen`` and/or ``reference``.

    Example
    -------
    >>> check_designs(study, Executor(serial=True))            # doctest: +SKIP
    """
    s = study.s
    bases = dict(zip(s.labels, _bases(s)))
    ref = None if s.reference is None else np.array([s.reference])
    if ref is None:
        for c in study.cases.values():
            c.reference = None
    jobs = []  # (label, key, names, xs)
    if "chosen" in which:
        for label, (names, xs) in candidate_designs(study).items():
            jobs.append((label, "candidates", names, xs))
    if ref is not None and "reference" in which:
        for label in study.cases:
            jobs.append((label, "reference", ["reference"], ref))
    results = runs.run_in_batches(
        study,
        ex,
        [
            ((j, base_label), bases[base_label], xs)
            for j, (label, _, _, xs) in enumerate(jobs)
            for base_label in ([label] if label in bases else s.labels)
        ],
    )
    w = dict(zip(s.labels, s.scene_weights()))
    for j, (label, key, names, xs) in enumerate(jobs):
        parts = [(bl, results[(j, bl)]) for bl in ([label] if label in bases else s.labels)]
        points = None
        if len(parts) == 1:
            values, conv, errors = parts[0][1]
        else:
            points = {bl: np.asarray(r[0]) for bl, r in parts}
            values = sum(w[bl] * r[0] for bl, r in parts)
            conv = np.all([r[1] for _, r in parts], axis=0)
            errors = [
                "; ".join(f"{bl}: {e}" for bl, e in zip((b for b, _ in parts), errs) if e)
                for errs in zip(*(r[2] for _, r in parts))
            ]
        setattr(
            study.cases[label],
            key,
            Checked(
                list(names),
                np.asarray(xs),
                np.asarray(values),
                predict(study, label, np.asarray(xs)),
                np.asarray(conv, bool),
                list(errors),
                points,
            ),
        )
    refs = [study.cases[label].reference for label in s.labels]
    if ref is not None and "reference" in which and all(r is not None for r in refs) and len(refs) > 1:
        at = {label: r.f_true for label, r in zip(s.labels, refs)}  # the same design at every point
        for r in refs:
            r.points = dict(at)
    if "chosen" in which:
        for label, c in study.cases.items():
            c.chosen = pick_designs(study, label, c.candidates)
            c.dominating = dominating_samples(study, label)
        run_at_every_point(study, ex)


def run_at_every_point(study: Study, ex: Executor) -> None:
    """Run each case's chosen designs at the other operating points (when the study has
    several and constraints), keeping their results there in :attr:`Checked.points`; a run
    that failed or did not converge there counts as not computed (NaN).

    Parameters
    ----------
    study : Study
        With chosen designs.
    ex : Executor

    Example
    -------
    >>> run_at_every_point(study, Executor(serial=True))        # doctest: +SKIP
    """
    s = study.s
    if len(s.labels) < 2 or not s.constraints:
        return
    bases = dict(zip(s.labels, _bases(s)))
    jobs = []
    for label in s.labels:
        chosen = study.cases[label].chosen
        for point in s.labels:
            if chosen is not None and point != label:
                jobs.append(((label, point), bases[point], chosen.x))
    results = runs.run_in_batches(study, ex, jobs)
    for label in s.labels:
        chosen = study.cases[label].chosen
        if chosen is None:
            continue
        chosen.points = {label: np.atleast_2d(chosen.f_true)}
        for point in s.labels:
            if point != label:
                values, conv, _ = results[(label, point)]
                chosen.points[point] = np.where(np.asarray(conv, bool)[:, None], values, np.nan)
        chosen.points = {p: chosen.points[p] for p in s.labels}  # in the study's order
