"""The constraints of a study: ``&study constraints`` entries parsed and evaluated."""

from __future__ import annotations

import dataclasses
import math
from typing import TYPE_CHECKING

import numpy as np

from .errors import RinglubeError
from .study_variables import output_units

if TYPE_CHECKING:
    from .study_store import Study

__all__ = ["Constraint", "parse_constraint", "constraint_bounds", "feasibility"]


@dataclasses.dataclass(frozen=True)
class Constraint:
    """One ``&study constraints`` entry: ``NAME <= VALUE``, ``NAME >= VALUE`` or
    ``NAME <= reference`` (the reference design's true-model value on the same case).

    Attributes
    ----------
    name : str
        A scalar result (:func:`~ringlube.study_variables.output_units`).
    sense : str
        ``'<='`` or ``'>='``.
    value : float or None
        The bound in the result's unit, or None for ``reference``.

    Example
    -------
    >>> c = parse_constraint("oil_to_chamber <= reference")
    >>> c.uses_reference, c.violation(3.0, 2.0)
    (True, 0.5)
    """

    name: str
    sense: str
    value: float | None

    @property
    def uses_reference(self) -> bool:
        """Is the bound the reference design's value?"""
        return self.value is None

    def __str__(self) -> str:
        rhs = "reference" if self.value is None else f"{self.value:g}"
        return f"{self.name} {self.sense} {rhs}"

    def violation(self, y, bound: float):
        """pymoo's inequality ``g <= 0``: ``(y - bound) / scale`` for ``<=`` (negated for
        ``>=``), scaled by ``|bound|`` (1 if the bound is 0) so constraints of different
        units weigh alike.

        Parameters
        ----------
        y : float or ndarray
            The result.
        bound : float
            The bound (:attr:`value`, or the reference's value).

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


def parse_constraint(text: str) -> Constraint:
    """Parse ``'NAME <= VALUE'``, ``'NAME >= VALUE'``, ``'NAME <= reference'``.

    Parameters
    ----------
    text : str
        One entry of ``&study constraints``; VALUE in the result's unit
        (:func:`~ringlube.study_variables.output_units`).

    Returns
    -------
    Constraint

    Raises
    ------
    ValueError
        Saying what is wrong (the caller names file, group and variable).

    Example
    -------
    >>> str(parse_constraint(" fmep<=10 "))
    'fmep <= 10'
    """
    import re

    m = re.fullmatch(r"\s*([A-Za-z_]\w*)\s*(<=|>=)\s*(\S+)\s*", str(text))
    if not m:
        raise ValueError(f"'{text}' is not 'NAME <= VALUE', 'NAME >= VALUE' or 'NAME <= reference'")
    name, sense, rhs = m.group(1).lower(), m.group(2), m.group(3)
    units = output_units()
    if name not in units:
        raise ValueError(f"'{text}': unknown result '{name}' (known: {', '.join(units)})")
    if rhs.lower() == "reference":
        return Constraint(name, sense, None)
    try:
        value = float(rhs.lower().replace("d", "e"))
    except ValueError:
        raise ValueError(f"'{text}': '{rhs}' is neither a number nor 'reference'") from None
    if not math.isfinite(value):
        raise ValueError(f"'{text}': the bound must be a finite number")
    return Constraint(name, sense, value)


def constraint_bounds(study: Study, label: str) -> list[tuple]:
    """The constraints of a case with their bounds in the result's unit.

    A bound ``reference`` is the reference design's true-model value on the same case (for
    the scene, its weighted mean), so the reference must have been re-simulated
    (:func:`~ringlube.study_check.check_designs` with ``which=("reference",)``).

    Parameters
    ----------
    study : Study
    label : str
        Case label or ``scene``.

    Returns
    -------
    list of (Constraint, int, float)
        Each constraint, its column in the outputs, its bound.

    Raises
    ------
    RinglubeError
        The bound is the reference design's value and its run failed.

    Example
    -------
    >>> constraint_bounds(study, "cold")                     # doctest: +SKIP
    [(Constraint(name='oil_to_chamber', sense='<=', value=None), 5, 0.0123)]
    """
    s = study.s
    out = []
    for k in s.parsed_constraints:
        j = s.outputs.index(k.name)
        bound = k.value
        if k.uses_reference:
            ref = study.cases[label].reference
            bound = float(ref.f_true[0, j]) if ref is not None else float("nan")
            if not np.isfinite(bound):
                raise RinglubeError(
                    f"case '{label}': constraint '{k}': the reference design's run failed "
                    f"({ref.errors[0] if ref is not None else 'not run'}), so it bounds nothing"
                )
        out.append((k, j, float(bound)))
    return out


def feasibility(study: Study, label: str, values: np.ndarray) -> np.ndarray:
    """Which designs satisfy every constraint of a case (by the values given).

    Parameters
    ----------
    study : Study
    label : str
    values : ndarray, shape (k, len(outputs))
        Results of the designs (true model or surfaces); NaN counts as infeasible.

    Returns
    -------
    ndarray of bool, shape (k,)

    Example
    -------
    >>> feasibility(study, "cold", study.cases["cold"].chosen.f_true)   # doctest: +SKIP
    array([ True,  True, False,  True])
    """
    values = np.atleast_2d(values)
    ok = np.ones(len(values), bool)
    for k, j, b in constraint_bounds(study, label):
        with np.errstate(invalid="ignore"):
            ok &= np.isfinite(values[:, j]) & (np.asarray(k.violation(values[:, j], b)) <= 0)
    return ok
