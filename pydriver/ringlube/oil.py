"""The oil a case runs with: its viscosity against temperature and pressure (the kernel's
Roelands law, with the inputs the kernel uses), an SAE J300 grade's viscosities, and the
Walther equation of ASTM D341 to compare with.

A case gives its oil by ``&lubricant eta0, theta0, beta`` (the source study's), or by the
kinematic viscosities of a data sheet (``kv40``, ``kv100``) or a grade (``grade``), through
which the kernel puts its law (docs/model.md, "Viscosity").

>>> from ringlube import Case, oil
>>> case = Case({"lubricant": {"kv40": 61.0, "kv100": 10.4, "oil_density": 850.0}})
>>> [round(float(v), 12) for v in oil.kinematic_viscosity(case, [313.15, 373.15])]
[61.0, 10.4]
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from .errors import InputError

__all__ = ["Grade", "grade", "viscosity", "kinematic_viscosity", "walther"]


class Grade(NamedTuple):
    """An SAE J300 grade's kinematic viscosities [mm^2/s]: at 40 and 100 degC as the kernel
    takes them, and the grade's window at 100 degC (``kv100_min`` up to below ``kv100_max``).

    Examples
    --------
    >>> Grade(64.85, 10.9, 9.3, 12.5).kv100
    10.9
    """

    kv40: float
    kv100: float
    kv100_min: float
    kv100_max: float


def grade(name: str) -> Grade:
    """The kinematic viscosities the kernel takes for an SAE J300 grade.

    Parameters
    ----------
    name : str
        ``'5W-30'``, ``'40'``, ... (``&lubricant grade``).

    Returns
    -------
    Grade

    Raises
    ------
    InputError
        For a name that is not a J300 grade.

    Examples
    --------
    >>> g = grade("5W-30")
    >>> g.kv100, (g.kv100_min, g.kv100_max), round(g.kv40, 2)
    (10.9, (9.3, 12.5), 64.85)
    """
    from . import _kernel
    from .case.kernel import kernel_text

    kv40, kv100, lo, hi, code, message = _kernel.rl_grade(name.encode())
    if code:
        raise InputError(f"&lubricant grade: {kernel_text(message)}")
    return Grade(float(kv40), float(kv100), float(lo), float(hi))


def viscosity(case, temperature, pressure=0.0) -> np.ndarray:
    """Dynamic viscosity [Pa s] of a case's oil at temperatures [K] and absolute pressures
    [Pa]: the kernel's law with the inputs it uses (a grade's or data sheet's fit included).

    Parameters
    ----------
    case : Case
        Its ``&lubricant`` inputs (and defaults).
    temperature, pressure : float or array_like
        Broadcast together.

    Returns
    -------
    ndarray

    Examples
    --------
    >>> from ringlube import Case
    >>> float(viscosity(Case(), 313.15)[0])   # the source study's eta0 at its theta0
    0.05
    """
    from . import _kernel

    t, p = np.broadcast_arrays(np.atleast_1d(np.asarray(temperature, float)), np.asarray(pressure, float))
    value = {name: float(case.value("lubricant", name)) for name in ("eta0", "theta0", "alpha", "beta")}
    return np.asarray(
        _kernel.rl_viscosity(
            t.ravel(), p.ravel(), value["eta0"], value["theta0"], value["alpha"], value["beta"]
        )
    ).reshape(t.shape)


def kinematic_viscosity(case, temperature) -> np.ndarray:
    """Kinematic viscosity [mm^2/s] of a case's oil at temperatures [K] and p = 0: the dynamic
    viscosity over ``&lubricant oil_density`` (the density the kernel converts with).

    Parameters
    ----------
    case : Case
        Its ``&lubricant`` inputs (and defaults).
    temperature : float or array_like
        [K].

    Returns
    -------
    ndarray

    Examples
    --------
    >>> from ringlube import Case
    >>> case = Case({"lubricant": {"grade": "5W-30"}})
    >>> round(float(kinematic_viscosity(case, 373.15)[0]), 9)   # the J300 window's centre
    10.9
    """
    rho = float(case.value("lubricant", "oil_density"))
    return viscosity(case, temperature) / rho * 1e6


def walther(kv40: float, kv100: float, temperature) -> np.ndarray:
    """Kinematic viscosity [mm^2/s] at temperatures [K] by the Walther equation of ASTM D341,
    ``log10 log10(nu + 0.7) = A - B log10 T``, through (313.15 K, kv40) and (373.15 K, kv100)
    (the standard's form for nu >= 2 mm^2/s).

    Parameters
    ----------
    kv40, kv100 : float
        Kinematic viscosities at 40 and 100 degC [mm^2/s].
    temperature : float or array_like
        [K].

    Returns
    -------
    ndarray

    Examples
    --------
    >>> [round(float(v), 9) for v in walther(61.0, 10.4, [313.15, 373.15])]
    [61.0, 10.4]
    """
    t = np.atleast_1d(np.asarray(temperature, float))
    z1, z2 = (np.log10(np.log10(v + 0.7)) for v in (kv40, kv100))
    b = (z1 - z2) / (np.log10(373.15) - np.log10(313.15))
    a = z1 + b * np.log10(313.15)
    return 10 ** (10 ** (a - b * np.log10(t))) - 0.7
