"""The constraints of a study: ``&study constraints`` entries parsed and evaluated.

An entry is ``NAME <= RHS`` or ``NAME >= RHS``, optionally followed by ``at LABEL``:

* RHS is a number in the result's unit, ``reference`` (the reference design's true-model value)
  or ``FACTOR * reference`` (that value times a positive number, e.g. ``1.05 * reference``);
* without ``at`` the constraint holds at every operating point (each case on its own values);
  ``at LABEL`` holds at that case only; ``at scene`` holds for the weighted scene's mean.

A case's designs are bound by the constraints of their own point (:func:`constraint_bounds`);
the scene's designs run at every point and are bound by every point's constraints on that
point's values (and by the ``at scene`` ones on their mean). Whether a case's chosen designs
also satisfy the other points' constraints is :func:`point_violations`.
"""

from __future__ import annotations

import dataclasses
import math
import re
import warnings
from typing import TYPE_CHECKING

import numpy as np

from ..errors import RinglubeError
from .variables import output_units

if TYPE_CHECKING:
    from .store import Study

__all__ = [
    "Constraint",
    "Bound",
    "parse_constraint",
    "constraint_bounds",
    "feasibility",
    "point_violations",
    "UnconvergedReferenceWarning",
    "unconverged_reference",
]

#: The label of the weighted scene (``at scene``).
SCENE = "scene"

_SYNTAX = "'NAME <= VALUE', 'NAME >= VALUE' or 'NAME <= [FACTOR *] reference', each optionally 'at LABEL'"


@dataclasses.dataclass(frozen=True)
class Constraint:
    """One ``&study constraints`` entry: ``NAME <= VALUE``, ``NAME >= VALUE``, ``NAME <=
    reference`` or ``NAME <= FACTOR * reference`` (the reference design's true-model value on the
    same point, times FACTOR), optionally ``at LABEL`` (one operating point, or ``scene``).

    Attributes
    ----------
    name : str
        A scalar result (:func:`~ringlube.study.variables.output_units`).
    sense : str
        ``'<='`` or ``'>='``.
    value : float or None
        The bound in the result's unit, or None for a bound by the reference.
    factor : float
        The reference's value is multiplied by it (1: ``reference``).
    at : str or None
        The case label it holds at, ``'scene'`` for the scene's weighted mean, None for every
        operating point.

    Example
    -------
    >>> c = parse_constraint("oil_to_chamber <= reference")
    >>> c.uses_reference, c.violation(3.0, 2.0)
    (True, 0.5)
    >>> str(parse_constraint("blowby<=1.05*reference at 'r8000'"))
    'blowby <= 1.05 * reference at r8000'
    """

    name: str
    sense: str
    value: float | None
    factor: float = 1.0
    at: str | None = None

    @property
    def uses_reference(self) -> bool:
        """Is the bound the reference design's value (times :attr:`factor`)?"""
        return self.value is None

    def __str__(self) -> str:
        if self.value is not None:
            rhs = _text(self.value)
        else:
            rhs = "reference" if self.factor == 1.0 else f"{_text(self.factor)} * reference"
        return f"{self.name} {self.sense} {rhs}" + (f" at {self.at}" if self.at else "")

    def holds_at(self, point: str) -> bool:
        """Does the constraint bind the values of ``point`` (a case label, or ``'scene'`` for
        the scene's weighted mean)?

        Example
        -------
        >>> c = parse_constraint("fmep <= 3 at overrun")
        >>> c.holds_at("overrun"), c.holds_at("rated"), parse_constraint("fmep <= 3").holds_at("scene")
        (True, False, False)
        """
        return self.at == point if (self.at or point == SCENE) else True

    def bound(self, reference_value: float | None = None) -> float:
        """The bound in the result's unit: :attr:`value`, or :attr:`factor` times the
        reference design's value.

        Example
        -------
        >>> parse_constraint("blowby <= 1.05 * reference").bound(2.0)
        2.1
        """
        return self.value if self.value is not None else self.factor * float(reference_value)

    def violation(self, y, bound: float):
        """pymoo's inequality ``g <= 0``: ``(y - bound) / scale`` for ``<=`` (negated for
        ``>=``), scaled by ``|bound|`` (1 if the bound is 0) so constraints of different
        units weigh alike.

        Parameters
        ----------
        y : float or ndarray
            The result.
        bound : float
            The bound (:meth:`bound`).

        Returns
        -------
        float or ndarray
            <= 0 where satisfied.

        Example
        -------
        >>> parse_constraint("min_film >= 1e-6").violation(0.5e-6, 1e-6)
        0.5
        """
        scale = abs(bound) if bound != 0 else 1.0
        g = (np.asarray(y, float) - bound) / scale
        g = g if self.sense == "<=" else -g
        return float(g) if np.ndim(g) == 0 else g


def _text(v: float) -> str:
    """The shortest text that reads back as ``v`` (the normal form is parsed again: a bound
    must not lose digits; it kept 6 before).

    >>> _text(3.0), _text(201.90288769599832)
    ('3', '201.90288769599832')
    """
    short = f"{v:g}"
    return short if float(short) == v else repr(float(v))


def _number(text: str) -> float:
    return float(text.lower().replace("d", "e"))


def parse_constraint(text: str) -> Constraint:
    """Parse ``'NAME <= VALUE'``, ``'NAME >= VALUE'``, ``'NAME <= reference'``,
    ``'NAME <= FACTOR * reference'``, each optionally followed by ``at LABEL`` (the label may
    be quoted, ``at 'overrun'``).

    Parameters
    ----------
    text : str
        One entry of ``&study constraints``; VALUE in the result's unit
        (:func:`~ringlube.study.variables.output_units`).

    Returns
    -------
    Constraint

    Raises
    ------
    ValueError
        Saying what is wrong (the caller names file, group and variable, and checks the label).

    Example
    -------
    >>> str(parse_constraint(" fmep<=10 "))
    'fmep <= 10'
    >>> parse_constraint("blowby <= 1.05 * reference at overrun").at
    'overrun'
    """
    m = re.fullmatch(
        r"\s*([A-Za-z_]\w*)\s*(<=|>=)\s*(.*?)(?:\s+at\s+(['\"]?)([^'\"\s]+)\4)?\s*", str(text), flags=re.I
    )
    if not m or not m.group(3):
        raise ValueError(f"'{text}' is not {_SYNTAX}")
    name, sense, rhs, at = m.group(1).lower(), m.group(2), m.group(3).strip(), m.group(5)
    units = output_units()
    if name not in units:
        raise ValueError(f"'{text}': unknown result '{name}' (known: {', '.join(units)})")
    scaled = re.fullmatch(r"(\S+?)\s*\*\s*reference|reference\s*\*\s*(\S+)", rhs, flags=re.I)
    if rhs.lower() == "reference":
        return Constraint(name, sense, None, 1.0, at)
    if scaled:
        word = scaled.group(1) or scaled.group(2)
        try:
            factor = _number(word)
        except ValueError:
            raise ValueError(f"'{text}': the factor '{word}' of the reference is not a number") from None
        if not (math.isfinite(factor) and factor > 0):
            raise ValueError(f"'{text}': the factor of the reference must be a positive number, not {word}")
        return Constraint(name, sense, None, factor, at)
    try:
        value = _number(rhs)
    except ValueError:
        raise ValueError(
            f"'{text}': '{rhs}' is neither a number nor 'reference' (nor 'FACTOR * reference')"
        ) from None
    if not math.isfinite(value):
        raise ValueError(f"'{text}': the bound must be a finite number")
    return Constraint(name, sense, value, 1.0, at)


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
    from .format import result_display

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
