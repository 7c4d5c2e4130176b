"""NSGA-II on a study's surfaces: the repeats, their merged Pareto front (non-dominated set,
hypervolumes) and the designs chosen on it (the extremes of each objective and the knee)."""

from __future__ import annotations

import numpy as np

from ..errors import RinglubeError
from ..executor import Executor, require
from .bounds import constraint_bounds
from .state import Front
from .store import Study
from .surrogate import QuadraticSurface

__all__ = ["ga_repeat", "nondominated", "hypervolume", "optimise", "choose_designs", "extremes_and_knee"]


def ga_repeat(
    surfaces: list[QuadraticSurface],
    lower,
    upper,
    population: int,
    generations: int,
    seed: int,
    constraints: list[tuple[QuadraticSurface, str, float]] = (),
) -> tuple[np.ndarray, np.ndarray]:
    """One NSGA-II run (pymoo) on quadratic surfaces.

    Parameters
    ----------
    surfaces : list of QuadraticSurface
        The fitted surfaces, one per objective.
    lower, upper : array_like
        The design box.
    population, generations, seed : int
        NSGA-II settings.
    constraints : list of (surface, sense, bound)
        Inequalities on fitted surfaces (``sense`` ``'<='`` or ``'>='``), handed to pymoo
        as ``G <= 0`` (:meth:`~ringlube.study.constraints.Constraint.violation`).

    Returns
    -------
    X, F : ndarray
        Designs and objectives of its final non-dominated set; only designs that satisfy
        every constraint on the surfaces (no rows if none does).

    Example
    -------
    >>> energy = QuadraticSurface(np.zeros(2), np.ones(2), np.ones(6))
    >>> X, F = ga_repeat([energy], [0, 0], [1, 1], 8, 2, 1)   # doctest: +SKIP
    """
    require("pymoo", "NSGA-II")
    from pymoo.algorithms.moo.nsga2 import NSGA2
    from pymoo.optimize import minimize

    from .problems import SurrogateProblem

    problem = SurrogateProblem(surfaces, lower, upper, constraints)
    res = minimize(problem, NSGA2(pop_size=population), ("n_gen", generations), seed=seed, verbose=False)
    if res.X is None:
        return np.zeros((0, problem.n_var)), np.zeros((0, problem.n_obj))
    x, f = np.atleast_2d(res.X), np.atleast_2d(res.F)
    if problem.constraints:  # pymoo returns the least infeasible design when none is feasible
        ok = np.all(problem.violations(x) <= 0, axis=1)
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
        surfs = [c.surfaces[o] for o in s.objectives]
        cons = [  # the scene's point constraints on that point's surfaces
            (study.cases[b.point].surfaces[b.constraint.name], b.constraint.sense, b.value)
            for b in constraint_bounds(study, label)
        ]
        for r in range(s.repeats):
            if r not in c.repeats:
                tasks.append((surfs, s.lower, s.upper, s.population, s.generations, s.seed + 1000 * r, cons))
                where.append((label, r))
    bar = tqdm(total=len(tasks), desc="NSGA-II repeats", disable=not progress or not tasks)

    def on_result(i, xf):
        label, r = where[i]
        study.cases[label].repeats[r] = (xf[0], xf[1])
        bar.update()
        study.save(force=False)

    try:
        ex.map(ga_repeat, tasks, on_result, on_idle=study.save_pending)
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
        names = [f"min {o}" for o in study.s.objectives] + ["knee"]
        out[label] = (names, np.asarray(c.front.x)[extremes_and_knee(c.front.f)])
    return out


def extremes_and_knee(f: np.ndarray) -> list[int]:
    """Rows of ``f`` (objectives minimised): the least of each column, then the knee, the row
    nearest the ideal point in objectives normalised over ``f``.

    Parameters
    ----------
    f : ndarray, shape (n, m)

    Returns
    -------
    list of int
        m + 1 row indices.

    Example
    -------
    >>> extremes_and_knee(np.array([[0.0, 1.0], [0.4, 0.4], [1.0, 0.0]]))
    [0, 2, 1]
    """
    f = np.asarray(f, dtype=float)
    z = (f - f.min(0)) / np.maximum(f.max(0) - f.min(0), 1e-300)
    return [int(np.argmin(f[:, j])) for j in range(f.shape[1])] + [int(np.argmin(np.linalg.norm(z, axis=1)))]
