"""The study's optimisation problems for pymoo: NSGA-II on the response surfaces
(:class:`SurrogateProblem`) and on the kernel itself (:class:`RingProblem`).

Importing this module imports pymoo (the ``study`` extra); the study's stages import it only
once :func:`~ringlube.executor.require` has said how to install pymoo if it is missing.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np
from pymoo.core.problem import Problem

from ..executor import Executor
from . import runs
from .bounds import constraint_bounds
from .constraints import Constraint
from .state_checks import DirectGeneration

if TYPE_CHECKING:
    from ..case import Case
    from .store import Study

__all__ = ["SurrogateProblem", "RingProblem", "FAILED_PENALTY"]

#: Objective value given to a design the kernel rejects during the direct NSGA-II (the GA
#: needs a finite number; any valid design is far better).
FAILED_PENALTY = 1e10


class SurrogateProblem(Problem):
    """Minimise every surface over the box, subject to constraints on surfaces.

    Parameters
    ----------
    surfaces : sequence of callable
        The objectives: each maps designs (k, n) to values (k,) (a
        :class:`~ringlube.study.surrogate.QuadraticSurface`).
    lower, upper : array_like
        The box of the n design variables.
    constraints : sequence of (callable, str, float)
        ``(surface, sense, bound)``: ``surface(x) <= bound`` for sense ``'<='``, ``>=`` for
        ``'>='``.

    Example
    -------
    >>> import numpy as np
    >>> p = SurrogateProblem([lambda x: x.sum(1)], [0, 0], [1, 1], [(lambda x: x[:, 0], ">=", 0.5)])
    >>> p.n_var, p.n_obj, p.n_ieq_constr
    (2, 1, 1)
    >>> p.violations(np.array([[0.25, 0.0], [0.75, 0.0]])).ravel().tolist()
    [0.5, -0.5]
    """

    def __init__(
        self,
        surfaces: Sequence[Callable[[np.ndarray], np.ndarray]],
        lower,
        upper,
        constraints: Sequence[tuple[Callable[[np.ndarray], np.ndarray], str, float]] = (),
    ):
        lower, upper = np.asarray(lower, float), np.asarray(upper, float)
        self.surfaces = list(surfaces)
        self.constraints = [(f, Constraint("", sense, bound), bound) for f, sense, bound in constraints]
        super().__init__(
            n_var=len(lower), n_obj=len(self.surfaces), n_ieq_constr=len(self.constraints), xl=lower, xu=upper
        )

    def violations(self, x: np.ndarray) -> np.ndarray:
        """pymoo's ``G``: each design (row of ``x``) against each constraint, relative to the
        bound (:meth:`~ringlube.study.constraints.Constraint.violation`; <= 0 inside).

        Parameters
        ----------
        x : ndarray, shape (k, n)

        Returns
        -------
        ndarray, shape (k, number of constraints)

        Example
        -------
        >>> p = SurrogateProblem([lambda x: x[:, 0]], [0], [1], [(lambda x: x[:, 0], "<=", 0.5)])
        >>> p.violations(np.array([[1.0], [0.25]])).tolist()
        [[1.0], [-0.5]]
        """
        return np.column_stack([c.violation(f(x), b) for f, c, b in self.constraints])

    def _evaluate(self, x, out, *args, **kwargs):
        out["F"] = np.column_stack([f(x) for f in self.surfaces])
        if self.constraints:
            out["G"] = self.violations(x)


class RingProblem(Problem):
    """The kernel itself as the problem, for one case of a study (its base deck): each
    generation's designs run as batches through an executor and are recorded in the study
    (:class:`~ringlube.study.state_checks.DirectGeneration`), so an interrupted run replays
    the generations it ran instead of re-running them.

    Objectives: the study's (:data:`FAILED_PENALTY` for a design the kernel rejects).
    Inequality constraints: first 0 for a converged run that keeps the ring on the liner
    (the share of the cycle lifted / 200 otherwise), 1 for a failed or unconverged run; then
    the study's constraints of the case.

    Parameters
    ----------
    study : Study
    label : str
        The case.
    base : Case
        Its base deck.
    executor : Executor
        Where the runs go.
    bar : tqdm progress bar, optional
        Advanced by each generation's designs.

    Example
    -------
    >>> problem = RingProblem(study, "cold", base, Executor(serial=True))   # doctest: +SKIP
    >>> minimize(problem, NSGA2(pop_size=16), ("n_gen", 4))                 # doctest: +SKIP
    """

    def __init__(self, study: Study, label: str, base: Case, executor: Executor, bar: Any = None):
        s = study.s
        self.study, self.label, self.base, self.executor, self.bar = study, label, base, executor, bar
        self.names = s.direct_outputs()
        self.limits = constraint_bounds(study, label)
        self.generation = 0
        super().__init__(
            n_var=len(s.variables),
            n_obj=len(s.objectives),
            n_ieq_constr=1 + len(self.limits),
            xl=np.array(s.lower),
            xu=np.array(s.upper),
        )

    def _evaluate(self, x, out, *args, **kwargs):
        done = self.study.cases[self.label].direct_generations
        if self.generation < len(done) and np.array_equal(done[self.generation].x, x):
            gen = done[self.generation]  # run before an interruption: replayed, not re-run
        else:
            del done[self.generation :]
            gen = self.run(x)
            done.append(gen)
            self.study.save(force=False)
        self.generation += 1
        if self.bar is not None:
            self.bar.update(len(x))
        names, m = self.names, len(self.study.s.objectives)
        out["F"] = np.where(gen.failed[:, None], FAILED_PENALTY, gen.f[:, :m])
        ok = gen.converged & ~gen.failed
        lift = np.nan_to_num(gen.f[:, names.index("liner_lift_share")], nan=0.0).clip(0.0, 100.0)
        g = [np.where(ok, lift / 200.0, 1.0)]
        for b in self.limits:  # (a case's own: the direct NSGA-II runs no scene)
            y = gen.f[:, names.index(b.constraint.name)]
            g.append(np.where(ok, np.nan_to_num(b.constraint.violation(y, b.value), nan=1.0), 1.0))
        out["G"] = np.column_stack(g)

    def run(self, x: np.ndarray) -> DirectGeneration:
        """Run one generation's designs with the true model (in batches of the study's size).

        Parameters
        ----------
        x : ndarray, shape (k, number of variables)

        Returns
        -------
        DirectGeneration

        Example
        -------
        >>> RingProblem(study, "cold", base, Executor(serial=True)).run(x).converged   # doctest: +SKIP
        array([ True,  True])
        """
        s = self.study.s
        chunks = np.array_split(np.arange(len(x)), max(1, len(x) // s.batch))
        f = np.empty((len(x), len(self.names)))
        converged, failed = np.zeros(len(x), bool), np.zeros(len(x), bool)

        def put(i, res):
            values, conv, errors = res
            f[chunks[i]] = values
            converged[chunks[i]] = conv
            failed[chunks[i]] = [bool(e) for e in errors]

        t0 = time.perf_counter()
        kernel = runs.study_kernel()
        tasks = [(self.base, s.groups_names, x[c], self.names, kernel) for c in chunks]
        self.executor.map(runs._run_designs, tasks, put)
        return DirectGeneration(np.array(x), f, converged, failed, time.perf_counter() - t0)
