"""The fit of every reading of ``ringlube readings``.

:func:`fit_reading` fits one reading on the cold case with the one calibrator,
:func:`ringlube.calibrate.calibrator.calibrate_inputs` (method 'least_squares': a 9-point coarse design
of the normalised input box, then ``scipy.optimize.least_squares`` from its best point) on the
readings' score (:mod:`ringlube.readings`), and predicts hot; :func:`calibrate_readings` fits
every reading in parallel worker processes.
"""

from __future__ import annotations

import time

import numpy as np

from ..calibrate import Param, calibrate_inputs, cold_targets, start_design
from ..case import Case
from .reading import (
    AT_BOUND,
    EVALS,
    READINGS,
    RELAXED_BOUNDS,
    STEP,
    Point,
    Reading,
    _params,
    _ring0,
    all_readings,
    evaluate,
    residuals,
)

__all__ = ["fit_reading", "calibrate_readings"]


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
        'reading', 'params', 'min' (the :class:`scipy.optimize.OptimizeResult` of
        :func:`ringlube.calibrate.calibrator.calibrate_inputs`), 'cold' and 'hot' (:class:`Point`),
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
    m = calibrate_inputs(batch, params, "least_squares", start=s, budget=budget, step=STEP)
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
    >>> from ringlube.readings import select_readings
    >>> out = calibrate_readings(select_readings(["swift-stieber/lumped/N/m"]), budget=10,
    ...                          quick=True, workers=1, relax=0, progress=False)
    >>> len(out["rows"])
    1
    """
    from ..executor import Executor

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
                f"{row['runs']} runs, {row['seconds']:.0f} s ({row['min'].message})",
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
    for p, u, g in zip(row["params"], m.u, m.grad):
        if u <= AT_BOUND:
            out.append((p, "lower", float(-g)))  # outward = decreasing u
        elif u >= 1 - AT_BOUND:
            out.append((p, "upper", float(g)))
    return out


def _on_bound(row: dict) -> bool:
    return bool(_bound_sides(row))
