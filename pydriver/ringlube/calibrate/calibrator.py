"""The one calibrator of ``ringlube calibrate`` and ``ringlube readings``.

:func:`calibrate_inputs` fits bounded uncertain inputs (each a :class:`Param`: bounds and
scale) to targets and returns a :class:`scipy.optimize.OptimizeResult`:

* ``x``: the fitted inputs (physical values), ``u``: the same normalised to [0, 1];
* ``fun``: the residual vector at ``x``, ``score``: its root-sum-square;
* ``nfev``: points evaluated, ``nit``: optimiser iterations;
* ``status`` (int), ``message`` (str), ``success`` (bool): how the optimiser stopped;
* ``active_mask``: per input, -1 / 1 where it ends on its lower / upper bound, else 0;
* ``grad`` (method 'least_squares'): d(score^2 / 2)/du at ``u``.

Two methods, each the one its command has always used (a refactor: no number changed):

``'least_squares'`` (``ringlube readings``)
    A coarse start design of the normalised box, then :func:`scipy.optimize.least_squares`
    (trust-region reflective, bounded) from its best point, with a forward-difference
    Jacobian whose steps are evaluated as one batch; every point evaluated is kept and the
    best one is the fit; the evaluation budget stops it.
``'bracket'`` (``ringlube calibrate``)
    Two inputs, two residuals, each residual increasing in its input: for a value of the
    second input, the first is solved by Brent's method for the first residual (ending on a
    bound when the root lies outside); the second input is then found by bisection on the
    second residual, keeping the point closest to its target.
``'brent'`` (``ringlube calibrate`` with one target)
    One input, one residual increasing in it: Brent's method, ending on a bound when the
    root lies outside (the inner solve of 'bracket').
"""

from __future__ import annotations

import dataclasses
import itertools
import math

import numpy as np
from scipy.optimize import OptimizeResult

__all__ = ["Param", "start_design", "calibrate_inputs", "METHODS"]

#: The methods of :func:`calibrate_inputs`.
METHODS = ("least_squares", "bracket", "brent")


@dataclasses.dataclass(frozen=True)
class Param:
    """A fitted input: its kernel key ('group:name'), bounds and scale.

    Parameters
    ----------
    name : str
        Variable name.
    key : str
        'group:name' for :func:`ringlube.run_designs`.
    lo, hi : float
        Bounds.
    log : bool
        Normalise on a log scale.

    Examples
    --------
    >>> p = Param("supply_film", "lubricant:supply_film", 1e-7, 1e-5, log=True)
    >>> round(p.physical(0.5) * 1e6, 6), p.normalised(1e-5)
    (1.0, 1.0)
    """

    name: str
    key: str
    lo: float
    hi: float
    log: bool = False

    def physical(self, u: float) -> float:
        """The value at normalised position ``u`` in [0, 1]."""
        if self.log:
            return float(math.exp(math.log(self.lo) + u * (math.log(self.hi) - math.log(self.lo))))
        return float(self.lo + u * (self.hi - self.lo))

    def normalised(self, x: float) -> float:
        """The normalised position of value ``x``."""
        if self.log:
            return (math.log(x) - math.log(self.lo)) / (math.log(self.hi) - math.log(self.lo))
        return (x - self.lo) / (self.hi - self.lo)


def start_design(d: int) -> np.ndarray:
    """The coarse start design in the unit box: a 3 x 3 grid of cell centres (d = 2), else the
    2^d corners of the inner half-box plus its centre.

    Parameters
    ----------
    d : int
        Number of inputs.

    Returns
    -------
    ndarray, shape (k, d)

    Examples
    --------
    >>> start_design(2).shape, start_design(3).shape
    ((9, 2), (9, 3))
    """
    if d <= 2:
        return np.array(list(itertools.product([1 / 6, 0.5, 5 / 6], repeat=d)))
    return np.array(list(itertools.product([0.25, 0.75], repeat=d)) + [[0.5] * d])


def calibrate_inputs(
    fun, params: list[Param] | None = None, method: str = "least_squares", **options
) -> OptimizeResult:
    """Fit bounded inputs to targets: the one calibrator of ``calibrate`` and ``readings``.

    Parameters
    ----------
    fun : callable
        'least_squares': ``fun(U)`` with ``U`` of shape (k, d) in [0, 1]^d (normalised inputs)
        returns the residual vectors, shape (k, m), finite. 'bracket': ``fun(x)`` with the two
        physical inputs returns the two residuals (each increasing in its input; a root of the
        first is solved for on the first input, of the second on the second).
    params : list of Param, optional
        The inputs with their bounds (default: ``d`` inputs on [0, 1], ``d`` from the start
        design).
    method : {'least_squares', 'bracket'}
    **options
        'least_squares': ``start`` (start design, shape (k, d), evaluated first in one
        batch), ``budget`` (most points evaluated; the start design and the final gradient's
        ``d`` points come on top when it is smaller), ``step`` (forward-difference step,
        pointing inside the box, default 0.02), ``tol`` (``xtol`` in the normalised inputs,
        default 1e-3). 'bracket': ``xtol``, ``rtol`` (of Brent's method, default 1e-5, 1e-6),
        ``bisections`` (default 12), ``nominal`` (of the second input: of two points equally
        close to the second target, the one closer to it wins; default: mid-range). 'brent':
        ``xtol``, ``rtol``.

    Returns
    -------
    scipy.optimize.OptimizeResult
        See the module description.

    Raises
    ------
    ValueError
        For an unknown method.

    Examples
    --------
    >>> f = lambda U: np.c_[U[:, 0] - 0.3, 2 * (U[:, 1] - 0.7)]
    >>> r = calibrate_inputs(f, start=start_design(2), budget=40)
    >>> np.round(r.x, 3).tolist(), r.score < 1e-6, r.success
    ([0.3, 0.7], True, True)
    >>> g = lambda x: (x[0] + x[1] - 1.0, x[1] - 0.25)
    >>> r = calibrate_inputs(g, [Param("a", "", 0, 1), Param("b", "", 0, 1)], "bracket")
    >>> np.round(r.x, 3).tolist(), r.nfev, r.active_mask.tolist()
    ([0.75, 0.25], 82, [0, 0])
    >>> r = calibrate_inputs(lambda x: (x[0] ** 2 - 0.25,), [Param("a", "", 0, 1)], "brent")
    >>> round(float(r.x[0]), 6), r.within_bounds
    (0.5, True)
    """
    if method == "least_squares":
        return _least_squares(fun, params, **options)
    if method == "bracket":
        return _bracket(fun, params, **options)
    if method == "brent":
        return _brent(fun, params, **options)
    raise ValueError(f"unknown calibration method '{method}' (one of {', '.join(METHODS)})")


def _unit_params(d: int) -> list[Param]:
    """``d`` inputs on [0, 1] (the physical value is the normalised one)."""
    return [Param(f"u{i}", "", 0.0, 1.0) for i in range(d)]


def _finish(x, u, fun, **fields) -> OptimizeResult:
    """The result with the fields every method fills."""
    u = np.asarray(u, float)
    fun = np.asarray(fun, float)
    active = np.where(u <= 0.0, -1, np.where(u >= 1.0, 1, 0))
    return OptimizeResult(
        x=np.asarray(x, float),
        u=u,
        fun=fun,
        score=float(np.sqrt(np.sum(fun**2))),
        active_mask=active,
        **fields,
    )


def _bracket(
    fun, params, xtol: float = 1e-5, rtol: float = 1e-6, bisections: int = 12, nominal: float | None = None
) -> OptimizeResult:
    """The nested fit of two inputs ('bracket')."""
    from scipy.optimize import brentq

    params = params or _unit_params(2)
    if len(params) != 2:
        raise ValueError(f"method 'bracket' fits two inputs, not {len(params)}")
    nfev = 0

    def f(x0: float, x1: float):
        nonlocal nfev
        nfev += 1
        return fun((x0, x1))

    lo0, hi0 = params[0].lo, params[0].hi

    def first_for(x1: float) -> tuple[float, object]:
        g = lambda z: f(z, x1)[0]  # noqa: E731
        glo, ghi = g(lo0), g(hi0)
        if glo > 0:
            return lo0, f(lo0, x1)
        if ghi < 0:
            return hi0, f(hi0, x1)
        z = brentq(g, lo0, hi0, xtol=xtol, rtol=rtol)
        return z, f(z, x1)

    lo1, hi1 = params[1].lo, params[1].hi
    mid = 0.5 * (lo1 + hi1) if nominal is None else nominal
    z_lo, r_lo = first_for(lo1)
    z_hi, r_hi = first_for(hi1)
    nit = 0
    if r_lo[1] >= 0:
        z, r, s = z_lo, r_lo, lo1
        message = "the second residual is not negative at the lower bound of the second input"
    elif r_hi[1] <= 0:
        z, r, s = z_hi, r_hi, hi1
        message = "the second residual is not positive at the upper bound of the second input"
    else:
        # bisection on the second residual; keep the bracket point closest to its target
        a, b = lo1, hi1
        best = min(((abs(r_lo[1]), lo1, z_lo, r_lo), (abs(r_hi[1]), hi1, z_hi, r_hi)), key=lambda t: t[0])
        for _ in range(bisections):
            nit += 1
            m = 0.5 * (a + b)
            zm, rm = first_for(m)
            cand = (abs(rm[1]), m, zm, rm)
            if cand[0] < best[0] or (cand[0] == best[0] and abs(m - mid) < abs(best[1] - mid)):
                best = cand
            if rm[1] < 0:
                a = m
            else:
                b = m
        _, s, z, r = best
        message = f"{bisections} bisections of the second input"
    z, s = float(z), float(s)
    within = (lo0 < z < hi0) and (lo1 < s < hi1)
    return _finish(
        [z, s],
        [params[0].normalised(z), params[1].normalised(s)],
        r,
        nfev=nfev,
        nit=nit,
        status=1 if within else 2,
        message=message + ("" if within else "; the fit ends on a bound"),
        success=True,
        within_bounds=within,
    )


def _brent(fun, params, xtol: float = 1e-5, rtol: float = 1e-6) -> OptimizeResult:
    """One input for one residual increasing in it ('brent')."""
    from scipy.optimize import brentq

    params = params or _unit_params(1)
    if len(params) != 1:
        raise ValueError(f"method 'brent' fits one input, not {len(params)}")
    nfev = 0

    def f(x: float):
        nonlocal nfev
        nfev += 1
        return fun((x,))

    lo, hi = params[0].lo, params[0].hi
    if f(lo)[0] > 0:
        x, message = lo, "the residual is positive at the lower bound"
    elif f(hi)[0] < 0:
        x, message = hi, "the residual is negative at the upper bound"
    else:
        x = float(brentq(lambda z: f(z)[0], lo, hi, xtol=xtol, rtol=rtol))
        message = "Brent's method"
    r = f(x)
    within = lo < x < hi
    return _finish(
        [x],
        [params[0].normalised(x)],
        r,
        nfev=nfev,
        nit=nfev,
        status=1 if within else 2,
        message=message + ("" if within else "; the fit ends on a bound"),
        success=True,
        within_bounds=within,
    )


class _Budget(Exception):
    """The evaluation budget is spent."""


def _least_squares(
    batch, params, start=None, budget: int = 60, step: float = 0.02, tol: float = 1e-3
) -> OptimizeResult:
    """Bounded least squares in the unit box from the best point of a start design
    ('least_squares')."""
    from scipy.optimize import least_squares

    start = start_design(len(params)) if start is None else start
    start = np.atleast_2d(np.asarray(start, float))
    d = start.shape[1]
    params = params or _unit_params(d)
    cache: dict[tuple, np.ndarray] = {}
    count = [0]

    def key(u) -> tuple:
        return tuple(np.round(np.asarray(u, float), 12))

    def run(U, limit: bool = True) -> np.ndarray:
        U = np.clip(np.atleast_2d(np.asarray(U, float)), 0.0, 1.0)
        todo = []
        for u in U:
            if key(u) not in cache and key(u) not in {key(t) for t in todo}:
                todo.append(u)
        if todo:
            if limit and count[0] + len(todo) > max(budget, len(start)):
                raise _Budget
            R = np.asarray(batch(np.array(todo)), float)
            count[0] += len(todo)
            for u, r in zip(todo, R):
                cache[key(u)] = r
        return np.array([cache[key(u)] for u in U])

    def fun(u):
        return run(u)[0]

    def jac(u, limit: bool = True):
        u = np.clip(np.asarray(u, float), 0.0, 1.0)
        h = np.where(u + step <= 1.0, step, -step)
        R = run(np.vstack([u] + [u + h[i] * np.eye(d)[i] for i in range(d)]), limit)
        return ((R[1:] - R[0]) / h[:, None]).T

    run(start, limit=False)
    best = min(cache, key=lambda k: float(np.sum(cache[k] ** 2)))
    status, message, nit = 0, "start design only", 0
    if budget > len(start):
        try:
            sol = least_squares(
                fun,
                np.clip(np.array(best), 1e-9, 1 - 1e-9),
                jac=jac,
                bounds=(0.0, 1.0),
                method="trf",
                xtol=tol,
                ftol=1e-6,
                gtol=1e-8,
                max_nfev=budget,
            )
            status, message, nit = sol.status, sol.message, sol.njev
        except _Budget:
            message = f"evaluation budget ({budget}) spent"
    best = min(cache, key=lambda k: float(np.sum(cache[k] ** 2)))
    u = np.array(best)
    J = jac(u, limit=False)
    r = cache[best]
    return _finish(
        [p.physical(float(v)) for p, v in zip(params, u)],
        u,
        r,
        nfev=count[0],
        nit=nit,
        status=status,
        message=message,
        success=status > 0,
        grad=J.T @ r,
        jac=J,
    )
