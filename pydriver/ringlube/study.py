"""Design optimisation (SPEC section 12): sample -> run -> fit -> NSGA-II -> check.

The pipeline of ``ringlube optimise``. Its pieces live in their own modules:
:mod:`ringlube.study_deck` (the ``&study`` deck), :mod:`ringlube.study_state` (typed state),
:mod:`ringlube.study_store` (the HDF5 study file), :mod:`ringlube.executor` (serial,
processes or Dask), :mod:`ringlube.surrogate` (quadratic surfaces),
:mod:`ringlube.study_plots` (figures from plain arrays), and :mod:`ringlube.study_summary`,
:mod:`ringlube.study_report`, :mod:`ringlube.study_pareto` and :mod:`ringlube.study_figures`
(summary, report.md, Pareto CSV, figures).

Every finished piece of work is checkpointed, so an interrupted study started again with
the same command resumes and re-runs nothing that finished. A design the kernel rejects
(an invalid combination inside the box) is recorded as failed with its message and the
study goes on.
"""

from __future__ import annotations

import os
import time
from pathlib import Path

import numpy as np

from .case import Case
from .errors import InputError, RinglubeError
from .executor import Executor, require
from .outputs import check_output
from .study_deck import read_study
from .study_settings import StudySettings
from .study_state import CaseState, Checked, Direct, DirectGeneration, Front, Runs, Sure, Surface
from .study_store import Study

__all__ = [
    "StudySettings",
    "Study",
    "Executor",
    "read_study",
    "run_study",
    "sample",
    "run_samples",
    "fit_surfaces",
    "optimise",
    "choose_designs",
    "check_designs",
    "scene_results",
    "direct",
    "surfaces_of",
    "constraint_bounds",
    "feasibility",
    "direct_outputs",
    "how_sure",
    "FAILED_PENALTY",
    "UNCERTAIN",
]

#: Objective value given to a design the kernel rejects during the direct NSGA-II (the GA
#: needs a finite number; any valid design is far better).
FAILED_PENALTY = 1e10
#: The uncertain inputs of :func:`how_sure`, each multiplied and divided by its factor:
#: the liner film the lower rings leave (unmeasured; only with a starved inlet), the
#: roughness parameter and the gas-pressure scale (both calibrated at best).
UNCERTAIN = {
    ("lubricant", "supply_film"): 2.0,
    ("surface", "zeta_kappa_sigma"): 1.5,
    ("operating", "pressure_scale"): 1.1,
}


# --- running designs -----------------------------------------------------------------


def _run_designs(
    base_case: Case, variables: list[tuple[str, str]], x: np.ndarray, outputs: list[str]
) -> tuple[np.ndarray, np.ndarray, list[str]]:
    """Run designs ``x`` (rows) of ``base_case``: the one batch call of every study.

    Parameters
    ----------
    base_case : Case
        The base deck.
    variables : list of (group, name)
        What the columns of ``x`` set.
    x : ndarray, shape (k, d)
        Designs.
    outputs : list of str
        Scalar results to return (attributes of :class:`~ringlube.CycleResult`).

    Returns
    -------
    values : ndarray, shape (k, len(outputs))
        NaN for a failed design.
    converged : ndarray of bool, shape (k,)
    errors : list of str
        The kernel's message for each failed design, "" for the others.

    Example
    -------
    >>> v, ok, err = _run_designs(case, [("ring", "width")], np.array([[1e-3]]),
    ...                           ["energy_loss"])                   # doctest: +SKIP
    """
    from .solve import run_designs

    values, converged, errs = run_designs(
        base_case, [f"{g}:{n}" for g, n in variables], np.atleast_2d(np.asarray(x, float)), list(outputs)
    )
    errors = [(e.splitlines()[0] if e else "") if e is not None else "" for e in errs]
    return values, converged, errors


def sample(s: StudySettings) -> np.ndarray:
    """Sobol or Latin hypercube sample of the design box (scipy.stats.qmc).

    Parameters
    ----------
    s : StudySettings
        ``sampler``, ``samples``, ``seed``, ``lower``, ``upper``.

    Returns
    -------
    ndarray, shape (samples, len(variables))

    Example
    -------
    >>> x = sample(read_study("inputs/study_default.nml"))   # doctest: +SKIP
    >>> x.shape                                               # doctest: +SKIP
    (1025, 4)
    """
    from scipy.stats import qmc

    d = len(s.variables)
    if s.sampler == "sobol":
        eng = qmc.Sobol(d=d, scramble=True, seed=s.seed)
        m = int(np.ceil(np.log2(s.samples)))
        u = eng.random_base2(m)[: s.samples]
    else:
        u = qmc.LatinHypercube(d=d, seed=s.seed).random(s.samples)
    return qmc.scale(u, s.lower, s.upper)


def _bases(s: StudySettings) -> list[Case]:
    return [Case.from_namelist(deck) for deck in s.cases]


def run_samples(study: Study, ex: Executor, progress: bool = True, stop_after: int | None = None) -> None:
    """Run every sample on every case; finished runs are kept across interruptions.

    Parameters
    ----------
    study : Study
        With ``x`` sampled.
    ex : Executor
        Where the batches run.
    progress : bool
        Show a progress bar.
    stop_after : int, optional
        Test hook: raise KeyboardInterrupt once this many runs finished in this process.

    Example
    -------
    >>> run_samples(study, Executor(serial=True), progress=False)   # doctest: +SKIP
    """
    from tqdm.auto import tqdm

    s = study.s
    for label in s.labels:
        if label not in study.cases:
            study.cases[label] = CaseState(Runs.empty(s.samples, len(s.outputs)))
    tasks, where = [], []
    for label, base in zip(s.labels, _bases(s)):
        todo = np.flatnonzero(~study.cases[label].runs.done)
        for chunk in np.array_split(todo, max(1, int(np.ceil(len(todo) / s.batch)))):
            if len(chunk):
                tasks.append((base, s.groups_names, study.x[chunk], list(s.outputs)))
                where.append((label, chunk))
    total = sum(len(c) for _, c in where)
    if total == 0:
        return
    bar = tqdm(total=total, desc="true-model runs", unit="run", disable=not progress)
    t0 = time.perf_counter()

    def on_result(i, result):
        values, converged, errors = result
        label, chunk = where[i]
        r = study.cases[label].runs
        r.outputs[chunk] = values
        r.converged[chunk] = converged
        r.failed[chunk] = [bool(e) for e in errors]
        for j, e in zip(chunk, errors):
            r.errors[j] = e
        r.done[chunk] = True
        study.runs_executed += len(chunk)
        bar.update(len(chunk))
        study.save(force=False)
        if stop_after is not None and study.runs_executed >= stop_after:
            raise KeyboardInterrupt("stop_after reached (test hook)")

    try:
        ex.map(_run_designs, tasks, on_result)
    finally:
        bar.close()
        wall = time.perf_counter() - t0
        for label in s.labels:
            study.cases[label].runs.wall_s += wall / len(s.labels)
        study.save()


def scene_results(study: Study) -> None:
    """The weighted scene: every result averaged over the cases with their weights.

    Parameters
    ----------
    study : Study
        With every case run.

    Example
    -------
    >>> scene_results(study); study.cases["scene"].runs.outputs.shape   # doctest: +SKIP
    (1025, 5)
    """
    s = study.s
    w = np.array(s.weights) / sum(s.weights)
    runs = [study.cases[label].runs for label in s.labels]
    out = Runs(
        sum(wi * r.outputs for wi, r in zip(w, runs)),
        np.all([r.done for r in runs], axis=0),
        np.all([r.converged for r in runs], axis=0),
        np.any([r.failed for r in runs], axis=0),
        ["; ".join(e for e in errs if e) for errs in zip(*(r.errors for r in runs))],
    )
    old = study.cases.get("scene")
    study.cases["scene"] = (
        CaseState(out)
        if old is None
        else CaseState(out, old.surfaces, old.repeats, old.front, old.chosen, old.reference, old.direct)
    )


def fit_surfaces(study: Study) -> None:
    """Fit a quadratic surface of every result on every case (and the scene).

    Only samples that ran, converged and did not fail are fitted.

    Parameters
    ----------
    study : Study

    Raises
    ------
    RinglubeError
        Too few usable samples on a case for a quadratic.

    Example
    -------
    >>> fit_surfaces(study); study.cases["cold"].surfaces["energy_loss"].r2  # doctest: +SKIP
    """
    from .surrogate import cross_validate, fit_quadratic, n_terms

    s = study.s
    for label, c in study.cases.items():
        ok = c.runs.usable()
        if ok.sum() < n_terms(len(s.variables)) + s.folds:
            raise RinglubeError(
                f"case '{label}': only {int(ok.sum())} of {s.samples} samples "
                "ran, converged and did not fail: too few for a quadratic "
                "surface (see the errors in the study file)"
            )
        x = study.x[ok]
        for j, o in enumerate(s.outputs):
            y = c.runs.outputs[ok, j]
            surf = fit_quadratic(x, y, s.lower, s.upper)
            rmse, rel = cross_validate(x, y, s.lower, s.upper, k=s.folds, seed=s.seed)
            c.surfaces[o] = Surface(surf.coef, surf.r2, surf.r2_adj, rmse, rel, len(y))


def surfaces_of(study: Study, label: str, names: list[str] | None = None) -> list:
    """The fitted surfaces of a case as callables.

    Parameters
    ----------
    study : Study
    label : str
        Case label or ``scene``.
    names : list of str, optional
        Results (default: the objectives).

    Returns
    -------
    list of QuadraticSurface

    Example
    -------
    >>> energy, = surfaces_of(study, "cold", ["energy_loss"])   # doctest: +SKIP
    >>> energy(study.x[:3])                                    # doctest: +SKIP
    """
    from .surrogate import QuadraticSurface

    s = study.s
    c = study.cases[label]
    return [
        QuadraticSurface(np.array(s.lower), np.array(s.upper), np.asarray(c.surfaces[o].coef))
        for o in (names or s.objectives)
    ]


def _predict_all(study: Study, label: str, x: np.ndarray) -> np.ndarray:
    return np.column_stack([f(x) for f in surfaces_of(study, label, list(study.s.outputs))])


def ga_repeat(
    coefs: list[np.ndarray],
    lower,
    upper,
    population: int,
    generations: int,
    seed: int,
    constraints: list[tuple[np.ndarray, str, float]] = (),
) -> tuple[np.ndarray, np.ndarray]:
    """One NSGA-II run (pymoo) on quadratic surfaces.

    Parameters
    ----------
    coefs : list of ndarray
        Surface coefficients, one per objective.
    lower, upper : array_like
        The design box.
    population, generations, seed : int
        NSGA-II settings.
    constraints : list of (coef, sense, bound)
        Inequalities on fitted surfaces (``sense`` ``'<='`` or ``'>='``), handed to pymoo
        as ``G <= 0`` (:meth:`~ringlube.study_constraints.Constraint.violation`).

    Returns
    -------
    X, F : ndarray
        Designs and objectives of its final non-dominated set; only designs that satisfy
        every constraint on the surfaces (no rows if none does).

    Example
    -------
    >>> X, F = ga_repeat([np.ones(6)], [0, 0], [1, 1], 8, 2, 1)   # doctest: +SKIP
    """
    require("pymoo", "NSGA-II")
    from pymoo.algorithms.moo.nsga2 import NSGA2
    from pymoo.core.problem import Problem
    from pymoo.optimize import minimize

    from .study_constraints import Constraint
    from .surrogate import QuadraticSurface

    lower, upper = np.asarray(lower, float), np.asarray(upper, float)
    surfs = [QuadraticSurface(lower, upper, np.asarray(c)) for c in coefs]
    cons = [
        (QuadraticSurface(lower, upper, np.asarray(c)), Constraint("", sense, bound), bound)
        for c, sense, bound in constraints
    ]

    def violations(x):
        return np.column_stack([c.violation(f(x), b) for f, c, b in cons])

    class Surrogate(Problem):
        def __init__(self):
            super().__init__(n_var=len(lower), n_obj=len(surfs), n_ieq_constr=len(cons), xl=lower, xu=upper)

        def _evaluate(self, x, out, *args, **kwargs):
            out["F"] = np.column_stack([f(x) for f in surfs])
            if cons:
                out["G"] = violations(x)

    res = minimize(Surrogate(), NSGA2(pop_size=population), ("n_gen", generations), seed=seed, verbose=False)
    if res.X is None:
        return np.zeros((0, len(lower))), np.zeros((0, len(surfs)))
    x, f = np.atleast_2d(res.X), np.atleast_2d(res.F)
    if cons:  # pymoo returns the least infeasible design when none is feasible
        ok = np.all(violations(x) <= 0, axis=1)
        x, f = x[ok], f[ok]
    return x, f


def nondominated(f: np.ndarray) -> np.ndarray:
    """Indices of the non-dominated rows of ``f`` (all objectives minimised).

    Parameters
    ----------
    f : ndarray, shape (n, m)

    Returns
    -------
    ndarray of int

    Example
    -------
    >>> nondominated(np.array([[0.0, 1.0], [1.0, 0.0], [1.0, 1.0]])).tolist()
    [0, 1]
    """
    require("pymoo", "NSGA-II")
    from pymoo.util.nds.non_dominated_sorting import NonDominatedSorting

    return np.sort(NonDominatedSorting().do(f, only_non_dominated_front=True))


def hypervolume(f: np.ndarray, ref: np.ndarray, lo: np.ndarray) -> float:
    """Hypervolume of ``f`` in objectives normalised by ``(ref - lo)``, reference point 1.

    Parameters
    ----------
    f : ndarray, shape (n, m)
    ref, lo : ndarray, shape (m,)
        Reference (worst) point and ideal corner.

    Returns
    -------
    float

    Example
    -------
    >>> hypervolume(np.array([[0.0, 0.0]]), np.ones(2), np.zeros(2))
    1.0
    """
    require("pymoo", "hypervolumes")
    from pymoo.indicators.hv import HV

    if len(f) == 0:
        return 0.0
    return float(HV(ref_point=np.ones(len(ref)))((f - lo) / (ref - lo)))


def constraint_bounds(study: Study, label: str) -> list[tuple]:
    """The constraints of a case with their bounds in the result's unit.

    A bound ``reference`` is the reference design's true-model value on the same case (for
    the scene, its weighted mean), so the reference must have been re-simulated
    (:func:`check_designs` with ``which=("reference",)``).

    Parameters
    ----------
    study : Study
    label : str
        Case label or ``scene``.

    Returns
    -------
    list of (Constraint, int, float)
        Each constraint, its column in the outputs, its bound.

    Raises
    ------
    RinglubeError
        The bound is the reference design's value and its run failed.

    Example
    -------
    >>> constraint_bounds(study, "cold")                     # doctest: +SKIP
    [(Constraint(name='oil_to_chamber', sense='<=', value=None), 5, 0.0123)]
    """
    s = study.s
    out = []
    for k in s.parsed_constraints:
        j = s.outputs.index(k.name)
        bound = k.value
        if k.uses_reference:
            ref = study.cases[label].reference
            bound = float(ref.f_true[0, j]) if ref is not None else float("nan")
            if not np.isfinite(bound):
                raise RinglubeError(
                    f"case '{label}': constraint '{k}': the reference design's run failed "
                    f"({ref.errors[0] if ref is not None else 'not run'}), so it bounds nothing"
                )
        out.append((k, j, float(bound)))
    return out


def feasibility(study: Study, label: str, values: np.ndarray) -> np.ndarray:
    """Which designs satisfy every constraint of a case (by the values given).

    Parameters
    ----------
    study : Study
    label : str
    values : ndarray, shape (k, len(outputs))
        Results of the designs (true model or surfaces); NaN counts as infeasible.

    Returns
    -------
    ndarray of bool, shape (k,)

    Example
    -------
    >>> feasibility(study, "cold", study.cases["cold"].chosen.f_true)   # doctest: +SKIP
    array([ True,  True, False,  True])
    """
    values = np.atleast_2d(values)
    ok = np.ones(len(values), bool)
    for k, j, b in constraint_bounds(study, label):
        with np.errstate(invalid="ignore"):
            ok &= np.isfinite(values[:, j]) & (np.asarray(k.violation(values[:, j], b)) <= 0)
    return ok


def optimise(study: Study, ex: Executor, progress: bool = True) -> None:
    """NSGA-II on each case's surfaces, repeated with distinct seeds, merged.

    Parameters
    ----------
    study : Study
        With surfaces fitted.
    ex : Executor
        Where the repeats run.
    progress : bool
        Show a progress bar.

    Example
    -------
    >>> optimise(study, Executor(serial=True), progress=False)   # doctest: +SKIP
    """
    from tqdm.auto import tqdm

    s = study.s
    tasks, where = [], []
    for label, c in study.cases.items():
        coefs = [np.asarray(c.surfaces[o].coef) for o in s.objectives]
        cons = [
            (np.asarray(c.surfaces[k.name].coef), k.sense, b) for k, _, b in constraint_bounds(study, label)
        ]
        for r in range(s.repeats):
            if r not in c.repeats:
                tasks.append((coefs, s.lower, s.upper, s.population, s.generations, s.seed + 1000 * r, cons))
                where.append((label, r))
    bar = tqdm(total=len(tasks), desc="NSGA-II repeats", disable=not progress or not tasks)

    def on_result(i, xf):
        label, r = where[i]
        study.cases[label].repeats[r] = (xf[0], xf[1])
        bar.update()
        study.save(force=False)

    try:
        ex.map(ga_repeat, tasks, on_result)
    finally:
        bar.close()
        study.save()
    for label, c in study.cases.items():
        reps = [c.repeats[r] for r in range(s.repeats)]
        xs = np.vstack([x for x, _ in reps])
        fs = np.vstack([f for _, f in reps])
        if len(fs) == 0:
            raise RinglubeError(
                f"case '{label}': no design satisfies the constraints "
                f"({'; '.join(s.constraints)}) on the fitted surfaces in {s.repeats} NSGA-II repeats"
            )
        keep = nondominated(fs)
        fx, ff = xs[keep], fs[keep]
        lo, ref = ff.min(0), ff.max(0) + 0.1 * (ff.max(0) - ff.min(0) + 1e-12)
        hv_all = hypervolume(ff, ref, lo)
        hv_reps = np.array([hypervolume(f, ref, lo) for _, f in reps])
        c.front = Front(
            fx, ff, hv_all, hv_reps, float(hv_reps.mean() / hv_all), float(hv_reps.min() / hv_all), ref, lo
        )


def choose_designs(study: Study) -> dict[str, tuple[list[str], np.ndarray]]:
    """The extremes of each objective on the merged front and the knee point.

    Parameters
    ----------
    study : Study
        With fronts.

    Returns
    -------
    dict of str to (names, x)
        Per case: ``['min OBJ', ..., 'knee']`` and the designs (rows).

    Example
    -------
    >>> choose_designs(study)["cold"][0]                       # doctest: +SKIP
    ['min energy_loss', 'min mixed_share', 'min ring_mass', 'knee']
    """
    out = {}
    for label, c in study.cases.items():
        x, f = np.asarray(c.front.x), np.asarray(c.front.f)
        idx = [int(np.argmin(f[:, j])) for j in range(f.shape[1])]
        z = (f - f.min(0)) / np.maximum(f.max(0) - f.min(0), 1e-300)
        knee = int(np.argmin(np.linalg.norm(z, axis=1)))
        names = [f"min {o}" for o in study.s.objectives] + ["knee"]
        out[label] = (names, x[idx + [knee]])
    return out


def check_designs(study: Study, ex: Executor, which: tuple[str, ...] = ("chosen", "reference")) -> None:
    """Re-simulate the chosen designs (and the reference design) with the true model.

    For the scene, each design runs on every base deck and the results are weighted.

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
        for label, (names, xs) in choose_designs(study).items():
            jobs.append((label, "chosen", names, xs))
    if ref is not None and "reference" in which:
        for label in study.cases:
            jobs.append((label, "reference", ["reference"], ref))
    tasks, where = [], []
    for j, (label, _, _, xs) in enumerate(jobs):
        for base_label in [label] if label in bases else s.labels:
            tasks.append((bases[base_label], s.groups_names, xs, list(s.outputs)))
            where.append((j, base_label))
    results: dict[tuple[int, str], tuple] = {}
    ex.map(_run_designs, tasks, lambda i, res: results.__setitem__(where[i], res))
    w = dict(zip(s.labels, np.array(s.weights) / sum(s.weights)))
    for j, (label, key, names, xs) in enumerate(jobs):
        parts = [(bl, results[(j, bl)]) for bl in ([label] if label in bases else s.labels)]
        if len(parts) == 1:
            values, conv, errors = parts[0][1]
        else:
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
                _predict_all(study, label, np.asarray(xs)),
                np.asarray(conv, bool),
                list(errors),
            ),
        )


def _uncertain_inputs(study: Study, label: str) -> list[tuple[str, str, float]]:
    """The :data:`UNCERTAIN` inputs that apply to a case: ``supply_film`` only when every
    base deck of the case has a starved inlet; none that is a design variable."""
    s = study.s
    decks = [d for lb, d in zip(s.labels, s.cases) if lb == label or label not in s.labels]
    bases = [Case.from_namelist(d) for d in decks]
    out = []
    for (group, name), factor in UNCERTAIN.items():
        if (group, name) in s.groups_names:
            continue
        if name == "supply_film" and not all(b.value("physics", "inlet") == "starved" for b in bases):
            continue
        out.append((group, name, factor))
    return out


def _varied(base: Case, group: str, name: str, factor: float) -> Case:
    """``base`` with ``&group name`` multiplied by ``factor`` (calibrated values included)."""
    case = base.inline_calibration()
    return case.with_(group, **{name: float(case.value(group, name)) * factor})


def how_sure(study: Study, ex: Executor) -> None:
    """Extra true-model runs of the chosen designs (and the reference): at the
    ``'accurate'`` preset, and with each :data:`UNCERTAIN` input multiplied and divided by
    its factor, one at a time. Stored as :class:`~ringlube.study_state.Sure` per case.

    Costs (chosen designs + reference) x (1 + 2 x inputs) runs per base deck.

    Parameters
    ----------
    study : Study
        With the chosen designs re-simulated.
    ex : Executor

    Example
    -------
    >>> how_sure(study, Executor(serial=True)); study.cases["cold"].sure.inputs   # doctest: +SKIP
    ['surface:zeta_kappa_sigma', 'operating:pressure_scale']
    """
    s = study.s
    bases = dict(zip(s.labels, _bases(s)))
    w = dict(zip(s.labels, np.array(s.weights) / sum(s.weights)))
    plans = {}  # label -> (names, xs, nominal, inputs)
    tasks, where = [], []
    for label, c in study.cases.items():
        checked = [ch for ch in (c.chosen, c.reference) if ch is not None]
        names = [n for ch in checked for n in ch.names]
        xs = np.vstack([ch.x for ch in checked])
        nominal = np.vstack([ch.f_true for ch in checked])
        inputs = _uncertain_inputs(study, label)
        plans[label] = (names, xs, nominal, inputs)
        variants = [("accurate", None)] + [
            (f"{g}:{n}:{side}", (g, n, f if side == "high" else 1.0 / f))
            for g, n, f in inputs
            for side in ("low", "high")
        ]
        for vname, change in variants:
            for bl in [label] if label in bases else s.labels:
                base = bases[bl]
                case = base.with_("numerics", preset="accurate") if change is None else _varied(base, *change)
                tasks.append((case, s.groups_names, xs, list(s.outputs)))
                where.append((label, vname, bl))
    results: dict[tuple, np.ndarray] = {}
    ex.map(_run_designs, tasks, lambda i, res: results.__setitem__(where[i], res[0]))

    def value(label, vname):
        if label in bases:
            return results[(label, vname, label)]
        return sum(w[bl] * results[(label, vname, bl)] for bl in s.labels)

    presets = {str(b.value("numerics", "preset")) for b in bases.values()}
    for label, (names, xs, nominal, inputs) in plans.items():
        k = len(names)
        shape = (len(inputs), k, len(s.outputs))
        study.cases[label].sure = Sure(
            names,
            xs,
            nominal,
            ", ".join(sorted(presets)),
            value(label, "accurate"),
            [f"{g}:{n}" for g, n, _ in inputs],
            [f for _, _, f in inputs],
            np.array([value(label, f"{g}:{n}:low") for g, n, _ in inputs]).reshape(shape),
            np.array([value(label, f"{g}:{n}:high") for g, n, _ in inputs]).reshape(shape),
        )


def direct(study: Study, ex: Executor, progress: bool = True) -> None:
    """NSGA-II on the true model (no surrogate); compared with the surrogate front.

    A design the kernel rejects gets :data:`FAILED_PENALTY` for every objective; a design
    that failed or did not converge violates the problem's first constraint, so pymoo ranks
    it below every converged design and never returns it in the front; so does, by less, a
    design that lifts the ring off the liner (``liner_lift_share`` > 0: by its share / 200,
    so less lift ranks higher among such designs). The study's
    ``constraints`` follow as further inequalities on the true results (pymoo's ``G <= 0``),
    so the direct front holds only designs that satisfy them. Every evaluated
    generation is checkpointed in the study file (``cases/LABEL/direct_generations``); an
    interrupted run resumes by replaying the same seeded NSGA-II over the stored
    generations, so it re-runs none of them.

    Parameters
    ----------
    study : Study
        With fronts.
    ex : Executor
    progress : bool

    Raises
    ------
    RinglubeError
        No design of the direct NSGA-II converged.

    Example
    -------
    >>> direct(study, Executor(serial=True), progress=False)   # doctest: +SKIP
    """
    require("pymoo", "NSGA-II")
    from pymoo.algorithms.moo.nsga2 import NSGA2
    from pymoo.core.problem import Problem
    from pymoo.indicators.igd import IGD
    from pymoo.optimize import minimize
    from tqdm.auto import tqdm

    s = study.s
    names = direct_outputs(s)
    m = len(s.objectives)
    lift_col = names.index("liner_lift_share")

    class TrueModel(Problem):
        """The kernel itself as the pymoo problem, for one case (its base deck); inequality
        constraints: 0 for a converged run, 1 for a failed or unconverged one; then the
        study's constraints."""

        def __init__(self, label, base, bar):
            self.limits = constraint_bounds(study, label)
            super().__init__(
                n_var=len(s.variables),
                n_obj=len(s.objectives),
                n_ieq_constr=1 + len(self.limits),
                xl=np.array(s.lower),
                xu=np.array(s.upper),
            )
            self.label, self.base, self.bar = label, base, bar
            self.generation = 0

        def _evaluate(self, x, out, *args, **kwargs):
            done = study.cases[self.label].direct_generations
            if self.generation < len(done) and np.array_equal(done[self.generation].x, x):
                gen = done[self.generation]  # run before an interruption: replayed, not re-run
            else:
                del done[self.generation :]
                gen = self._run(x)
                done.append(gen)
                study.save(force=False)
            self.generation += 1
            self.bar.update(len(x))
            out["F"] = np.where(gen.failed[:, None], FAILED_PENALTY, gen.f[:, :m])
            ok = gen.converged & ~gen.failed
            lift = np.nan_to_num(gen.f[:, names.index("liner_lift_share")], nan=0.0).clip(0.0, 100.0)
            g = [np.where(ok, lift / 200.0, 1.0)]
            for k, _, b in self.limits:
                y = gen.f[:, names.index(k.name)]
                g.append(np.where(ok, np.nan_to_num(k.violation(y, b), nan=1.0), 1.0))
            out["G"] = np.column_stack(g)

        def _run(self, x) -> DirectGeneration:
            chunks = np.array_split(np.arange(len(x)), max(1, len(x) // s.batch))
            f = np.empty((len(x), len(names)))
            converged, failed = np.zeros(len(x), bool), np.zeros(len(x), bool)

            def put(i, res):
                values, conv, errors = res
                f[chunks[i]] = values
                converged[chunks[i]] = conv
                failed[chunks[i]] = [bool(e) for e in errors]

            t0 = time.perf_counter()
            ex.map(_run_designs, [(self.base, s.groups_names, x[c], names) for c in chunks], put)
            return DirectGeneration(np.array(x), f, converged, failed, time.perf_counter() - t0)

    for label, base in zip(s.labels, _bases(s)):
        if study.cases[label].direct is not None:
            continue
        bar = tqdm(
            total=s.direct_population * s.direct_generations,
            unit="run",
            desc=f"direct NSGA-II ({label})",
            disable=not progress,
        )
        problem = TrueModel(label, base, bar)
        try:
            res = minimize(
                problem,
                NSGA2(pop_size=s.direct_population),
                ("n_gen", s.direct_generations),
                seed=s.seed,
                verbose=False,
            )
        finally:
            bar.close()
            study.save()
        gens = study.cases[label].direct_generations
        if res.F is None or (s.constraints and np.atleast_2d(res.G).max() > 0):
            raise RinglubeError(
                f"case '{label}': no design of the direct NSGA-II converged without lifting "
                "the ring off the liner"
                + (f" and satisfied the constraints ({'; '.join(s.constraints)})" if s.constraints else "")
            )
        fd = np.atleast_2d(res.F)
        fs = np.asarray(study.cases[label].front.f)
        both = np.vstack([fd, fs])
        lo, ref = both.min(0), both.max(0) + 0.1 * (both.max(0) - both.min(0) + 1e-12)
        scale = ref - lo
        study.cases[label].direct = Direct(
            np.atleast_2d(res.X),
            fd,
            sum(len(g.x) for g in gens),
            sum(g.wall_s for g in gens),
            hypervolume(fd, ref, lo),
            hypervolume(fs, ref, lo),
            float(IGD(fd / scale)(fs / scale)),
            float(IGD(fs / scale)(fd / scale)),
            int(sum(g.failed.sum() for g in gens)),
            int(sum((~g.converged & ~g.failed).sum() for g in gens)),
            int(sum((g.converged & ~g.failed & (g.f[:, lift_col] > 0)).sum() for g in gens)),
        )
        study.save()


def direct_outputs(s: StudySettings) -> list[str]:
    """Results the direct NSGA-II records per design: the objectives, then the constrained
    results that are not objectives.

    Parameters
    ----------
    s : StudySettings

    Returns
    -------
    list of str

    Example
    -------
    >>> direct_outputs(StudySettings("s", [], [], [], [], [], [], ["energy_loss"],
    ...                              constraints=["fmep <= 3", "energy_loss <= 2"]))
    ['energy_loss', 'fmep', 'liner_lift_share']
    """
    return s.direct_outputs()


# --- the whole study -----------------------------------------------------------------


def _out_folder(out: str | os.PathLike | None, s: StudySettings) -> Path:
    out = Path(out) if out is not None else Path("out") / s.name
    if out.exists() and not out.is_dir():
        raise InputError(f"--out {out}: exists and is not a folder")
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise InputError(f"--out {out}: cannot create the folder ({exc.strerror or exc})") from None
    return out


def run_study(
    deck: str | os.PathLike,
    out: str | os.PathLike | None = None,
    *,
    scheduler: str | None = None,
    workers: int | None = None,
    serial: bool = False,
    backend: str | None = None,
    with_direct: bool = False,
    figures: bool = True,
    progress: bool = True,
    stop_after: int | None = None,
    connect_timeout: float | None = None,
) -> Study:
    """The whole pipeline; resumes from the study file in ``out`` if there is one.

    Parameters
    ----------
    deck : path
        The study deck (``&study``).
    out : path, optional
        Output folder (default ``out/NAME``); the study file is ``OUT/NAME.h5``.
    scheduler, workers, serial, backend, connect_timeout
        Where runs go (see :class:`~ringlube.executor.Executor`).
    with_direct : bool
        Also NSGA-II on the true model, compared with the surrogate front.
    figures : bool
        Write the figures (the report and CSV files are always written).
    progress : bool
        Progress bars.
    stop_after : int, optional
        Test hook (see :func:`run_samples`).

    Returns
    -------
    Study

    Raises
    ------
    InputError
        Bad study deck, base deck, output folder or study file.
    RinglubeError
        Another process works on the same study, the scheduler is unreachable, too few
        usable samples.

    Example
    -------
    >>> study = run_study("inputs/study_default.nml", serial=True)   # doctest: +SKIP
    """
    s = read_study(deck)
    out = _out_folder(out, s)
    for name in ["report.md", *(f"pareto_{label}.csv" for label in [*s.labels, "scene"])]:
        check_output(out / name, s.cases)  # before the work, not after it
    path = out / f"{s.name}.h5"
    study = Study.open(s, path, lock=True)
    try:
        _pipeline(
            study,
            scheduler=scheduler,
            workers=workers,
            serial=serial,
            backend=backend,
            with_direct=with_direct,
            progress=progress,
            stop_after=stop_after,
            connect_timeout=connect_timeout,
        )
        from .study_report import write_outputs

        write_outputs(study, out, figures=figures)
    finally:
        study.unlock()
    return study


def _pipeline(
    study: Study, *, scheduler, workers, serial, backend, with_direct, progress, stop_after, connect_timeout
) -> None:
    s = study.s
    if study.x is None:
        study.x = sample(s)
        study.stages.add("sampled")
        study.save()
    require("pymoo", "ringlube optimise")  # before any run, not hours later
    ex = Executor(
        scheduler=scheduler, workers=workers, serial=serial, backend=backend, connect_timeout=connect_timeout
    )
    try:
        run_samples(study, ex, progress=progress, stop_after=stop_after)
        study.stages.add("ran")
        if s.scene and len(s.labels) > 1:
            scene_results(study)
        if "fitted" not in study.stages or any(not c.surfaces for c in study.cases.values()):
            fit_surfaces(study)
            study.stages.add("fitted")
            study.save()
        if _reference_stale(study):  # before the GA: a constraint may be bounded by it
            check_designs(study, ex, which=("reference",))
            for c in study.cases.values():
                c.sure = None
            study.save()
        optimise(study, ex, progress=progress)
        study.stages.add("optimised")
        if "checked" not in study.stages or any(c.chosen is None for c in study.cases.values()):
            check_designs(study, ex, which=("chosen",))
            for c in study.cases.values():
                c.sure = None
            study.stages.add("checked")
            study.save()
        if any(c.sure is None for c in study.cases.values()):
            how_sure(study, ex)
            study.stages.add("sure")
            study.save()
        if with_direct:
            direct(study, ex, progress=progress)
            study.stages.add("direct")
            study.save()
    finally:
        ex.close()


def _reference_stale(study: Study) -> bool:
    """Is a stored reference check missing or for another reference than the deck's now?"""
    ref = study.s.reference
    for c in study.cases.values():
        if ref is not None and c.reference is None:
            return True
        have = None if c.reference is None else np.asarray(c.reference.x)[0].tolist()
        if have != (None if ref is None else list(ref)):
            return True
    return False
