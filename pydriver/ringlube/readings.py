"""Calibration of every reading of the open modelling choices (issue 9).

A reading is a film model (SPEC 13) crossed with the contact area and the tension unit. For
each, the uncertain inputs are fitted to the **cold** case only, with the published trend
directions at cold as targets beside the two Table 2 numbers; the hot case stays a prediction.

Fitted inputs: ``&surface zeta_kappa_sigma`` and ``&operating pressure_scale`` on their
calibration bounds (:data:`ringlube.calibrate.BOUNDS`), and ``&lubricant supply_film`` on
:data:`SUPPLY_BOUNDS` (logarithmic) for the starved readings.

Score. One residual vector per point, every entry in units of the goal of issue 9:

* the cold energy's relative error over 5 % (:data:`GOAL`),
* the cold mixed share's error over 1.5 points,
* for each published trend, its continuous measure (:func:`trend_measures`, a fraction of the
  energy by which the sweep goes the wrong way) over the same 5 %: a sweep 5 % of the energy
  the wrong way weighs as much as a 5 % energy error.

The score is the root-sum-square of that vector; the discrete yes/no verdicts
(:func:`ringlube.validate.trend_verdicts`) are reported beside it but not optimised (they are
not smooth). Each point costs one base run and the trend sweeps of :data:`SWEEP_POINTS`.

Optimiser (:func:`minimise`): a 9-point coarse design of the (normalised) input box, then
``scipy.optimize.least_squares`` (trust-region reflective, bounded) from its best point, with a
forward-difference Jacobian whose steps are run as one batch; every point evaluated is kept
and the best one is the fit. Each reading is one task; readings run in parallel worker
processes, and each point's runs go to the kernel as one ``run_designs`` batch.

    ringlube readings [--out docs/readings.md] [--readings ID ...] [--evals 60] [--quick]
"""

from __future__ import annotations

import dataclasses
import fnmatch
import math
import os
import time
from pathlib import Path

import numpy as np

from .calibrate import BOUNDS, cold_targets
from .case import Case
from .errors import InputError
from .outputs import check_output, write_text
from .validate import READINGS, TRENDS, trend_verdicts

__all__ = [
    "SUPPLY_BOUNDS",
    "RELAXED_BOUNDS",
    "GOAL",
    "SWEEP_POINTS",
    "Reading",
    "Param",
    "all_readings",
    "select_readings",
    "trend_measures",
    "residuals",
    "minimise",
    "fit_reading",
    "calibrate_readings",
    "write_readings",
]

#: Bounds of the supply film fitted for starved readings [m] (fitted on a log scale).
SUPPLY_BOUNDS = (0.1e-6, 10e-6)
#: Wider bounds, outside the physical range, used only to show whether a bound stops a better
#: fit (never a shipped reading).
RELAXED_BOUNDS = {
    "zeta_kappa_sigma": (0.01, 0.3),
    "pressure_scale": (0.6, 1.6),
    "supply_film": (0.02e-6, 50e-6),
}
#: The goal of issue 9: cold energy within 5 % (relative) and mixed share within 1.5 points.
GOAL = {"energy_loss": 0.05, "mixed_share": 1.5}
#: Points of each cold trend sweep (the offset verdict compares the two ends only).
SWEEP_POINTS = {"tension": 5, "crown_height": 5, "crown_offset": 2, "width": 5}
#: The ring variables swept (order of :data:`ringlube.validate.TRENDS`).
RING = tuple(name for name, _, _ in TRENDS)
#: A trend measure where a sweep point failed (the whole energy the wrong way).
FAILED_MEASURE = 1.0
#: Residual entries of a point whose base run failed.
FAILED_RESIDUAL = 100.0
#: A normalised input closer than this to 0 or 1 counts as on its bound.
AT_BOUND = 0.005
#: Default budget: points per reading the optimiser may evaluate (start design included).
EVALS = 60
#: Forward-difference step of the Jacobian (normalised inputs).
STEP = 0.02
#: The scalar results read from each run.
_OUTPUTS = ["energy_loss", "mixed_share"]


# --- readings and fitted inputs -------------------------------------------------------------


@dataclasses.dataclass(frozen=True)
class Reading:
    """One reading: film model (a key of :data:`ringlube.validate.READINGS`), contact area
    ('lumped' / 'local') and tension unit ('N/m' / 'N').

    Parameters
    ----------
    film, area, unit : str

    Examples
    --------
    >>> Reading("JFO starved", "lumped", "N/m").id
    'jfo-starved/lumped/N/m'
    """

    film: str
    area: str
    unit: str

    @property
    def physics(self) -> dict:
        """The ``&physics`` options of the film model."""
        return READINGS[self.film]

    @property
    def starved(self) -> bool:
        """Whether the inlet is starved (``supply_film`` is fitted)."""
        return self.physics.get("inlet") == "starved"

    @property
    def id(self) -> str:
        """Short name: film slug / contact area / tension unit."""
        ph = self.physics
        if not ph:
            slug = "swift-stieber"
        else:
            parts = [ph.get("cavitation", ""), ph.get("inlet", ""), ph.get("cavity_pressure", "")]
            slug = "-".join(p.replace("_", "-") for p in parts if p and p != "flooded")
        return f"{slug}/{self.area}/{self.unit}"

    def apply(self, case: Case) -> Case:
        """The case with this reading's options."""
        return case.with_physics(**self.physics, contact_area=self.area).with_ring(tension_unit=self.unit)


def all_readings() -> list[Reading]:
    """Every reading: film models x contact area x tension unit (20).

    Examples
    --------
    >>> len(all_readings())
    20
    """
    return [Reading(f, a, u) for f in READINGS for a in ("lumped", "local") for u in ("N/m", "N")]


def select_readings(patterns: list[str] | None) -> list[Reading]:
    """The readings whose id matches one of ``patterns`` (shell wildcards allowed).

    Parameters
    ----------
    patterns : list of str or None
        None: every reading.

    Returns
    -------
    list of Reading

    Raises
    ------
    InputError
        If a pattern matches no reading (the message lists the ids).

    Examples
    --------
    >>> [r.id for r in select_readings(["jfo-starved/lumped/*"])]
    ['jfo-starved/lumped/N/m', 'jfo-starved/lumped/N']
    """
    every = all_readings()
    if not patterns:
        return every
    chosen = []
    for pat in patterns:
        hit = [r for r in every if fnmatch.fnmatchcase(r.id, pat)]
        if not hit:
            raise InputError(
                f"--readings: '{pat}' matches no reading (ids: {', '.join(r.id for r in every)})"
            )
        chosen += [r for r in hit if r not in chosen]
    return chosen


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


def _params(reading: Reading, bounds: dict | None = None) -> list[Param]:
    b = {**BOUNDS, "supply_film": SUPPLY_BOUNDS, **(bounds or {})}
    ps = [
        Param("zeta_kappa_sigma", "surface:zeta_kappa_sigma", *b["zeta_kappa_sigma"]),
        Param("pressure_scale", "operating:pressure_scale", *b["pressure_scale"]),
    ]
    if reading.starved:
        ps.append(Param("supply_film", "lubricant:supply_film", *b["supply_film"], log=True))
    return ps


# --- the score ------------------------------------------------------------------------------


def trend_measures(sweeps: dict) -> dict[str, float]:
    """A continuous measure of each published trend: 0 where the trend appears, else the
    fraction of the sweep's mean energy by which it goes the wrong way.

    * tension (energy rises): the sum of the falls between neighbouring points;
    * crown_height (energy falls): the sum of the rises;
    * crown_offset (negative better): how much the most negative end exceeds the most positive;
    * width (interior optimum): how much the lowest interior point exceeds the lower end.

    Each is zero exactly when :func:`ringlube.validate.trend_verdicts` says yes, except on
    exact ties (equal energies), where the verdict, a strict comparison, says no and the
    measure is zero; a sweep with a failed point (NaN) measures :data:`FAILED_MEASURE`.

    Parameters
    ----------
    sweeps : dict of str to (ndarray, ndarray)
        For each trend variable, its values and the energy losses.

    Returns
    -------
    dict of str to float

    Examples
    --------
    >>> x = np.linspace(0, 1, 5)
    >>> m = trend_measures({"tension": (x, [1, 2, 3, 2.5, 4.0]), "crown_height": (x, [4, 3, 2, 1, 0.5]),
    ...                     "crown_offset": (x[[0, -1]], [1.0, 2.0]), "width": (x, [2, 1, 2, 3, 4.0])})
    >>> {k: round(v, 4) for k, v in m.items()}
    {'tension': 0.2, 'crown_height': 0.0, 'crown_offset': 0.0, 'width': 0.0}
    """
    out = {}
    for name, (_, e) in sweeps.items():
        e = np.asarray(e, float)
        if not np.all(np.isfinite(e)) or len(e) < 2:
            out[name] = FAILED_MEASURE
            continue
        d = np.diff(e)
        if name == "tension":
            wrong = np.sum(np.maximum(0.0, -d))
        elif name == "crown_height":
            wrong = np.sum(np.maximum(0.0, d))
        elif name == "crown_offset":
            wrong = max(0.0, e[0] - e[-1])
        elif name == "width":
            wrong = max(0.0, np.min(e[1:-1]) - min(e[0], e[-1])) if len(e) > 2 else abs(d[0])
        else:
            raise KeyError(f"no published trend '{name}'")
        out[name] = float(wrong / np.mean(np.abs(e)))
    return out


def _verdicts(sweeps: dict) -> dict[str, bool]:
    """The discrete verdicts; a sweep with a failed point says no."""
    v = trend_verdicts(sweeps)
    return {k: bool(v[k] and np.all(np.isfinite(sweeps[k][1]))) for k in v}


def residuals(energy: float, mixed: float, measures: dict[str, float], targets: dict) -> np.ndarray:
    """The residual vector of one point, in units of the goal (:data:`GOAL`).

    Parameters
    ----------
    energy, mixed : float
        Cold energy loss [J] and mixed share [%] (NaN: a failed run).
    measures : dict of str to float
        :func:`trend_measures` of the cold sweeps.
    targets : dict
        'energy_loss' and 'mixed_share' targets.

    Returns
    -------
    ndarray, shape (2 + len(measures),)
        Energy error over 5 %, mixed-share error over 1.5 points, each measure over 5 %.

    Examples
    --------
    >>> residuals(2.016, 9.97, {"width": 0.025}, {"energy_loss": 1.92, "mixed_share": 8.47})
    array([1. , 1. , 0.5])
    """
    if not (math.isfinite(energy) and math.isfinite(mixed)):
        return np.full(2 + len(measures), FAILED_RESIDUAL)
    r = [
        (energy / targets["energy_loss"] - 1.0) / GOAL["energy_loss"],
        (mixed - targets["mixed_share"]) / GOAL["mixed_share"],
    ]
    return np.array(r + [m / GOAL["energy_loss"] for m in measures.values()])


# --- the optimiser --------------------------------------------------------------------------


class _Budget(Exception):
    """The evaluation budget is spent."""


@dataclasses.dataclass
class Minimum:
    """What :func:`minimise` found.

    Parameters
    ----------
    u : ndarray
        Best normalised point.
    residuals : ndarray
        Its residual vector.
    evaluations : int
        Points evaluated (start design, optimiser, Jacobians, the gradient at the end).
    gradient : ndarray
        d(score^2 / 2)/du at ``u`` (one-sided forward differences pointing inside the box).
    status : str
        How the optimiser stopped.

    Examples
    --------
    >>> Minimum(np.zeros(1), np.array([3.0, 4.0]), 1, np.zeros(1), "").score
    5.0
    """

    u: np.ndarray
    residuals: np.ndarray
    evaluations: int
    gradient: np.ndarray
    status: str

    @property
    def score(self) -> float:
        """Root-sum-square of the residuals."""
        return float(np.sqrt(np.sum(self.residuals**2)))


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
    import itertools

    if d <= 2:
        return np.array(list(itertools.product([1 / 6, 0.5, 5 / 6], repeat=d)))
    return np.array(list(itertools.product([0.25, 0.75], repeat=d)) + [[0.5] * d])


def minimise(batch, start: np.ndarray, budget: int, step: float = STEP, tol: float = 1e-3) -> Minimum:
    """Bounded least squares in the unit box from the best point of a start design.

    Parameters
    ----------
    batch : callable
        ``batch(U)`` with ``U`` of shape (k, d) in [0, 1]^d returns the residual vectors,
        shape (k, m), finite.
    start : ndarray, shape (k, d)
        Start design (evaluated first, in one batch).
    budget : int
        Most points evaluated before the optimiser stops (the start design and the final
        gradient's ``d`` points come on top of it when it is smaller).
    step : float
        Forward-difference step of the Jacobian (pointing inside the box).
    tol : float
        ``xtol`` of :func:`scipy.optimize.least_squares` (in the normalised inputs).

    Returns
    -------
    Minimum
        The best point evaluated.

    Examples
    --------
    >>> f = lambda U: np.c_[U[:, 0] - 0.3, 2 * (U[:, 1] - 0.7)]
    >>> m = minimise(f, start_design(2), budget=40)
    >>> np.round(m.u, 3).tolist(), m.score < 1e-6
    ([0.3, 0.7], True)
    """
    from scipy.optimize import least_squares

    start = np.atleast_2d(np.asarray(start, float))
    d = start.shape[1]
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
    status = "start design only"
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
            status = sol.message
        except _Budget:
            status = f"evaluation budget ({budget}) spent"
    best = min(cache, key=lambda k: float(np.sum(cache[k] ** 2)))
    u = np.array(best)
    J = jac(u, limit=False)
    r = cache[best]
    return Minimum(u, r, count[0], J.T @ r, status)


# --- one reading ----------------------------------------------------------------------------


def _run_batch(case: Case, variables: list[str], x: np.ndarray):
    """(values (n, 2): energy, mixed; converged (n,)) of designs ``x`` (the one kernel call)."""
    from .solve import run_designs

    values, converged, _ = run_designs(case, variables, x, _OUTPUTS)
    return values, converged


@dataclasses.dataclass
class Point:
    """One evaluated point of a reading: its inputs, the base run and the trend sweeps.

    Parameters
    ----------
    inputs : dict of str to float
        Fitted inputs (physical values).
    energy, mixed : float
        Energy loss [J] and mixed share [%] of the base ring (NaN: failed).
    converged : bool
        Whether the base run converged.
    sweeps : dict of str to (ndarray, ndarray)
        Trend sweeps.
    failed : int
        Failed runs among the point's runs.
    runs : int
        Runs of the point.

    Examples
    --------
    >>> Point({}, 1.9, 8.5, True, {}, 0, 1).measures
    {}
    """

    inputs: dict
    energy: float
    mixed: float
    converged: bool
    sweeps: dict
    failed: int
    runs: int

    @property
    def measures(self) -> dict[str, float]:
        """:func:`trend_measures` of the sweeps."""
        return trend_measures(self.sweeps) if self.sweeps else {}

    @property
    def verdicts(self) -> dict[str, bool]:
        """The discrete trend verdicts."""
        return _verdicts(self.sweeps) if self.sweeps else {}


def _sweep_values() -> dict[str, np.ndarray]:
    return {name: np.linspace(lo, hi, SWEEP_POINTS[name]) for name, (lo, hi), _ in TRENDS}


def evaluate(case: Case, params: list[Param], U: np.ndarray, ring0: dict, sweeps: bool = True) -> list[Point]:
    """Run the base ring and (``sweeps``) the trend sweeps at each normalised point of ``U``,
    all in one kernel batch.

    Parameters
    ----------
    case : Case
        The reading's case.
    params : list of Param
        The fitted inputs (columns of ``U``).
    U : ndarray, shape (k, len(params))
    ring0 : dict
        The base ring's tension, crown height, crown offset and width.
    sweeps : bool
        Run the trend sweeps too.

    Returns
    -------
    list of Point

    Examples
    --------
    >>> evaluate(Case(), [], np.zeros((0, 0)), {})
    []
    """
    plan = [(None, None)]
    if sweeps:
        plan += [(name, float(x)) for name, xs in _sweep_values().items() for x in xs]
    rows = []
    for u in np.atleast_2d(U):
        if len(u) != len(params):
            break
        phys = [p.physical(float(v)) for p, v in zip(params, u)]
        for name, x in plan:
            ring = dict(ring0)
            if name is not None:
                ring[name] = x
            rows.append(phys + [ring[k] for k in RING])
    if not rows:
        return []
    variables = [p.key for p in params] + [f"ring:{k}" for k in RING]
    values, converged = _run_batch(case, variables, np.array(rows))
    out, n = [], len(plan)
    for i, u in enumerate(np.atleast_2d(U)):
        v, ok = values[i * n : (i + 1) * n], converged[i * n : (i + 1) * n]
        sw: dict = {}
        for (name, x), e in zip(plan[1:], v[1:, 0]):
            xs, es = sw.setdefault(name, ([], []))
            xs.append(x)
            es.append(e)
        out.append(
            Point(
                {p.name: p.physical(float(w)) for p, w in zip(params, u)},
                float(v[0, 0]),
                float(v[0, 1]),
                bool(ok[0]),
                {k: (np.array(a), np.array(b)) for k, (a, b) in sw.items()},
                int(np.sum(~np.isfinite(v[:, 0]))),
                n,
            )
        )
    return out


def _ring0(case: Case) -> dict[str, float]:
    """The base ring's swept variables (as set in the case, else the kernel's value)."""
    return {
        k: float(case.get("ring", k) if case.get("ring", k) is not None else case.value("ring", k))
        for k in RING
    }


def fit_reading(
    reading: Reading,
    cold: Case,
    hot: Case,
    targets: dict,
    budget: int,
    bounds: dict | None = None,
    start: dict | None = None,
) -> dict:
    """Fit one reading on the cold case; predict the hot case with the fitted inputs.

    Parameters
    ----------
    reading : Reading
    cold, hot : Case
        The cold and hot cases (no calibration file: the fitted inputs are set per design).
    targets : dict
        Cold 'energy_loss' and 'mixed_share'.
    budget : int
        Most points the optimiser evaluates (each: 1 + sum(SWEEP_POINTS) runs).
    bounds : dict, optional
        Bounds replacing the physical ones (the relaxed run).
    start : dict, optional
        Start from these input values instead of the start design.

    Returns
    -------
    dict
        'reading', 'params', 'min' (:class:`Minimum`), 'cold' and 'hot' (:class:`Point`),
        'runs', 'seconds'.

    Examples
    --------
    >>> fit_reading(Reading("JFO flooded", "lumped", "N/m"), cold, hot, t, 30)  # doctest: +SKIP
    """
    t0 = time.perf_counter()
    params = _params(reading, bounds)
    c, h = reading.apply(cold), reading.apply(hot)
    ring0 = _ring0(cold)
    seen: dict[tuple, Point] = {}

    def batch(U):
        pts = evaluate(c, params, U, ring0)
        for u, p in zip(U, pts):
            seen[tuple(np.round(u, 12))] = p
        return np.array([residuals(p.energy, p.mixed, p.measures, targets) for p in pts])

    if start is not None:
        s = np.array([[min(1.0, max(0.0, p.normalised(start[p.name]))) for p in params]])
    else:
        s = start_design(len(params))
    m = minimise(batch, s, budget)
    best = seen[tuple(np.round(m.u, 12))]
    hot_pt = evaluate(h, params, m.u[None], ring0)[0]
    runs = sum(p.runs for p in seen.values()) + hot_pt.runs
    return {
        "reading": reading,
        "params": params,
        "min": m,
        "cold": best,
        "hot": hot_pt,
        "runs": runs,
        "seconds": time.perf_counter() - t0,
    }


# --- every reading ---------------------------------------------------------------------------


def _cases(quick: bool) -> tuple[Case, Case, dict, dict, Case, Case]:
    """Cold and hot cases without calibration file, their targets, and the shipped cold and
    hot cases (with the shipped calibration file)."""
    deck, targets = cold_targets()
    hot_deck, hot_targets = cold_targets(condition="hot")
    shipped, shipped_hot = Case.from_namelist(deck), Case.from_namelist(hot_deck)
    cold = shipped.with_("calibration", file="")
    hot = shipped_hot.with_("calibration", file="")
    cases = [cold, hot, shipped, shipped_hot]
    if quick:
        cases = [x.with_numerics(preset="fast", max_cycles=3) for x in cases]
    return cases[0], cases[1], targets, hot_targets, cases[2], cases[3]


def _cost(reading: Reading) -> int:
    """Relative cost rank (expensive first, for the worker pool)."""
    return 2 * reading.starved + (reading.physics.get("cavity_pressure") == "trailing_gas")


def calibrate_readings(
    readings: list[Reading] | None = None,
    budget: int = EVALS,
    quick: bool = False,
    workers: int = 2,
    relax: int = 1,
    progress: bool = True,
) -> dict:
    """Fit every reading (or ``readings``) on the cold case; predict hot with the fitted inputs.

    Parameters
    ----------
    readings : list of Reading, optional
        Default: :func:`all_readings`.
    budget : int
        Points per reading the optimiser may evaluate.
    quick : bool
        Coarse numerics (preset 'fast', 3 cycles): a smoke test, not a result.
    workers : int
        Worker processes (one reading per task).
    relax : int
        Re-fit the best this many readings that end with an input on a bound, and the best of
        those with the most published trends, with :data:`RELAXED_BOUNDS` (outside the
        physical range: shown, never shipped); 0: none.
    progress : bool
        Print a line as each reading finishes.

    Returns
    -------
    dict
        'rows' (from :func:`fit_reading`, best score first), 'relaxed' (the same for the
        relaxed re-fits), 'shipped' (the shipped calibration's cold and hot :class:`Point`,
        its residuals and options), 'targets', 'hot_targets', 'runs', 'quick', 'budget', 'workers'.

    Examples
    --------
    >>> out = calibrate_readings(select_readings(["swift-stieber/lumped/N/m"]), budget=10,
    ...                          quick=True, workers=1, relax=0, progress=False)
    >>> len(out["rows"])
    1
    """
    from .executor import Executor

    readings = all_readings() if readings is None else list(readings)
    cold, hot, targets, hot_targets, shipped, shipped_hot = _cases(quick)
    order = sorted(range(len(readings)), key=lambda i: -_cost(readings[i]))
    tasks = [(readings[i], cold, hot, targets, budget) for i in order]
    rows: list[dict] = []

    def done(i: int, row: dict) -> None:
        rows.append(row)
        if progress:
            print(
                f"[{len(rows)}/{len(tasks)}] {row['reading'].id}: score {row['min'].score:.3g}, "
                f"{row['runs']} runs, {row['seconds']:.0f} s ({row['min'].status})",
                flush=True,
            )

    def pool(n: int) -> Executor:
        return Executor(workers=max(1, workers), backend="processes" if workers > 1 and n > 1 else "serial")

    ex = pool(len(tasks))
    try:
        ex.map(fit_reading, tasks, done)
        rows.sort(key=lambda r: r["min"].score)
        relaxed: list[dict] = []
        bound = [r for r in rows if _on_bound(r)]
        again = bound[: max(0, relax)]
        if relax > 0 and bound:  # and the best of those with the most published trends
            most = max(sum(r["cold"].verdicts.values()) for r in bound)
            pick = next(r for r in bound if sum(r["cold"].verdicts.values()) == most)
            again += [pick] if pick not in again else []
        if again:
            t2 = [(r["reading"], cold, hot, targets, budget, RELAXED_BOUNDS, r["cold"].inputs) for r in again]
            ex.map(fit_reading, t2, lambda i, row: relaxed.append(row))
            relaxed.sort(key=lambda r: r["min"].score)
    finally:
        ex.close()
    # the shipped calibration (deck + inputs/calibration.nml), scored the same way
    ship_params = _params(Reading(list(READINGS)[0], "lumped", "N/m"))
    ship_in = {p.name: float(shipped.value(*p.key.split(":"))) for p in ship_params}
    ring0 = _ring0(cold)
    u_ship = np.array([[p.normalised(ship_in[p.name]) for p in ship_params]])
    sp = evaluate(shipped, ship_params, u_ship, ring0)[0]
    sph = evaluate(shipped_hot, ship_params, u_ship, ring0)[0]
    return {
        "rows": rows,
        "relaxed": relaxed,
        "shipped": {
            "point": sp,
            "hot": sph,
            "residuals": residuals(sp.energy, sp.mixed, sp.measures, targets),
            "options": {
                k: shipped.value(*k.split(":"))
                for k in ("physics:cavitation", "physics:contact_area", "ring:tension_unit")
            },
        },
        "targets": targets,
        "hot_targets": hot_targets,
        "runs": sum(r["runs"] for r in rows + relaxed) + sp.runs + sph.runs,
        "quick": quick,
        "budget": budget,
        "workers": workers,
    }


def _bound_sides(row: dict) -> list[tuple[Param, str, float]]:
    """(param, 'lower'/'upper', outward derivative of score^2/2) of each input on a bound."""
    m = row["min"]
    out = []
    for p, u, g in zip(row["params"], m.u, m.gradient):
        if u <= AT_BOUND:
            out.append((p, "lower", float(-g)))  # outward = decreasing u
        elif u >= 1 - AT_BOUND:
            out.append((p, "upper", float(g)))
    return out


def _on_bound(row: dict) -> bool:
    return bool(_bound_sides(row))


# --- the report ------------------------------------------------------------------------------


def _fmt_input(p: Param, x: float) -> str:
    return f"{x * 1e6:.3g} um" if p.name == "supply_film" else f"{x:.4g}"


def _misses(pt: Point, targets: dict, hot: Point | None = None, hot_targets: dict | None = None) -> list[str]:
    """What a reading misses of the goal: cold Table 2 and trends, and the hot prediction."""
    out = []
    for label, q, t in (("", pt, targets), ("hot ", hot, hot_targets)):
        if q is None:
            continue
        de = q.energy / t["energy_loss"] - 1
        dm = q.mixed - t["mixed_share"]
        if not math.isfinite(de) or abs(de) > GOAL["energy_loss"]:
            out.append(f"{label}energy {de:+.1%}")
        if not math.isfinite(dm) or abs(dm) > GOAL["mixed_share"]:
            out.append(f"{label}mixed {dm:+.2f} pts")
        if not label:
            ms = pt.measures
            out += [f"{k} ({ms[k]:.1%} wrong way)" for k, ok in pt.verdicts.items() if not ok]
    return out


def _table2(pt: Point, t: dict) -> str:
    if not math.isfinite(pt.energy):
        return "failed | failed"
    return (
        f"{pt.energy:.3f} ({pt.energy / t['energy_loss'] - 1:+.1%}) | "
        f"{pt.mixed:.2f} ({pt.mixed - t['mixed_share']:+.2f})"
    )


def _yn(v: dict) -> str:
    return " ".join("Y" if v.get(n) else "n" for n in RING)


def _within(pt: Point, t: dict) -> bool:
    return (
        math.isfinite(pt.energy)
        and abs(pt.energy / t["energy_loss"] - 1) <= GOAL["energy_loss"]
        and abs(pt.mixed - t["mixed_share"]) <= GOAL["mixed_share"]
    )


def _stop(status: str) -> str:
    """A short word for how the optimiser stopped."""
    for word in ("budget", "xtol", "ftol", "gtol"):
        if word in status:
            return word
    return status.split()[0] if status else "-"


def _ids(rows: list[dict]) -> str:
    return f" ({', '.join(r['reading'].id for r in rows)})" if rows else ""


def write_readings(out: dict, path: str | os.PathLike, command: str, seconds: float) -> Path:
    """The readings report as Markdown (written whole or not at all).

    Parameters
    ----------
    out : dict
        From :func:`calibrate_readings`.
    path : path
        Markdown file written.
    command : str
        The command that made it (written in the file).
    seconds : float
        How long it took.

    Returns
    -------
    Path

    Examples
    --------
    >>> out = calibrate_readings(select_readings(["swift-stieber/lumped/N/m"]), budget=10,
    ...                          quick=True, workers=1, relax=0, progress=False)
    >>> write_readings(out, "/tmp/readings.md", "ringlube readings", 0.0).name
    'readings.md'
    """
    rows, t, th = out["rows"], out["targets"], out["hot_targets"]
    per = 1 + sum(SWEEP_POINTS.values())
    e_tol, m_tol = GOAL["energy_loss"], GOAL["mixed_share"]
    md = [
        "# Every reading calibrated on the cold case (issue 9)",
        "",
        f"Regenerated by `{command}` ({seconds:.0f} s wall, {out['runs']} runs, "
        f"{out['workers']} worker processes).",
    ]
    if out["quick"]:
        md += ["", "**Quick mode (coarse numerics, small budget): a smoke test, not a result.**"]
    md += [
        "",
        "Each reading (film model x contact area x tension unit) has its own fit of "
        f"`zeta_kappa_sigma` {BOUNDS['zeta_kappa_sigma']} and `pressure_scale` "
        f"{BOUNDS['pressure_scale']}, and for the starved readings `supply_film` "
        f"({SUPPLY_BOUNDS[0] * 1e6:g}-{SUPPLY_BOUNDS[1] * 1e6:g} um, log scale), to the **cold** "
        f"Table 2 case ({t['energy_loss']:g} J, {t['mixed_share']:g} %) and the four published trend "
        "directions at cold. The hot case "
        f"({th['energy_loss']:g} J, {th['mixed_share']:g} %) is a prediction with the same inputs. "
        "The goal of issue 9: all four trends, and Table 2 within "
        f"{e_tol:.0%} energy and {m_tol:g} points mixed share, cold fitted and hot predicted.",
        "",
        "How (`pydriver/ringlube/readings.py`): the score is the root-sum-square of a residual "
        "vector in units of that goal: the cold energy's relative error over "
        f"{e_tol:.0%}, the cold mixed share's error over {m_tol:g} points, "
        "and for each trend a continuous measure (the fraction of the sweep's mean energy by which "
        "the sweep goes the wrong way: zero exactly when the published direction appears) over "
        f"{e_tol:.0%}, so a sweep {e_tol:.0%} of the energy the wrong way weighs as much as a "
        f"{e_tol:.0%} energy error. A 9-point coarse design of the normalised inputs, then bounded "
        "least squares (`scipy.optimize.least_squares`, trust-region reflective) from its best "
        f"point, with forward-difference Jacobians (step {STEP} of each range) run as one batch, "
        f"at most {out['budget']} points per reading; each point is {per} runs (the base ring "
        "and sweeps of " + ", ".join(f"{SWEEP_POINTS[n]} {n}" for n in RING) + " values over the "
        "study's design ranges, the other variables at the optimum ring). The fit is the best "
        "point evaluated. The hot case is never used in the fit.",
        "",
        "## Fits and Table 2",
        "",
        "Sorted by score. Table 2 cells: value (error; mixed share in points). 'bound': the "
        "inputs that end within 0.5 % of the range of a bound. 'conv': whether the cold and hot "
        "base runs met `cycle_tol` within `max_cycles` (a run that does not is the last cycle's "
        "answer, less certain). 'stop': how the optimiser stopped (xtol/ftol/gtol: converged; "
        "budget: the point budget ran out).",
        "",
        "| # | reading | zeta_kappa_sigma | pressure_scale | supply_film | bound | cold energy J "
        "| cold mixed % | hot energy J (prediction) | hot mixed % (prediction) | conv | score "
        "| stop | points | runs |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for i, r in enumerate(rows, 1):
        ps, c, h, m = r["params"], r["cold"], r["hot"], r["min"]
        ins = [_fmt_input(p, c.inputs[p.name]) for p in ps] + (["-"] if len(ps) == 2 else [])
        bnd = ", ".join(f"{p.name} {side}" for p, side, _ in _bound_sides(r)) or "-"
        md.append(
            f"| {i} | {r['reading'].id} | {' | '.join(ins)} | {bnd} | {_table2(c, t)} | "
            f"{_table2(h, th)} | {'y' if c.converged else 'n'}/{'y' if h.converged else 'n'} | "
            f"{m.score:.3g} | {_stop(m.status)} | {m.evaluations} | {r['runs']} |"
        )
    md += [
        "",
        "## Trends and what each reading misses",
        "",
        "Verdicts in the order tension, crown height, offset, width (Y: the published direction "
        "appears). Measures: the fraction of energy by which each cold sweep goes the wrong way "
        "(0 where the trend appears). Hot trends: a prediction at the cold fit. Misses: every part "
        "of the goal not met (cold Table 2 and trends; hot Table 2).",
        "",
        "| # | reading | cold trends | cold measures % (T, C, O, W) | hot trends | misses |",
        "|---|---|---|---|---|---|",
    ]
    for i, r in enumerate(rows, 1):
        c, h = r["cold"], r["hot"]
        ms = c.measures
        md.append(
            f"| {i} | {r['reading'].id} | {_yn(c.verdicts)} | "
            + ", ".join(f"{100 * ms[n]:.2f}" for n in RING)
            + f" | {_yn(h.verdicts)} | {'; '.join(_misses(c, t, h, th)) or 'nothing'} |"
        )
    md += [
        "",
        "## Does a bound stop a better fit?",
        "",
        "For each input that ends on a bound: the derivative of score^2/2 per unit of normalised "
        "input in the outward direction at the fit (one-sided differences from inside the box). "
        "Negative: the score would fall beyond the bound. This is a local test: at a fit that "
        "converged onto a bound it is negative by construction, and its size says how hard the "
        "fit presses on the bound; the re-fit with relaxed bounds below says how much better the "
        "score gets beyond it.",
        "",
        "| reading | input | bound | outward derivative | score falls beyond it |",
        "|---|---|---|---|---|",
    ]
    nb = 0
    for r in rows:
        for p, side, g in _bound_sides(r):
            nb += 1
            edge = _fmt_input(p, p.lo if side == "lower" else p.hi)
            md.append(
                f"| {r['reading'].id} | {p.name} | {side} ({edge}) | {g:+.3g} | {'yes' if g < 0 else 'no'} |"
            )
    if not nb:
        md.append("| (no input ends on a bound) | | | | |")
    if out["relaxed"]:
        md += [
            "",
            "**Outside the physical range (not a candidate default):** the best readings that end "
            "with an input on a bound (and the best of those with the most trends), re-fitted from "
            "their fit with the bounds relaxed to "
            + ", ".join(
                f"{k} {_fmt_input(Param(k, '', *v), v[0])}-{_fmt_input(Param(k, '', *v), v[1])}"
                for k, v in RELAXED_BOUNDS.items()
            )
            + ".",
            "",
            "| reading | inputs | cold energy J | cold mixed % | hot energy J | hot mixed % | cold trends "
            "| cold measures % | score relaxed | score in bounds |",
            "|---|---|---|---|---|---|---|---|---|---|",
        ]
        inb = {r["reading"]: r["min"].score for r in rows}
        for r in out["relaxed"]:
            c = r["cold"]
            ins = ", ".join(f"{p.name} {_fmt_input(p, c.inputs[p.name])}" for p in r["params"])
            md.append(
                f"| {r['reading'].id} | {ins} | {_table2(c, t)} | {_table2(r['hot'], th)} | "
                f"{_yn(c.verdicts)} | {', '.join(f'{100 * c.measures[n]:.2f}' for n in RING)} | "
                f"{r['min'].score:.3g} | {inb[r['reading']]:.3g} |"
            )
    # the shipped calibration
    sh = out["shipped"]
    sp, sr = sh["point"], sh["residuals"]
    opts = ", ".join(f"{k} {v!r}" for k, v in sh["options"].items())
    md += [
        "",
        "## The shipped calibration, scored the same way",
        "",
        f"The shipped cold deck with `inputs/calibration.nml` ({opts}, "
        + ", ".join(f"{k} {_fmt_input(Param(k, '', 1, 2), v)}" for k, v in sp.inputs.items())
        + f"): cold {_table2(sp, t).replace(' | ', ' J, ')} %, trends {_yn(sp.verdicts)} (measures "
        + ", ".join(f"{100 * sp.measures[n]:.2f} %" for n in RING)
        + f"), score {float(np.sqrt(np.sum(sr**2))):.3g}; hot (prediction) "
        + f"{_table2(sh['hot'], th).replace(' | ', ' J, ')} %, trends {_yn(sh['hot'].verdicts)}.",
    ]
    # the computed summary
    ok = [r for r in rows if math.isfinite(r["cold"].energy)]
    all4 = [r for r in ok if all(r["cold"].verdicts.values())]
    t2 = [r for r in ok if _within(r["cold"], t)]
    hot_ok = [r for r in ok if _within(r["hot"], th)]
    both = [r for r in all4 if r in t2]
    goal = [r for r in both if r in hot_ok]
    onb = [r for r in ok if _on_bound(r)]
    most = max((sum(r["cold"].verdicts.values()) for r in ok), default=0)
    most_t2 = [r for r in t2 if sum(r["cold"].verdicts.values()) == most]
    md += ["", "## Summary (computed)", ""]
    md += [
        f"- Readings fitted: {len(ok)} of {len(rows)}.",
        f"- All four published trends at cold: {len(all4)}{_ids(all4)}.",
        f"- Most trends in one reading: {most}; readings with {most} trends and cold Table 2 within "
        f"the goal: {len(most_t2)}{_ids(most_t2)}.",
        f"- Cold Table 2 within {e_tol:.0%} energy and {m_tol:g} points: {len(t2)}{_ids(t2)}.",
        f"- Hot Table 2 (prediction) within the same tolerances: {len(hot_ok)}{_ids(hot_ok)}.",
        f"- All four trends and cold Table 2: {len(both)}{_ids(both)}; and the hot prediction too "
        f"(the goal of issue 9): {len(goal)}{_ids(goal)}.",
        f"- Fits with an input on a bound: {len(onb)}.",
    ]
    if out["relaxed"]:
        gains = [
            f"{r['reading'].id} {next(x['min'].score for x in rows if x['reading'] == r['reading']):.3g}"
            f" -> {r['min'].score:.3g}"
            for r in out["relaxed"]
        ]
        md.append(f"- Score with the bounds relaxed (outside the physical range): {'; '.join(gains)}.")
    if ok:
        b = ok[0]
        md.append(
            f"- Closest by score: **{b['reading'].id}** (score {b['min'].score:.3g}); it misses "
            f"{'; '.join(_misses(b['cold'], t, b['hot'], th)) or 'nothing'}."
        )
        hot_res = {
            id(r): math.hypot(
                (r["hot"].energy / th["energy_loss"] - 1) / e_tol,
                (r["hot"].mixed - th["mixed_share"]) / m_tol,
            )
            for r in ok
        }
        if t2:
            c = min(t2, key=lambda r: hot_res[id(r)])
            md.append(
                f"- Best hot prediction among those with cold Table 2 within the goal: **{c['reading'].id}** "
                f"(hot {_table2(c['hot'], th).replace(' | ', ' J, ')} %; score {c['min'].score:.3g}); "
                f"it misses {'; '.join(_misses(c['cold'], t, c['hot'], th)) or 'nothing'}."
            )
        for name in RING:
            if not any(r["cold"].verdicts.get(name) for r in ok):
                w = min(ok, key=lambda r: r["cold"].measures[name])
                md.append(
                    f"- No reading gives the published {name} trend; the smallest miss is "
                    f"{w['cold'].measures[name]:.1%} of the energy ({w['reading'].id})"
                    + (
                        "; with relaxed bounds: "
                        + ", ".join(
                            f"{x['cold'].measures[name]:.1%} ({x['reading'].id})" for x in out["relaxed"]
                        )
                        if out["relaxed"]
                        else ""
                    )
                    + "."
                )
    path = Path(path)
    write_text(path, "\n".join(md) + "\n")
    return path


def add_arguments(ap) -> None:
    """The options of ``ringlube readings`` (shared with the ``ringlube`` command).

    Parameters
    ----------
    ap : argparse.ArgumentParser

    Examples
    --------
    >>> import argparse
    >>> ap = argparse.ArgumentParser(); add_arguments(ap)
    >>> ap.parse_args(["--quick"]).quick
    True
    """
    ap.add_argument("--out", default="docs/readings.md", help="Markdown file written")
    ap.add_argument(
        "--readings",
        nargs="+",
        metavar="ID",
        help="fit only these readings (ids like 'jfo-starved/lumped/N/m'; shell wildcards allowed)",
    )
    ap.add_argument(
        "--evals", type=int, default=EVALS, help="most points per reading the optimiser evaluates"
    )
    ap.add_argument("--workers", type=int, default=2, help="worker processes")
    ap.add_argument("--relax", type=int, default=2, help="re-fit the best N readings with relaxed bounds")
    ap.add_argument(
        "--quick",
        action="store_true",
        help="coarse numerics, at most 10 points, no relaxed re-fit: a smoke test",
    )
    ap.add_argument("--list", action="store_true", help="list the reading ids and stop")


def run_args(args) -> int:
    """Run ``ringlube readings`` with parsed arguments.

    Parameters
    ----------
    args : argparse.Namespace
        From a parser given :func:`add_arguments`.

    Returns
    -------
    int
        Exit status.

    Raises
    ------
    InputError
        For an unknown reading or a bad number.

    Examples
    --------
    >>> import argparse
    >>> ap = argparse.ArgumentParser(); add_arguments(ap)
    >>> run_args(ap.parse_args(["--list"]))  # doctest: +ELLIPSIS
    swift-stieber/lumped/N/m
    ...
    0
    """
    if args.list:
        print("\n".join(r.id for r in all_readings()))
        return 0
    if args.evals < 1 or args.workers < 1 or args.relax < 0:
        raise InputError("--evals and --workers must be at least 1, --relax at least 0")
    readings = select_readings(args.readings)
    check_output(args.out, option="--out")  # before hours of fits, not after
    budget = min(args.evals, 10) if args.quick else args.evals
    relax = 0 if args.quick else args.relax
    t0 = time.perf_counter()
    out = calibrate_readings(readings, budget=budget, quick=args.quick, workers=args.workers, relax=relax)
    cmd = "ringlube readings"
    if args.readings:
        cmd += " --readings " + " ".join(args.readings)
    if args.quick:
        cmd += " --quick"
    elif args.evals != EVALS:
        cmd += f" --evals {args.evals}"
    if args.relax != 2 and not args.quick:
        cmd += f" --relax {args.relax}"
    if args.workers != 2:
        cmd += f" --workers {args.workers}"
    print(f"written {write_readings(out, args.out, cmd, time.perf_counter() - t0)}")
    return 0


def main(argv: list[str] | None = None) -> int:
    """``ringlube readings``: fit every reading and write the report.

    Parameters
    ----------
    argv : list of str, optional

    Returns
    -------
    int

    Examples
    --------
    >>> main(["--out", "docs/readings.md"])  # doctest: +SKIP
    0
    """
    import argparse
    import sys

    ap = argparse.ArgumentParser(prog="ringlube readings", description=__doc__.splitlines()[0])
    add_arguments(ap)
    args = ap.parse_args(argv)
    try:
        return run_args(args)
    except InputError as exc:
        print(f"ringlube readings: error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":  # pragma: no cover
    raise SystemExit(main())
