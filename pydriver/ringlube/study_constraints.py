"""The constraints of a study: ``&study constraints`` entries parsed and evaluated."""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from .study_variables import output_units

__all__ = ["Constraint", "parse_constraint"]


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
