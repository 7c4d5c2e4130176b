"""The constraints of a study applied to its designs: the bound each constraint sets for the
designs of a case or of the scene, and whether designs satisfy them.

A case's designs are bound by the constraints of their own point (:func:`constraint_bounds`);
the scene's designs run at every point and are bound by every point's constraints on that
point's values (and by the ``at scene`` ones on their mean). Whether a case's chosen designs
also satisfy the other points' constraints is :func:`point_violations`. A bound taken from a
reference design whose run did not converge is said (:class:`UnconvergedReferenceWarning`).
"""

from __future__ import annotations

import dataclasses
import warnings

import numpy as np

from ..errors import RinglubeError
from .constraints import SCENE, Constraint
from .store import Study
from .variables import result_display

__all__ = [
    "Bound",
    "constraint_bounds",
    "feasibility",
    "point_violations",
    "UnconvergedReferenceWarning",
    "unconverged_reference",
]


@dataclasses.dataclass(frozen=True)
class Bound:
    """A constraint with its bound for the designs of one case or the scene.

    Attributes
    ----------
    constraint : Constraint
    column : int
        The result's column in the study's outputs.
    value : float
        The bound in the result's unit.
    point : str
        Whose values it binds: the case's own label, or, for the scene, the operating point
        (a case label) or ``'scene'`` (the weighted mean).

    Example
    -------
    >>> from ringlube.study.constraints import parse_constraint
    >>> Bound(parse_constraint("fmep <= 3"), 4, 3.0, "cold").point
    'cold'
    """

    constraint: Constraint
    column: int
    value: float
    point: str


def _reference_value(study: Study, point: str, k: Constraint, j: int) -> float:
    ref = study.cases[point].reference
    value = float(ref.f_true[0, j]) if ref is not None else float("nan")
    if not np.isfinite(value):
        raise RinglubeError(
            f"case '{point}': constraint '{k}': the reference design's run failed "
            f"({ref.errors[0] if ref is not None else 'not run'}), so it bounds nothing"
        )
    if unconverged_reference(study, point):  # (said once per point and text)
        warnings.warn(unconverged_reference(study, point), UnconvergedReferenceWarning, stacklevel=1)
    return value


class UnconvergedReferenceWarning(UserWarning):
    """A constraint takes its bound from a reference design whose run did not converge
    (``ringlube optimise`` shows it as one line on stderr).

    Example
    -------
    >>> issubclass(UnconvergedReferenceWarning, UserWarning)
    True
    """


def unconverged_reference(study: Study, point: str) -> str:
    """'' or why the ``reference`` bounds at a point are not earned: its reference design's
    true-model run there did not converge (the bound is the last cycle's value).

    Parameters
    ----------
    study : Study
    point : str
        Case label or ``scene``.

    Returns
    -------
    str
        The warning's text, or '' (a converged reference, none checked, or no constraint
        bounded by a reference).

    Example
    -------
    >>> unconverged_reference(study, "cold")                 # doctest: +SKIP
    "case 'cold': the reference design did NOT CONVERGE: ..."
    """
    ref = study.cases[point].reference if point in study.cases else None
    names = [str(k) for k in study.s.parsed_constraints if k.uses_reference]
    if not names or ref is None or bool(np.asarray(ref.converged)[0]):
        return ""
    return (
        f"case '{point}': the reference design did NOT CONVERGE, so {', '.join(names)} "
        "takes its bound from a cycle that is not periodic (give the base deck a larger "
        "max_cycles or a looser cycle_tol)"
    )


def constraint_bounds(study: Study, label: str) -> list[Bound]:
    """The constraints binding the designs of a case or the scene, with their bounds.

    A case's designs are bound by the constraints that hold at its point, on its own values.
    The scene's designs run at every point: each constraint without ``at`` binds them at every
    point, one ``at LABEL`` at that point (each on the point's values), one ``at scene`` on
    their weighted mean. A bound ``reference`` is the reference design's true-model value at
    the point it binds (times the factor), so the reference must have been re-simulated
    (:func:`~ringlube.study.check.check_designs` with ``which=("reference",)``).

    Parameters
    ----------
    study : Study
    label : str
        Case label or ``scene``.

    Returns
    -------
    list of Bound

    Raises
    ------
    RinglubeError
        The bound is the reference design's value and its run failed.

    Example
    -------
    >>> [(b.constraint.name, b.point) for b in constraint_bounds(study, "scene")]  # doctest: +SKIP
    [('blowby', 'r4000'), ('blowby', 'r8000'), ('blowby', 'r12000')]
    """
    s = study.s
    out = []
    for k in s.parsed_constraints:
        j = s.outputs.index(k.name)
        if label == SCENE:
            points = [k.at] if k.at else list(s.labels)
        else:
            points = [label] if k.holds_at(label) else []
        for p in points:
            bound = k.bound(_reference_value(study, p, k, j) if k.uses_reference else None)
            out.append(Bound(k, j, float(bound), p))
    return out


def feasibility(
    study: Study, label: str, values: np.ndarray, points: dict[str, np.ndarray] | None = None
) -> np.ndarray:
    """Which designs satisfy every constraint binding a case or the scene (by the values given).

    Parameters
    ----------
    study : Study
    label : str
    values : ndarray, shape (k, len(outputs))
        Results of the designs on the case (for the scene: the weighted means), from the true
        model or the surfaces; NaN counts as infeasible.
    points : dict of str to ndarray, optional
        The scene's designs' results at each operating point (needed by its point constraints).

    Returns
    -------
    ndarray of bool, shape (k,)

    Raises
    ------
    ValueError
        A scene constraint at a point whose values are not given.

    Example
    -------
    >>> feasibility(study, "cold", study.cases["cold"].chosen.f_true)   # doctest: +SKIP
    array([ True,  True, False,  True])
    """
    values = np.atleast_2d(values)
    ok = np.ones(len(values), bool)
    for b in constraint_bounds(study, label):
        if b.point == label:
            y = values[:, b.column]
        elif points is not None and b.point in points:
            y = np.atleast_2d(points[b.point])[:, b.column]
        else:
            raise ValueError(
                f"'{b.constraint}' binds the {label}'s designs at {b.point}: its values are needed"
            )
        with np.errstate(invalid="ignore"):
            ok &= np.isfinite(y) & (np.asarray(b.constraint.violation(y, b.value)) <= 0)
    return ok


def point_violations(study: Study, points: dict[str, np.ndarray]) -> list[list[str]]:
    """For designs run at every operating point, the constraints of every point each violates.

    Parameters
    ----------
    study : Study
    points : dict of str to ndarray
        Each case label to the designs' results there, shape (k, len(outputs)).

    Returns
    -------
    list of list of str
        Per design, ``'at P: NAME y > bound UNIT'`` for each violated constraint of each
        point P (NaN: ``'at P: NAME not computed'``); empty where the design satisfies them all.

    Example
    -------
    >>> point_violations(study, study.cases["r4000"].chosen.points)    # doctest: +SKIP
    [[], ['at r12000: flutter_events 2 > 1']]
    """
    k = len(next(iter(points.values()))) if points else 0
    out: list[list[str]] = [[] for _ in range(k)]
    for p in study.s.labels:
        if p not in points:
            continue
        y_all = np.atleast_2d(points[p])
        for b in constraint_bounds(study, p):
            unit, scale = result_display(b.constraint.name)
            unit = "" if unit == "1" else unit  # a count
            rel = ">" if b.constraint.sense == "<=" else "<"
            for i, y in enumerate(y_all[:, b.column]):
                if not np.isfinite(y):
                    out[i].append(f"at {p}: {b.constraint.name} not computed")
                elif b.constraint.violation(y, b.value) > 0:
                    text = f"at {p}: {b.constraint.name} {y * scale:.6g} {rel} {b.value * scale:.6g} {unit}"
                    out[i].append(text.rstrip())
    return out
