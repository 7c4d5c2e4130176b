"""The constraints of a study: ``&study constraints`` entries parsed and evaluated.

An entry is ``NAME <= RHS`` or ``NAME >= RHS``, optionally followed by ``at LABEL``:

* RHS is a number in the result's unit, ``reference`` (the reference design's true-model value)
  or ``FACTOR * reference`` (that value times a positive number, e.g. ``1.05 * reference``);
* without ``at`` the constraint holds at every operating point (each case on its own values);
  ``at LABEL`` holds at that case only; ``at scene`` holds for the weighted scene's mean.

What binds the designs of a case or of the scene, and whether they satisfy it, is
:mod:`ringlube.study.bounds`.
"""

from __future__ import annotations

import dataclasses
import math
import re

import numpy as np

from .variables import output_units

__all__ = ["Constraint", "parse_constraint"]

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
    low, high = _range(name, units[name])
    if (sense == "<=" and value < low) or (sense == ">=" and value > high):
        span = f"{_text(low)} .. {_text(high)} {units[name]}" if high < math.inf else f"at least {_text(low)}"
        raise ValueError(f"'{text}' never holds: {name} is {span}")
    return Constraint(name, sense, value, 1.0, at)


def _range(name: str, unit: str) -> tuple[float, float]:
    """The values a result can take by its definition: a share 0 .. 100 %, a ratio over a
    limit or a count at least 0; any other result unbounded.

    Example
    -------
    >>> _range("light_gap_share", "%"), _range("conformability", "1"), _range("fmep", "Pa")
    ((0.0, 100.0), (0.0, inf), (-inf, inf))
    """
    if name.endswith("_share") and unit == "%":
        return 0.0, 100.0
    if name in ("conformability", "flutter_events"):
        return 0.0, math.inf
    return -math.inf, math.inf
