"""How a study's designs and results are shown: display units, marks and feasibility.

Every number carries its unit; designs are shown in the units of
:func:`~ringlube.study.variables.display` (lengths in mm or µm, tension in the base decks'
``&ring tension_unit``). A re-checked design that did not converge or lifted the ring off the
liner is marked (:data:`NOT_CONVERGED`, :data:`LIFTED`), never shown as a good design; one
that came close to a change of state is marked :data:`BRANCH_RISK`.
"""

from __future__ import annotations

import numpy as np

from .bounds import constraint_bounds
from .store import Study
from .variables import display, result_display

#: How a re-checked design whose true-model run did not converge is marked (its numbers are
#: the last cycle's, not a verified periodic result).
NOT_CONVERGED = "NOT CONVERGED, not verified"
#: Mark of a design whose true-model run lifted the ring off the liner at some crank steps
#: (``liner_lift_share`` > 0: the film carried no load there and the results at those steps
#: rest on the lift-off model): reported, never ranked as a good design.
LIFTED = "LIFTED OFF the liner, not a good design"
#: Mark of a design whose true-model run came close to a change of state: a branch-risk margin
#: (``lift_margin``, ``seal_margin``) below its threshold (:data:`ringlube.tables.MARGINS`;
#: docs/model.md, "Branch risk"): its numbers may belong to the other state after a small
#: change of the inputs or the numerics. Reported, as a run that did not converge is.
BRANCH_RISK = "BRANCH RISK"
#: Pareto CSV column marking designs the surfaces predict to lift off the liner.
LIFTED_COLUMN = "lifted off the liner (surrogate)"

__all__ = [
    "BRANCH_RISK",
    "LIFTED",
    "LIFTED_COLUMN",
    "NOT_CONVERGED",
    "format_design",
    "surrogate_error",
    "with_unit",
]


def format_design(study: Study, x) -> str:
    """A design as text in display units, e.g. ``width 1.004 mm, tension 8 N/m``.

    Parameters
    ----------
    study : Study
    x : array_like
        One value per variable (SI).

    Returns
    -------
    str

    Example
    -------
    >>> format_design(study, [1.004e-3, 9.31e-6, -38.3e-6, 8.0])    # doctest: +SKIP
    'width 1.004 mm, crown height 9.31 µm, crown offset -38.3 µm, tension 8 N/m'
    """
    s = study.s
    parts = []
    for v, u, lo, hi, xi in zip(s.variables, s.units, s.lower, s.upper, x):
        label, scale = display(v, u, lo, hi)
        name, _, unit = label.partition(" [")
        parts.append(f"{name} {xi * scale:.4g}" + (f" {unit[:-1]}" if unit else ""))
    return ", ".join(parts)


def with_unit(number: str, unit: str) -> str:
    """A number as text with its unit, none for a unit-less result (unit '1').

    Parameters
    ----------
    number : str
        The number as text.
    unit : str
        Its unit (``result_display``).

    Returns
    -------
    str

    Examples
    --------
    >>> with_unit("2.5", "J"), with_unit("1", "1"), with_unit("3", "")
    ('2.5 J', '1', '3')
    """
    return number if unit in ("", "1") else f"{number} {unit}"


def _values(names, values) -> str:
    out = []
    for o, v in zip(names, values):
        unit, k = result_display(o)
        out.append(f"{o} {with_unit(f'{v * k:.4g}', unit)}")
    return ", ".join(out)


def lift_share(study: Study, values: np.ndarray) -> float:
    """The ``liner_lift_share`` [%] among a design's results (0 if the study does not record
    it or the value is not a number).

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> st = SimpleNamespace(s=SimpleNamespace(outputs=["energy_loss", "liner_lift_share"]))
    >>> lift_share(st, np.array([1.5, 2.5])), lift_share(st, np.array([1.5, np.nan]))
    (2.5, 0.0)
    """
    outputs = list(study.s.outputs)
    if "liner_lift_share" not in outputs:
        return 0.0
    v = float(values[outputs.index("liner_lift_share")])
    return v if np.isfinite(v) and v > 0 else 0.0


def _lift_mark(study: Study, values: np.ndarray) -> str:
    """'' or the lift-off mark with the share of the cycle lifted."""
    share = lift_share(study, values)
    return f"{LIFTED} ({share:.3g} % of the cycle)" if share > 0 else ""


def branch_risks(study: Study, values: np.ndarray) -> list[str]:
    """The branch-risk marks of a design's true results: one per recorded margin whose
    magnitude is below its threshold (:data:`ringlube.tables.MARGINS`).

    Parameters
    ----------
    study : Study
    values : ndarray
        The design's results, one per ``study.s.outputs``.

    Returns
    -------
    list of str

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> st = SimpleNamespace(s=SimpleNamespace(outputs=["energy_loss", "lift_margin"]))
    >>> branch_risks(st, np.array([1.5, -0.0037])), branch_risks(st, np.array([1.5, 0.2]))
    (['BRANCH RISK (lift_margin -0.0037, below 0.01)'], [])
    """
    from ..tables import MARGINS

    outputs = list(study.s.outputs)
    out = []
    for name, spec in MARGINS.items():
        if name in outputs:
            v = float(values[outputs.index(name)])
            if np.isfinite(v) and abs(v) < spec.threshold:
                out.append(f"{BRANCH_RISK} ({name} {v:+.4f}, below {spec.threshold:g})")
    return out


def _feasible_text(study: Study, label: str, ft: np.ndarray, points: dict | None = None) -> str:
    """'feasible' or which constraints the true results violate (``points``: a scene design's
    results at each operating point, for its point constraints)."""
    bad = []
    for bd in constraint_bounds(study, label):
        k, j, b = bd.constraint, bd.column, bd.value
        unit, scale = result_display(k.name)
        at = "" if bd.point == label else f" at {bd.point}"
        y = ft[j] if bd.point == label else (points[bd.point][j] if points else np.nan)
        if not np.isfinite(y) or k.violation(y, b) > 0:
            rel = ">" if k.sense == "<=" else "<"
            bad.append(f"{k.name}{at} {y * scale:.6g} {rel} {with_unit(f'{b * scale:.6g}', unit)}")
    return "feasible" if not bad else "INFEASIBLE: " + "; ".join(bad)


def surrogate_error(name: str, predicted: float, true: float) -> str:
    """The surrogate's error on a result: relative to the true value (``+1.2%``), or where
    that is 0, the difference in the result's unit (a relative error would be inf or nan).

    Parameters
    ----------
    name : str
        The result (its unit: :func:`~ringlube.study.variables.result_display`).
    predicted, true : float
        The surrogate's value and the true model's.

    Returns
    -------
    str
        ``-`` where either is not a number.

    Examples
    --------
    >>> surrogate_error("energy_loss", 1.01, 1.0), surrogate_error("mixed_share", 0.25, 0.0)
    ('+1.0%', '+0.25 % (true 0)')
    >>> surrogate_error("flutter_events", 0.0, 0.0)
    '+0 (true 0)'
    """
    if not (np.isfinite(predicted) and np.isfinite(true)):
        return "-"
    if true != 0:
        return f"{(predicted - true) / abs(true):+.1%}"
    unit, scale = result_display(name)
    return f"{with_unit(f'{(predicted - true) * scale:+.3g}', unit)} (true 0)"


def design_points(ch, i: int) -> dict | None:
    """The results of design ``i`` of a :class:`~ringlube.study.state_checks.Checked` at each
    operating point (None when not run there)."""
    return None if ch.points is None else {p: np.atleast_2d(v)[i] for p, v in ch.points.items()}
