"""The study's published trends, each with its measure and its verdict, in one table.

A trend is read from a sweep of one ring variable over the study's range (the energy loss at
each value). Its **verdict** is the yes/no answer: does the sweep show the published
direction? Its **measure** is continuous: 0 where the trend appears, else the fraction of the
sweep's mean energy by which it goes the wrong way (what ``ringlube readings`` optimises; the
verdicts are not smooth). ``ringlube validate`` reports the verdicts, ``ringlube readings``
both; :data:`TRENDS` is the one list both use.

The measure is zero exactly when the verdict says yes, except on exact ties (equal energies),
where the verdict, a strict comparison, says no and the measure is zero; a sweep with a failed
point (NaN) measures :data:`FAILED_MEASURE`.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from .study.variables import DESIGN_RANGES

__all__ = ["Trend", "TRENDS", "FAILED_MEASURE", "trend_verdicts", "trend_measures"]

#: A trend measure where a sweep point failed (the whole energy the wrong way).
FAILED_MEASURE = 1.0


@dataclass(frozen=True)
class Trend:
    """One published trend: the ring variable swept, its range, what the study says, the
    points of the ``ringlube readings`` sweep, the verdict and the wrong-way amount.

    Parameters
    ----------
    name : str
        Ring variable swept.
    range : (float, float)
        Its range (the study's design range).
    says : str
        What the study says.
    points : int
        Points of the cold sweep of ``ringlube readings``.
    agrees : callable
        ``agrees(e)``: the verdict on the energies of a sweep (in sweep order).
    wrong : callable
        ``wrong(e, d)``: by how much (J) the sweep goes the wrong way; ``d = np.diff(e)``.

    Examples
    --------
    >>> t = TRENDS[0]
    >>> t.name, t.verdict([1.0, 2.0, 3.0]), round(t.measure([1.0, 2.0, 1.5]), 4)
    ('tension', True, 0.3333)
    """

    name: str
    range: tuple
    says: str
    points: int
    agrees: Callable
    wrong: Callable

    def verdict(self, e) -> bool:
        """Does the sweep (energies ``e``) show the published trend?"""
        return self.agrees(e)

    def measure(self, e) -> float:
        """The fraction of the mean energy by which the sweep goes the wrong way (0: the trend
        appears; :data:`FAILED_MEASURE` for a failed point or fewer than two points)."""
        e = np.asarray(e, float)
        if _failed(e):
            return FAILED_MEASURE
        return float(self.wrong(e, np.diff(e)) / np.mean(np.abs(e)))


def _failed(e: np.ndarray) -> bool:
    """A sweep with a failed point (NaN) or fewer than two points."""
    return not np.all(np.isfinite(e)) or len(e) < 2


def _width_agrees(e) -> bool:
    i = int(np.argmin(e))
    return 0 < i < len(e) - 1


#: The study's stated trends (order: tension, crown height, crown offset, width).
TRENDS = [
    Trend(
        "tension",
        DESIGN_RANGES["tension"],
        "energy loss rises with tension",
        5,
        lambda e: bool(np.all(np.diff(e) > 0)),
        lambda e, d: np.sum(np.maximum(0.0, -d)),  # the sum of the falls
    ),
    Trend(
        "crown_height",
        DESIGN_RANGES["crown_height"],
        "energy loss falls as crown height rises",
        5,
        lambda e: bool(np.all(np.diff(e) < 0)),
        lambda e, d: np.sum(np.maximum(0.0, d)),  # the sum of the rises
    ),
    Trend(
        "crown_offset",
        DESIGN_RANGES["crown_offset"],
        "a negative offset gives lower energy loss than a positive one",
        2,  # the verdict compares the two ends only
        lambda e: bool(e[0] < e[-1]),
        lambda e, d: max(0.0, e[0] - e[-1]),  # how much the negative end exceeds the positive
    ),
    Trend(
        "width",
        DESIGN_RANGES["width"],
        "energy loss has an interior optimum in width",
        5,
        _width_agrees,
        # how much the lowest interior point exceeds the lower end
        lambda e, d: max(0.0, np.min(e[1:-1]) - min(e[0], e[-1])) if len(e) > 2 else abs(d[0]),
    ),
]
_BY_NAME = {t.name: t for t in TRENDS}


def trend_verdicts(sweeps: dict) -> dict[str, bool]:
    """Does ringlube agree with each stated trend (on one sweep of each)?

    Parameters
    ----------
    sweeps : dict of str to (ndarray, ndarray)
        For every trend variable, its values and the energy losses.

    Returns
    -------
    dict of str to bool
        In the order of :data:`TRENDS`.

    Examples
    --------
    >>> x = np.linspace(0, 1, 3)
    >>> trend_verdicts({"tension": (x, [1, 2, 3]), "crown_height": (x, [3, 2, 1]),
    ...                 "crown_offset": (x, [1, 2, 3]), "width": (x, [2, 1, 2])})
    {'tension': True, 'crown_height': True, 'crown_offset': True, 'width': True}
    """
    return {t.name: t.verdict(sweeps[t.name][1]) for t in TRENDS}


def trend_measures(sweeps: dict) -> dict[str, float]:
    """The continuous measure of each published trend swept (:meth:`Trend.measure`).

    Parameters
    ----------
    sweeps : dict of str to (ndarray, ndarray)
        For each trend variable, its values and the energy losses.

    Returns
    -------
    dict of str to float
        In the order of ``sweeps``.

    Raises
    ------
    KeyError
        For a variable that is no published trend.

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
        t = _BY_NAME.get(name)
        if t is None:
            if _failed(np.asarray(e, float)):  # a failed sweep measures failed before the name
                out[name] = FAILED_MEASURE
                continue
            raise KeyError(f"no published trend '{name}'")
        out[name] = t.measure(e)
    return out
