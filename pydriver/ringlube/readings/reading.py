"""Calibration of every reading of the open modelling choices.

A reading is a film model crossed with the contact area and the tension unit. For
each, the uncertain inputs are fitted to the **cold** case only, with the published trend
directions at cold as targets beside the two Table 2 numbers; the hot case stays a prediction.

Fitted inputs: ``&surface zeta_kappa_sigma`` and ``&operating pressure_scale`` on their
calibration bounds (:data:`ringlube.calibrate.BOUNDS`), and ``&lubricant supply_film`` on
:data:`SUPPLY_BOUNDS` (logarithmic) for the starved readings.

Score. One residual vector per point, every entry in units of the goal:

* the cold energy's relative error over 5 % (:data:`GOAL`),
* the cold mixed share's error over 1.5 points,
* for each published trend, its continuous measure (:func:`ringlube.trends.trend_measures`, a
  fraction of the energy by which the sweep goes the wrong way) over the same 5 %: a sweep 5 %
  of the energy the wrong way weighs as much as a 5 % energy error.

The score is the root-sum-square of that vector; the discrete yes/no verdicts
(:func:`ringlube.trends.trend_verdicts`) are reported beside it but not optimised (they are
not smooth). Each point costs one base run and the trend sweeps of :data:`SWEEP_POINTS`.

Optimiser: the one calibrator, :func:`ringlube.calibrate.calibrator.calibrate_inputs` (method
'least_squares', called by :func:`ringlube.readings.fit.fit_reading`): a 9-point coarse
design of the (normalised) input box, then ``scipy.optimize.least_squares`` (trust-region
reflective, bounded) from its best point, with a forward-difference Jacobian whose steps are
run as one batch; every point evaluated is kept and the best one is the fit. Each reading is one task;
readings run in parallel worker processes, and each point's runs go to the kernel as one
``run_designs`` batch (:func:`evaluate`). The report is :mod:`ringlube.readings.report`, the
command (``ringlube readings``) :mod:`ringlube.readings.cli`.
"""

from __future__ import annotations

import dataclasses
import fnmatch
import math

import numpy as np

from ..calibrate import BOUNDS, Param
from ..case import Case
from ..errors import InputError
from ..trends import TRENDS, trend_measures, trend_verdicts

__all__ = [
    "READINGS",
    "SUPPLY_BOUNDS",
    "RELAXED_BOUNDS",
    "GOAL",
    "SWEEP_POINTS",
    "Reading",
    "all_readings",
    "select_readings",
    "residuals",
    "Point",
    "evaluate",
]

#: The film models (docs/readings.md), read one at a time (the other open choices crossed
#: with them).
READINGS = {
    "Swift-Stieber (the study)": {},
    "JFO flooded": {"cavitation": "jfo"},
    "JFO flooded, trailing gas": {"cavitation": "jfo", "cavity_pressure": "trailing_gas"},
    "JFO starved": {"cavitation": "jfo", "inlet": "starved"},
    "JFO starved, trailing gas": {"cavitation": "jfo", "inlet": "starved", "cavity_pressure": "trailing_gas"},
}


#: Bounds of the supply film fitted for starved readings [m] (fitted on a log scale).
SUPPLY_BOUNDS = (0.1e-6, 10e-6)
#: Wider bounds, outside the physical range, used only to show whether a bound stops a better
#: fit (never a shipped reading).
RELAXED_BOUNDS = {
    "zeta_kappa_sigma": (0.01, 0.3),
    "pressure_scale": (0.6, 1.6),
    "supply_film": (0.02e-6, 50e-6),
}
#: The goal: cold energy within 5 % (relative) and mixed share within 1.5 points.
GOAL = {"energy_loss": 0.05, "mixed_share": 1.5}
#: Points of each cold trend sweep (:attr:`ringlube.trends.Trend.points`).
SWEEP_POINTS = {t.name: t.points for t in TRENDS}
#: The ring variables swept (order of :data:`ringlube.trends.TRENDS`).
RING = tuple(t.name for t in TRENDS)
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
    """One reading: film model (a key of :data:`READINGS`), contact area
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


def _verdicts(sweeps: dict) -> dict[str, bool]:
    """The discrete verdicts; a sweep with a failed point says no."""
    v = trend_verdicts(sweeps)  # every trend swept
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


# --- one reading ----------------------------------------------------------------------------


def _run_batch(case: Case, variables: list[str], x: np.ndarray):
    """(values (n, 2): energy, mixed; converged (n,)) of designs ``x`` (the one kernel call)."""
    from ..solve import run_designs

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
    return {t.name: np.linspace(*t.range, t.points) for t in TRENDS}


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
