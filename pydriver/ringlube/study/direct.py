"""NSGA-II on the true model (``ringlube optimise --direct``), compared with the surrogate front."""

from __future__ import annotations

import numpy as np

from ..errors import RinglubeError
from ..executor import Executor, require
from .optimise import hypervolume
from .runs import _bases
from .settings import StudySettings
from .state_checks import Direct
from .store import Study

__all__ = ["direct", "direct_outputs"]


def direct(study: Study, ex: Executor, progress: bool = True) -> None:
    """NSGA-II on the true model (no surrogate); compared with the surrogate front.

    The problem is :class:`~ringlube.study.problems.RingProblem`: a design the kernel rejects
    gets :data:`~ringlube.study.problems.FAILED_PENALTY` for every objective; a design that
    failed or did not converge violates the problem's first constraint, so pymoo ranks
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
    from pymoo.indicators.igd import IGD
    from pymoo.optimize import minimize
    from tqdm.auto import tqdm

    from .problems import RingProblem

    s = study.s
    names = direct_outputs(s)
    lift_col = names.index("liner_lift_share")

    for label, base in zip(s.labels, _bases(s)):
        if study.cases[label].direct is not None:
            continue
        bar = tqdm(
            total=s.direct_population * s.direct_generations,
            unit="run",
            desc=f"direct NSGA-II ({label})",
            disable=not progress,
        )
        problem = RingProblem(study, label, base, ex, bar)
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
