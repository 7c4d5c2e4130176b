"""Synthetic in-cylinder gas-pressure traces for any engine, from a single-zone model.

The source study used measured pressure traces that it does not publish, so ringlube
ships synthetic ones (SPEC section 10), and ``ringlube gas`` makes one for your engine
when you have no measurement. The model, per crank angle psi (deg, 0 = TDC at the start
of intake, 360 = firing TDC):

* slider-crank volume ``V = Vc + (pi/4) B^2 x(psi)`` (the kernel's kinematics), with the
  clearance volume ``Vc = Vd / (rc - 1)`` from the compression ratio ``rc``;
* intake (0 .. ivc): manifold pressure; exhaust (evo + blowdown .. 720): exhaust pressure;
* closed cycle (ivc .. evo): first law of one ideal-gas zone with a constant ratio of
  specific heats ``gamma`` (also the polytropic exponent of compression and expansion:
  there is no separate wall heat transfer) and a Wiebe heat release
  ``x_b = 1 - exp(-a ((psi - soc)/duration)^(m+1))``,
  ``dp = (gamma - 1)/V dQ - gamma p/V dV`` (trapezoidal steps of 0.05 deg);
* blowdown (evo .. evo + blowdown): pressure relaxes to the exhaust value.

The total heat released ``Q`` sets the load; it comes from exactly one of

* ``peak_pressure``: ``Q`` such that the trace peaks there (the shipped traces);
* ``imep``: ``Q`` such that the net indicated mean effective pressure, the whole cycle's
  ``(closed integral of p dV) / Vd`` over 0..720 deg including the pumping loop, is the target;
* neither: the fuel in the trapped charge, ``Q = heat_fraction * m / (1 + AFR) * LHV``
  with ``m = p_manifold V(ivc) / (R T_intake)``; ``heat_fraction`` is the share of the fuel's
  energy that heats the gas (net of wall heat loss and incomplete combustion), and
  ``heat_fraction = 0`` gives the motored trace.

Everything is a plain parameter of :class:`GasModel`; a trace file records them in its
``#`` header, with the command that regenerates it (:mod:`ringlube.gas`: trace files,
figures and ``ringlube gas``, which with no arguments regenerates the shipped traces,
:data:`PRESETS`).
"""

from __future__ import annotations

import dataclasses
import functools
import math
from collections.abc import Callable

import numpy as np

__all__ = ["GasModel", "PRESETS", "CRF450R", "R_AIR", "trace", "imep", "heat_released", "burn_angles"]

#: Gas constant of the charge [J/(kg K)] (air; used only for the trapped mass).
R_AIR = 287.0

_FINE_STEP = 0.05  # deg, step of the closed-cycle integration

# the parameters every trace depends on, in the order of the shipped files' headers
_COMMON = (
    "bore",
    "crank_radius",
    "conrod_length",
    "compression_ratio",
    "manifold_pressure",
    "exhaust_pressure",
    "gamma",
    "ivc",
    "evo",
    "blowdown",
    "soc",
    "duration",
    "wiebe_a",
    "wiebe_m",
)
_FUEL = ("intake_temperature", "air_fuel_ratio", "lower_heating_value", "heat_fraction")


@dataclasses.dataclass(frozen=True)
class GasModel:
    """Parameters of the single-zone model (SI units: m, Pa, K, J/kg; angles in degrees).

    Attributes
    ----------
    bore, crank_radius, conrod_length : float
        Engine geometry [m] (the stroke is ``2 crank_radius``); no defaults, so no trace
        silently takes another engine's geometry.
    compression_ratio : float
        Geometric compression ratio (> 1).
    manifold_pressure, exhaust_pressure : float
        Cylinder pressure [Pa abs] during intake and exhaust; ``manifold_pressure`` is also
        the pressure at intake valve closing.
    gamma : float
        Ratio of specific heats, the polytropic exponent of compression and expansion.
    ivc, evo, blowdown : float
        Intake valve closing, exhaust valve opening [deg] and the crank angle over which
        the cylinder empties to the exhaust pressure.
    soc, duration, wiebe_a, wiebe_m : float
        Wiebe heat release: start of combustion and duration [deg], efficiency and form
        factors.
    peak_pressure, imep : float or None
        The load as a target [Pa]: the peak of the trace or the net IMEP (at most one).
    intake_temperature, air_fuel_ratio, lower_heating_value, heat_fraction : float
        The load from the fuel when neither target is given: charge temperature at intake
        valve closing [K], air-fuel mass ratio, the fuel's lower heating value [J/kg] and
        the share of the fuel's energy that heats the gas (0: motored).
    speed_rpm : float or None
        Recorded only: the model works in crank angle and has no heat transfer, so speed
        does not change the trace (give the burn ``duration`` your speed has).

    Examples
    --------
    >>> m = GasModel(**CRF450R, peak_pressure=50e5)
    >>> float(m.volume([180.0])[0]) > float(m.volume([0.0])[0])
    True
    >>> GasModel(**CRF450R, peak_pressure=50e5, imep=8e5)
    Traceback (most recent call last):
    ...
    ValueError: peak_pressure, imep: give at most one load target
    """

    bore: float
    crank_radius: float
    conrod_length: float
    compression_ratio: float
    manifold_pressure: float = 1.0e5
    exhaust_pressure: float = 1.1e5
    gamma: float = 1.32
    ivc: float = 200.0  # intake valve closing
    evo: float = 490.0  # exhaust valve opening
    blowdown: float = 50.0  # deg over which the cylinder empties to exhaust pressure
    soc: float = 340.0  # start of combustion (50 % burned 8.5 deg after firing TDC)
    duration: float = 55.0  # combustion duration
    wiebe_a: float = 5.0
    wiebe_m: float = 2.0
    peak_pressure: float | None = None
    imep: float | None = None
    intake_temperature: float = 330.0
    air_fuel_ratio: float = 14.7
    lower_heating_value: float = 43.4e6
    heat_fraction: float = 0.75
    speed_rpm: float | None = None

    def __post_init__(self):
        for name, why in self._problems():
            raise ValueError(f"{name}: {why}")

    def _problems(self):
        positive = ("bore", "crank_radius", "conrod_length", "manifold_pressure", "exhaust_pressure")
        for name in (*positive, "duration", "blowdown", "lower_heating_value", "intake_temperature"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0):
                yield name, f"must be a positive number, not {value}"
        for name in ("wiebe_a", "air_fuel_ratio", "heat_fraction"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value >= 0):
                yield name, f"must be a number >= 0, not {value}"
        if not self.wiebe_m > -1:
            yield "wiebe_m", f"must be > -1, not {self.wiebe_m}"
        if self.conrod_length <= self.crank_radius:
            yield "conrod_length", "must be longer than the crank radius (half the stroke)"
        if not (math.isfinite(self.compression_ratio) and self.compression_ratio > 1):
            yield "compression_ratio", f"must be > 1, not {self.compression_ratio}"
        if not (math.isfinite(self.gamma) and 1 < self.gamma < 2):
            yield "gamma", f"must be between 1 and 2, not {self.gamma}"
        if not 0 < self.ivc < self.evo < 720:
            yield "ivc, evo", f"need 0 < ivc < evo < 720 deg, not {self.ivc}, {self.evo}"
        if self.evo + self.blowdown > 720:
            yield "blowdown", "evo + blowdown must not pass 720 deg"
        if not self.ivc <= self.soc < self.evo:
            yield "soc", f"start of combustion must lie between ivc and evo, not {self.soc}"
        if self.peak_pressure is not None and self.imep is not None:
            yield "peak_pressure, imep", "give at most one load target"
        for name in ("peak_pressure", "imep", "speed_rpm"):
            value = getattr(self, name)
            if value is not None and not (math.isfinite(value) and value > 0):
                yield name, f"must be a positive number, not {value}"

    @property
    def load(self) -> str:
        """How the heat released is set: 'peak_pressure', 'imep' or 'fuel'.

        >>> GasModel(**CRF450R).load, GasModel(**CRF450R, imep=9e5).load
        ('fuel', 'imep')
        """
        if self.peak_pressure is not None:
            return "peak_pressure"
        if self.imep is not None:
            return "imep"
        return "fuel"

    @property
    def swept_volume(self) -> float:
        """Swept volume Vd [m^3].

        >>> round(GasModel(86e-3, 43e-3, 143.5e-3, 10.5).swept_volume * 1e6, 1)
        499.6
        """
        return np.pi / 4 * self.bore**2 * 2 * self.crank_radius

    def parameters(self) -> dict[str, float]:
        """The parameters the trace depends on (the header of its file), in order.

        >>> list(GasModel(**CRF450R, imep=9e5).parameters())[-1]
        'imep'
        """
        names = [*_COMMON, self.load] if self.load != "fuel" else [*_COMMON, *_FUEL]
        if self.speed_rpm is not None:
            names.append("speed_rpm")
        return {n: getattr(self, n) for n in names}

    def volume(self, psi_deg: np.ndarray) -> np.ndarray:
        """Cylinder volume [m^3] at crank angles [deg] (the kernel's slider-crank)."""
        from . import _kernel

        psi = np.atleast_1d(np.asarray(psi_deg, dtype=float))
        x, _ = _kernel.rl_kinematics(psi, self.crank_radius, self.conrod_length, 1.0)
        area = np.pi / 4 * self.bore**2
        vd = area * 2 * self.crank_radius
        vc = vd / (self.compression_ratio - 1)
        return vc + area * x

    def burned(self, psi_deg: float) -> float:
        """Wiebe mass fraction burned at a crank angle [deg].

        >>> m = GasModel(**CRF450R)
        >>> m.burned(300.0), round(m.burned(m.soc + m.duration), 6)   # 1 - exp(-a) at the end
        (0.0, 0.993262)
        """
        if psi_deg <= self.soc:
            return 0.0
        z = (psi_deg - self.soc) / self.duration
        return float(1.0 - np.exp(-self.wiebe_a * z ** (self.wiebe_m + 1)))

    def fuel_heat(self) -> float:
        """Heat released by the trapped charge's fuel [J] (the 'fuel' load).

        >>> round(GasModel(**CRF450R, heat_fraction=0).fuel_heat(), 6)
        0.0
        """
        mass = self.manifold_pressure * float(self.volume([self.ivc])[0]) / (R_AIR * self.intake_temperature)
        return self.heat_fraction * mass / (1 + self.air_fuel_ratio) * self.lower_heating_value


#: The source study's engine (Honda CRF450R): compression ratio 12, bore 96 mm, the
#: study's crank radius and conrod.
CRF450R = dict(bore=96e-3, crank_radius=31.5e-3, conrod_length=107e-3, compression_ratio=12.0)

#: Shipped operating points (see inputs/README.md).
PRESETS: dict[str, GasModel] = {
    "crf450r_4000rpm_full": GasModel(**CRF450R, manifold_pressure=1.0e5, peak_pressure=60e5, soc=342.0),
    "crf450r_3000rpm_half": GasModel(**CRF450R, manifold_pressure=0.55e5, peak_pressure=35e5, soc=348.0),
}


def _closed_cycle(m: GasModel, psi: np.ndarray, q_total: float) -> np.ndarray:
    """Integrate the first law from ivc to evo on the fine grid ``psi``."""
    v = m.volume(psi)
    p = np.empty_like(psi)
    p[0] = m.manifold_pressure
    xb_prev = 0.0
    for i in range(1, len(psi)):
        xb = m.burned(psi[i])
        dq = q_total * (xb - xb_prev)
        xb_prev = xb
        dv = v[i] - v[i - 1]
        vm = 0.5 * (v[i] + v[i - 1])
        # trapezoidal in p for the compression term (stable for any step)
        g = m.gamma
        p[i] = (p[i - 1] * (1 - 0.5 * g * dv / vm) + (g - 1) * dq / vm) / (1 + 0.5 * g * dv / vm)
    return p


def _fine(m: GasModel) -> np.ndarray:
    return np.linspace(m.ivc, m.evo, int((m.evo - m.ivc) / _FINE_STEP) + 1)


def _assemble(m: GasModel, psi: np.ndarray, fine: np.ndarray, pc: np.ndarray) -> np.ndarray:
    """The whole cycle on ``psi`` from the closed part ``pc`` on ``fine``."""
    p_evo = pc[-1]
    p = np.full_like(psi, m.exhaust_pressure)
    p[psi <= m.ivc] = m.manifold_pressure
    closed = (psi > m.ivc) & (psi <= m.evo)
    p[closed] = np.interp(psi[closed], fine, pc)
    blow = (psi > m.evo) & (psi <= m.evo + m.blowdown)
    frac = (psi[blow] - m.evo) / m.blowdown
    p[blow] = m.exhaust_pressure + (p_evo - m.exhaust_pressure) * np.exp(-5.0 * frac) * (1 - frac)
    return p


def _bisect(f: Callable[[float], float], target: float, what: str) -> float:
    """The heat ``q >= 0`` with ``f(q) = target`` for an increasing ``f``."""
    if f(0.0) >= target:
        raise ValueError(f"{what}: {target:g} Pa is not above the motored trace's {f(0.0):g} Pa")
    lo, hi = 0.0, 1.0e4
    while f(hi) < target:
        hi *= 2
        if hi > 1e9:
            raise ValueError(f"{what}: {target:g} Pa is out of reach of the model")
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if f(mid) < target else (lo, mid)
    return 0.5 * (lo + hi)


def imep(psi: np.ndarray, p: np.ndarray, m: GasModel) -> float:
    """Net indicated mean effective pressure [Pa] of a trace: ``(closed integral of p dV)
    / Vd`` over 0..720 deg (trapezoidal in V), for the engine of ``m``.

    Parameters
    ----------
    psi, p : ndarray
        Crank angle [deg] from 0 to 720 and absolute pressure [Pa].
    m : GasModel
        The engine (geometry only).

    Examples
    --------
    >>> m = GasModel(**CRF450R)
    >>> psi = np.linspace(0.0, 720.0, 1441)
    >>> abs(imep(psi, np.full_like(psi, 1e5), m)) < 1e-6    # no work at constant pressure
    True
    """
    v = m.volume(psi)
    return float(np.sum(0.5 * (p[1:] + p[:-1]) * np.diff(v)) / m.swept_volume)


@functools.lru_cache(maxsize=32)  # GasModel is frozen: the same model, the same heat
def heat_released(m: GasModel, step: float = 0.5) -> float:
    """Total heat released per cycle [J] for the model's load.

    Parameters
    ----------
    m : GasModel
    step : float
        Crank-angle step [deg] of the trace whose IMEP is the target.

    >>> heat_released(GasModel(**CRF450R, heat_fraction=0.0))
    0.0
    """
    fine = _fine(m)
    if m.load == "peak_pressure":
        return _bisect(lambda q: float(_closed_cycle(m, fine, q).max()), m.peak_pressure, "peak_pressure")
    if m.load == "imep":
        psi = np.arange(0.0, 720.0 + step / 2, step)
        return _bisect(
            lambda q: imep(psi, _assemble(m, psi, fine, _closed_cycle(m, fine, q)), m), m.imep, "imep"
        )
    return m.fuel_heat()


def trace(m: GasModel, step: float = 0.5) -> tuple[np.ndarray, np.ndarray]:
    """Crank angle (deg, 0..720 inclusive) and absolute pressure (Pa) of one cycle.

    Parameters
    ----------
    m : GasModel
    step : float
        Crank-angle step [deg].

    Returns
    -------
    (ndarray, ndarray)

    Raises
    ------
    ValueError
        If a load target cannot be reached (an IMEP below the motored trace's).

    Examples
    --------
    >>> psi, p = trace(PRESETS["crf450r_4000rpm_full"])
    >>> round(float(p.max()) / 1e5, 3), float(psi[-1])
    (60.0, 720.0)
    """
    psi = np.arange(0.0, 720.0 + step / 2, step)
    fine = _fine(m)
    pc = _closed_cycle(m, fine, heat_released(m, step))
    return psi, _assemble(m, psi, fine, pc)


def burn_angles(m: GasModel, fractions=(0.1, 0.5, 0.9)) -> list[float]:
    """Crank angles [deg] at which the Wiebe function reaches the mass fractions burned.

    Parameters
    ----------
    m : GasModel
    fractions : sequence of float
        Mass fractions burned, each in [0, 1).

    Examples
    --------
    >>> [round(a, 1) for a in burn_angles(PRESETS["crf450r_4000rpm_full"])]
    [357.2, 370.5, 384.5]
    """
    out = []
    for x in fractions:
        z = (-math.log(1.0 - x) / m.wiebe_a) ** (1.0 / (m.wiebe_m + 1)) if m.wiebe_a > 0 else math.inf
        out.append(m.soc + z * m.duration)
    return out
