"""Synthetic in-cylinder gas-pressure traces for any engine, from a single-zone model.

The source study used measured pressure traces that it does not publish, so ringlube
ships synthetic ones, and ``ringlube gas`` makes one for your engine when you have no
measurement. The model, per crank angle psi (deg, 0 = TDC at the start of intake, 360 =
firing TDC):

* slider-crank volume ``V = Vc + (pi/4) B^2 x(psi)`` (the kernel's kinematics), with the
  clearance volume ``Vc = Vd / (rc - 1)`` from the compression ratio ``rc``;
* intake (0 .. ivc): manifold pressure; exhaust (evo + blowdown .. 720): exhaust pressure;
* closed cycle (ivc .. evo): first law of one ideal-gas zone with a constant ratio of
  specific heats ``gamma``, a Wiebe heat release
  ``x_b = 1 - exp(-a ((psi - soc)/duration)^(m+1))`` and, optionally, wall heat loss
  ``dQ_w/dt = h A (T - T_w)`` by Woschni's or Hohenberg's correlation (:func:`heat_transfer_coefficient`),
  ``dp = (gamma - 1)/V (dQ - dQ_w) - gamma p/V dV`` (trapezoidal steps of 0.05 deg; the wall
  loss by Heun's predictor-corrector, also second order);
* blowdown (evo .. evo + blowdown): pressure relaxes to the exhaust value.

Without wall heat loss (``heat_transfer = 'none'``, the shipped traces) ``gamma`` is also
the polytropic exponent of compression and expansion. With it, the gas temperature is
``T = T_ivc p V / (p_ivc V_ivc)`` (ideal gas, the trapped charge at the intake temperature),
the wall area ``A = 2 (pi/4) B^2 + 4 V / B`` (head and piston crown as flat discs, the liner
above the piston) and the time per crank degree ``1 / (6 N)`` s, so the engine speed
``speed_rpm`` is required.

The total heat released ``Q`` sets the load; it comes from

* ``peak_pressure``: ``Q`` such that the trace peaks there (the shipped traces);
* ``imep``: ``Q`` such that the net indicated mean effective pressure, the whole cycle's
  ``(closed integral of p dV) / Vd`` over 0..720 deg including the pumping loop, is the target;
* both (with wall heat loss): ``Q`` and the factor ``heat_transfer_scale`` on the
  correlation's coefficient, so that the trace has both the peak and the IMEP of an engine;
* neither: the fuel in the trapped charge, ``Q = heat_fraction * m / (1 + AFR) * LHV``
  with ``m = p_manifold V(ivc) / (R T_intake)``; ``heat_fraction`` is the share of the fuel's
  energy that heats the gas: without wall heat loss net of it (default 0.75), with it the
  combustion efficiency alone (default 0.95); ``heat_fraction = 0`` gives the motored trace
  (no combustion, for overrun: a closed throttle with the fuel cut).

Every parameter is checked against a plausible range (:data:`LIMITS`, the engine geometry
and speed against the kernel's input table), so that a value in the wrong unit (a bore in
mm, a pressure in bar) is refused by name. Everything is a plain parameter of
:class:`GasModel`; a trace file records them in its ``#`` header, with the command that
regenerates it (:mod:`ringlube.gas`: trace files, figures and ``ringlube gas``).
"""

from __future__ import annotations

import dataclasses
import functools
import math
from collections.abc import Callable

import numpy as np

__all__ = [
    "GasModel",
    "PRESETS",
    "CRF450R",
    "R_AIR",
    "LIMITS",
    "HEAT_TRANSFER",
    "limits",
    "range_problem",
    "trace",
    "imep",
    "heat_released",
    "wall_heat",
    "load_solution",
    "heat_transfer_coefficient",
    "burn_angles",
]

#: Gas constant of the charge [J/(kg K)] (air; used only for the trapped mass).
R_AIR = 287.0

_FINE_STEP = 0.05  # deg, step of the closed-cycle integration

#: Wall heat-transfer correlations: 'none', Woschni (1967) and Hohenberg (1979).
HEAT_TRANSFER = ("none", "woschni", "hohenberg")

#: Largest factor on the correlation's coefficient a fit to peak pressure and IMEP may need.
MAX_HEAT_TRANSFER_SCALE = 20.0

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
_COMBUSTION = ("soc", "duration", "wiebe_a", "wiebe_m")
_FUEL = ("intake_temperature", "air_fuel_ratio", "lower_heating_value", "heat_fraction")
_WALL = ("heat_transfer", "wall_temperature", "heat_transfer_scale")

#: Plausible range (inclusive) and unit of each parameter that is not engine geometry or
#: speed (those are the kernel's: ``&engine`` and ``&operating speed_rpm`` of its input table).
LIMITS: dict[str, tuple[float, float, str]] = {
    "compression_ratio": (2.0, 40.0, ""),
    "manifold_pressure": (1.0e3, 1.0e7, "Pa"),
    "exhaust_pressure": (1.0e3, 1.0e7, "Pa"),
    "gamma": (1.05, 1.67, ""),
    "ivc": (90.0, 330.0, "deg"),
    "evo": (390.0, 690.0, "deg"),
    "blowdown": (5.0, 180.0, "deg"),
    "soc": (270.0, 405.0, "deg"),
    "duration": (5.0, 180.0, "deg"),
    "wiebe_a": (1.0, 20.0, ""),
    "wiebe_m": (0.0, 10.0, ""),
    "peak_pressure": (1.0e4, 1.0e8, "Pa"),
    "imep": (1.0e4, 1.0e7, "Pa"),
    "intake_temperature": (200.0, 1000.0, "K"),
    "air_fuel_ratio": (1.0, 200.0, ""),
    "lower_heating_value": (1.0e6, 1.5e8, "J/kg"),
    "heat_fraction": (0.0, 1.0, ""),
    "wall_temperature": (250.0, 1000.0, "K"),
    "heat_transfer_scale": (0.0, MAX_HEAT_TRANSFER_SCALE, ""),
}

# geometry and speed: (kernel group, kernel name, factor from the kernel's value)
_KERNEL_RANGES = {
    "bore": ("engine", "bore_radius", 2.0),
    "crank_radius": ("engine", "crank_radius", 1.0),
    "conrod_length": ("engine", "conrod_length", 1.0),
    "speed_rpm": ("operating", "speed_rpm", 1.0),
}


def limits(name: str) -> tuple[float, float, str]:
    """Plausible range (inclusive) and unit of a parameter of :class:`GasModel`.

    Engine geometry and speed come from the kernel's input table (the bore is twice its
    ``bore_radius``), everything else from :data:`LIMITS`.

    Parameters
    ----------
    name : str
        A numeric parameter of :class:`GasModel`.

    Examples
    --------
    >>> limits("bore")
    (0.002, 2.0, 'm')
    """
    if name in _KERNEL_RANGES:
        from ..tables import INPUTS

        group, var, k = _KERNEL_RANGES[name]
        spec = INPUTS[group, var]
        return spec.lower * k, spec.upper * k, spec.unit
    return LIMITS[name]


def range_problem(name: str, value: float, factor: float = 1.0) -> str | None:
    """Why ``value`` is not a plausible ``name`` (None if it is), with a hint at the unit
    (a length that fits in mm, a pressure that fits in bar).

    Parameters
    ----------
    name : str
        A parameter of :class:`GasModel`.
    value : float
    factor : float
        ``value`` is ``factor`` times the parameter (2 for a stroke against the crank radius).

    Examples
    --------
    >>> range_problem("bore", 86.0)
    'must be within 0.002 .. 2 m, not 86 (in mm? give metres: 0.086)'
    >>> range_problem("manifold_pressure", 1.0)
    'must be within 1000 .. 1e+07 Pa, not 1 (in bar? give Pa: 100000)'
    """
    lo, hi, unit = limits(name)
    lo, hi = lo * factor, hi * factor
    if math.isfinite(value) and lo <= value <= hi:
        return None
    u = f" {unit}" if unit else ""
    why = f"must be within {lo:g} .. {hi:g}{u}, not {value:g}"
    if math.isfinite(value) and unit == "m" and lo <= value / 1000 <= hi:
        why += f" (in mm? give metres: {value / 1000:g})"
    elif math.isfinite(value) and unit == "Pa" and value < lo and lo <= value * 1e5 <= hi:
        why += f" (in bar? give Pa: {value * 1e5:g})"
    return why


@dataclasses.dataclass(frozen=True)
class GasModel:
    """Parameters of the single-zone model (SI units: m, Pa, K, J/kg; angles in degrees).

    Attributes
    ----------
    bore, crank_radius, conrod_length : float
        Engine geometry [m] (the stroke is ``2 crank_radius``); no defaults, so no trace
        silently takes another engine's geometry.
    compression_ratio : float
        Geometric compression ratio.
    manifold_pressure, exhaust_pressure : float
        Cylinder pressure [Pa abs] during intake and exhaust; ``manifold_pressure`` is also
        the pressure at intake valve closing.
    gamma : float
        Ratio of specific heats (without wall heat loss also the polytropic exponent of
        compression and expansion).
    ivc, evo, blowdown : float
        Intake valve closing, exhaust valve opening [deg] and the crank angle over which
        the cylinder empties to the exhaust pressure.
    soc, duration, wiebe_a, wiebe_m : float
        Wiebe heat release: start of combustion and duration [deg], efficiency and form
        factors (the combustion must end by exhaust valve opening).
    peak_pressure, imep : float or None
        The load as targets [Pa]: the peak of the trace, the net IMEP, or both (with wall
        heat loss).
    intake_temperature, air_fuel_ratio, lower_heating_value, heat_fraction : float
        Charge temperature at intake valve closing [K] (also the reference of the gas
        temperature with wall heat loss), and the load from the fuel when no target is
        given: air-fuel mass ratio, the fuel's lower heating value [J/kg] and the share of
        the fuel's energy that heats the gas (0: motored; default 0.75 without wall heat
        loss, 0.95 with it).
    speed_rpm : float or None
        Engine speed [r/min]: sets the time the wall heat loss acts; without wall heat loss
        recorded only (the model then works in crank angle alone: give the burn
        ``duration`` your speed has).
    heat_transfer : str
        Wall heat loss: 'none', 'woschni' or 'hohenberg' (:func:`heat_transfer_coefficient`).
    wall_temperature : float
        Mean temperature of the chamber walls [K].
    heat_transfer_scale : float or None
        Factor on the correlation's coefficient (default 1; fitted when both
        ``peak_pressure`` and ``imep`` are given).

    Examples
    --------
    >>> m = GasModel(**CRF450R, peak_pressure=50e5)
    >>> float(m.volume([180.0])[0]) > float(m.volume([0.0])[0])
    True
    >>> GasModel(**CRF450R, peak_pressure=50e5, imep=8e5)
    Traceback (most recent call last):
    ...
    ValueError: peak_pressure, imep: both targets need wall heat loss (heat_transfer 'woschni' or 'hohenberg')
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
    heat_fraction: float | None = None
    speed_rpm: float | None = None
    heat_transfer: str = "none"
    wall_temperature: float = 450.0
    heat_transfer_scale: float | None = None

    def __post_init__(self):
        for name, why in self._problems():
            raise ValueError(f"{name}: {why}")
        if self.heat_fraction is None:  # the default depends on whether the wall loss is modelled
            object.__setattr__(self, "heat_fraction", 0.75 if self.heat_transfer == "none" else 0.95)

    def _problems(self):
        if self.heat_transfer not in HEAT_TRANSFER:
            yield "heat_transfer", f"'{self.heat_transfer}' is not one of {', '.join(HEAT_TRANSFER)}"
            return
        for f in dataclasses.fields(self):
            value = getattr(self, f.name)
            if f.name == "heat_transfer" or value is None:
                continue
            if not isinstance(value, (int, float)) or isinstance(value, bool):
                yield f.name, f"must be a number, not {value!r}"
                return
            why = range_problem(f.name, float(value))
            if why:
                yield f.name, why
        if self.conrod_length <= self.crank_radius:
            yield "conrod_length", "must be longer than the crank radius (half the stroke)"
        if not self.ivc < self.evo:
            yield "ivc, evo", f"need ivc < evo, not {self.ivc:g}, {self.evo:g}"
        if self.evo + self.blowdown > 720:
            yield "blowdown", f"evo + blowdown must not pass 720 deg ({self.evo:g} + {self.blowdown:g})"
        if self.heat_fraction != 0 or self.peak_pressure is not None or self.imep is not None:
            if not self.ivc <= self.soc:
                yield (
                    "soc",
                    f"the combustion must start after intake valve closing ({self.ivc:g} deg), "
                    f"not at {self.soc:g}",
                )
            if self.soc + self.duration > self.evo:
                yield (
                    "duration",
                    f"the combustion must end by exhaust valve opening: soc + duration = "
                    f"{self.soc + self.duration:g} deg is after evo = {self.evo:g} deg",
                )
        wall = self.heat_transfer != "none"
        if self.peak_pressure is not None and self.imep is not None and not wall:
            yield (
                "peak_pressure, imep",
                "both targets need wall heat loss (heat_transfer 'woschni' or 'hohenberg')",
            )
        if self.heat_fraction == 0 and (self.peak_pressure is not None or self.imep is not None):
            yield "heat_fraction", "0 is the motored trace (no combustion); it has no load target"
        if wall and self.speed_rpm is None:
            yield "speed_rpm", "the wall heat loss acts over time: give the engine speed"
        if self.heat_transfer_scale is not None:
            if not wall:
                yield "heat_transfer_scale", "scales the wall heat loss: give heat_transfer too"
            elif self.peak_pressure is not None and self.imep is not None:
                yield (
                    "heat_transfer_scale",
                    "is fitted to the peak pressure and IMEP; give at most two of the three",
                )

    @property
    def load(self) -> str:
        """How the heat released is set: 'peak_pressure', 'imep', 'peak_pressure and imep',
        'fuel' or 'motored'.

        >>> GasModel(**CRF450R).load, GasModel(**CRF450R, imep=9e5).load
        ('fuel', 'imep')
        >>> GasModel(**CRF450R, heat_fraction=0).load
        'motored'
        """
        if self.peak_pressure is not None and self.imep is not None:
            return "peak_pressure and imep"
        if self.peak_pressure is not None:
            return "peak_pressure"
        if self.imep is not None:
            return "imep"
        return "motored" if self.heat_fraction == 0 else "fuel"

    @property
    def motored(self) -> bool:
        """No combustion (``heat_fraction = 0`` and no load target)."""
        return self.load == "motored"

    @property
    def swept_volume(self) -> float:
        """Swept volume Vd [m^3].

        >>> round(GasModel(86e-3, 43e-3, 143.5e-3, 10.5).swept_volume * 1e6, 1)
        499.6
        """
        return np.pi / 4 * self.bore**2 * 2 * self.crank_radius

    @property
    def mean_piston_speed(self) -> float:
        """Mean piston speed [m/s], ``2 stroke N / 60`` (0 without a speed).

        >>> GasModel(86e-3, 43e-3, 143.5e-3, 10.5, speed_rpm=3000).mean_piston_speed
        8.6
        """
        return 4 * self.crank_radius * (self.speed_rpm or 0.0) / 60.0

    def parameters(self) -> dict[str, float | str]:
        """The parameters the trace depends on (the header of its file), in order.

        >>> list(GasModel(**CRF450R, imep=9e5).parameters())[-1]
        'imep'
        >>> "soc" in GasModel(**CRF450R, heat_fraction=0).parameters()
        False
        """
        load = self.load
        if load in ("fuel", "motored"):
            names = [*_COMMON, *_FUEL]
        else:
            names = [*_COMMON, *(t for t in ("peak_pressure", "imep") if getattr(self, t) is not None)]
        if load == "motored":  # no combustion: neither its timing nor the fuel matter
            names = [n for n in names if n not in (*_COMBUSTION, "air_fuel_ratio", "lower_heating_value")]
            if self.heat_transfer == "none":
                names.remove("intake_temperature")
        if self.speed_rpm is not None:
            names.append("speed_rpm")
        if self.heat_transfer != "none":
            if "intake_temperature" not in names:
                names.append("intake_temperature")
            names += [n for n in _WALL if getattr(self, n) is not None]
        return {n: getattr(self, n) for n in names}

    def volume(self, psi_deg: np.ndarray) -> np.ndarray:
        """Cylinder volume [m^3] at crank angles [deg] (the kernel's slider-crank)."""
        from .. import _kernel

        psi = np.atleast_1d(np.asarray(psi_deg, dtype=float))
        x, _ = _kernel.rl_kinematics(psi, self.crank_radius, self.conrod_length, 1.0)
        area = np.pi / 4 * self.bore**2
        vd = area * 2 * self.crank_radius
        vc = vd / (self.compression_ratio - 1)
        return vc + area * x

    def burned(self, psi_deg: float) -> float:
        """Wiebe mass fraction burned at a crank angle [deg] (0 for the motored trace).

        >>> m = GasModel(**CRF450R)
        >>> m.burned(300.0), round(m.burned(m.soc + m.duration), 6)   # 1 - exp(-a) at the end
        (0.0, 0.993262)
        """
        if psi_deg <= self.soc or self.motored:
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

_FULL = dict(**CRF450R, manifold_pressure=1.0e5, peak_pressure=60e5, soc=342.0)

# the own engine of docs/own_engine.md: 86 mm bore and stroke, 143.5 mm conrod, compression
# ratio 10.5 (assumed)
_OWN86 = dict(bore=86e-3, crank_radius=43e-3, conrod_length=143.5e-3, compression_ratio=10.5)

#: Shipped operating points (see inputs/README.md): the 8000 and 12,000 r/min traces are the
#: 4000 r/min one with their speed recorded; the own engine's is the walkthrough's trace of
#: docs/own_engine.md (full load at 3000 r/min, net IMEP 10 bar), which its distorted deck reads.
PRESETS: dict[str, GasModel] = {
    "crf450r_4000rpm_full": GasModel(**_FULL),
    "crf450r_3000rpm_half": GasModel(**CRF450R, manifold_pressure=0.55e5, peak_pressure=35e5, soc=348.0),
    "crf450r_8000rpm_full": GasModel(**_FULL, speed_rpm=8000.0),
    "crf450r_12000rpm_full": GasModel(**_FULL, speed_rpm=12000.0),
    "own86_3000rpm_full": GasModel(**_OWN86, manifold_pressure=1.0e5, imep=10e5, speed_rpm=3000.0),
}


def heat_transfer_coefficient(m: GasModel, p, v, temperature, motored_pressure=None, burning: bool = False):
    """Wall heat-transfer coefficient h [W/(m^2 K)] of the model's correlation (times
    ``heat_transfer_scale`` is not applied here).

    * Woschni (1967; Heywood, *Internal Combustion Engine Fundamentals*, 1988, eq. 12.19):
      ``h = 3.26 B^-0.2 p^0.8 T^-0.55 w^0.8`` with B in m, p in kPa, T in K and the gas
      velocity ``w = 2.28 S_p + C2 (Vd T_r / (p_r V_r)) (p - p_m)`` [m/s], S_p the mean
      piston speed, ``C2 = 3.24e-3 m/(s K)`` from the start of combustion (0 before it and
      in the motored trace), p_m the motored pressure and r the state at intake valve
      closing (``(p - p_m) / p_r`` is a ratio; ``2.28`` is C1 of compression and expansion,
      the closed cycle this model integrates).
    * Hohenberg (1979, SAE 790825): ``h = 130 V^-0.06 p^0.8 T^-0.4 (S_p + 1.4)^0.8`` with
      V in m^3, p in bar, T in K.

    Parameters
    ----------
    m : GasModel
    p, v, temperature : float or ndarray
        Pressure [Pa], volume [m^3] and gas temperature [K].
    motored_pressure : float or ndarray, optional
        Woschni's p_m [Pa] (needed when ``burning``).
    burning : bool
        From the start of combustion on (Woschni's combustion term).

    Examples
    --------
    >>> m = GasModel(86e-3, 43e-3, 143.5e-3, 10.5, speed_rpm=3000, heat_transfer="hohenberg")
    >>> round(float(heat_transfer_coefficient(m, 50e5, 1e-4, 2000.0)), 1)
    1558.5
    """
    sp = m.mean_piston_speed
    if m.heat_transfer == "hohenberg":
        return 130.0 * v**-0.06 * (p / 1e5) ** 0.8 * temperature**-0.4 * (sp + 1.4) ** 0.8
    if m.heat_transfer != "woschni":
        raise ValueError(f"heat_transfer '{m.heat_transfer}' has no coefficient")
    w = 2.28 * sp
    if burning:
        v_r = float(m.volume([m.ivc])[0])
        rise = np.maximum(p - motored_pressure, 0.0)
        w = w + 3.24e-3 * m.swept_volume * m.intake_temperature / (m.manifold_pressure * v_r) * rise
    return 3.26 * m.bore**-0.2 * (p / 1e3) ** 0.8 * temperature**-0.55 * w**0.8


def _closed_cycle(m: GasModel, psi: np.ndarray, q_total: float, scale: float = 0.0) -> np.ndarray:
    """Integrate the first law from ivc to evo on the fine grid ``psi`` (with wall heat loss
    when the model has it and ``scale`` > 0)."""
    if m.heat_transfer != "none" and scale > 0:
        return _closed_cycle_wall(m, psi, q_total, scale)[0]
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


def _closed_cycle_wall(m: GasModel, psi: np.ndarray, q_total: float, scale: float):
    """The closed cycle with wall heat loss: pressure and the cumulative wall heat [J] on
    ``psi``. Each step is the trapezoidal step of :func:`_closed_cycle` with the wall heat of
    the step by Heun's rule (the loss rate at the step's start, then at its predicted end,
    averaged). The coefficient is :func:`heat_transfer_coefficient`'s, written out on plain
    floats (a test compares the two)."""
    v_arr = m.volume(psi)
    g = m.gamma
    p_r, v_r, t_r = m.manifold_pressure, float(v_arr[0]), m.intake_temperature
    p_mot = (p_r * (v_r / v_arr) ** g).tolist()  # Woschni's motored pressure (polytropic from ivc)
    area = (2 * np.pi / 4 * m.bore**2 + 4 * v_arr / m.bore).tolist()
    dq_comb = (q_total * np.diff(_burned(m, psi))).tolist()
    burning = ((psi > m.soc) & (not m.motored)).tolist()
    v = v_arr.tolist()
    per_deg = scale / (6.0 * m.speed_rpm)  # s per crank degree, times the factor
    t_wall, sp, t_per_pv = m.wall_temperature, m.mean_piston_speed, t_r / (p_r * v_r)
    woschni = m.heat_transfer == "woschni"
    if woschni:
        k0 = 3.26 * m.bore**-0.2 * 1e-3**0.8
        w0, k_comb = 2.28 * sp, 3.24e-3 * m.swept_volume * t_r / (p_r * v_r)
    else:
        k0 = 130.0 * 1e-5**0.8 * (sp + 1.4) ** 0.8
        vk = (v_arr**-0.06).tolist()

    def loss(pi: float, i: int) -> float:
        """Wall heat-loss rate [J/deg] at pressure ``pi`` and grid point ``i``."""
        t = t_per_pv * pi * v[i]
        if woschni:
            w = w0 + k_comb * max(pi - p_mot[i], 0.0) if burning[i] else w0
            h = k0 * pi**0.8 * t**-0.55 * w**0.8
        else:
            h = k0 * vk[i] * pi**0.8 * t**-0.4
        return per_deg * h * area[i] * (t - t_wall)

    p = [p_r] * len(v)
    qw = [0.0] * len(v)
    rate = loss(p_r, 0)
    for i in range(1, len(v)):
        dpsi = float(psi[i] - psi[i - 1])
        dv = v[i] - v[i - 1]
        vm = 0.5 * (v[i] + v[i - 1])
        a, b = 1 - 0.5 * g * dv / vm, 1 + 0.5 * g * dv / vm
        guess = (p[i - 1] * a + (g - 1) * (dq_comb[i - 1] - rate * dpsi) / vm) / b
        dqw = 0.5 * (rate + loss(guess, i)) * dpsi
        p[i] = (p[i - 1] * a + (g - 1) * (dq_comb[i - 1] - dqw) / vm) / b
        qw[i] = qw[i - 1] + dqw
        rate = loss(p[i], i)
    return np.array(p), np.array(qw)


def _burned(m: GasModel, psi: np.ndarray) -> np.ndarray:
    """:meth:`GasModel.burned` at every crank angle of ``psi`` at once."""
    if m.motored:
        return np.zeros_like(psi)
    z = np.maximum(psi - m.soc, 0.0) / m.duration
    return np.where(psi <= m.soc, 0.0, 1.0 - np.exp(-m.wiebe_a * z ** (m.wiebe_m + 1)))


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


def _bracket(f: Callable[[float], float], target: float, what: str) -> float:
    """An upper bound ``hi`` of the heat with ``f(hi) >= target`` (``f`` increasing)."""
    if f(0.0) >= target:
        raise ValueError(f"{what}: {target:g} Pa is not above the motored trace's {f(0.0):g} Pa")
    hi = 1.0e4
    while f(hi) < target:
        hi *= 2
        if hi > 1e9:
            raise ValueError(f"{what}: {target:g} Pa is out of reach of the model")
    return hi


def _bisect(f: Callable[[float], float], target: float, what: str) -> float:
    """The heat ``q >= 0`` with ``f(q) = target`` for an increasing ``f``."""
    lo, hi = 0.0, _bracket(f, target, what)
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if f(mid) < target else (lo, mid)
    return 0.5 * (lo + hi)


def _root(f: Callable[[float], float], target: float, what: str, guess: float | None = None) -> float:
    """As :func:`_bisect` by Brent's method (the traces with wall heat loss, each ~50 times
    dearer than one without), in a bracket of +-2 % about ``guess`` when that holds the root."""
    from scipy.optimize import brentq

    def g(q: float) -> float:
        return f(q) - target

    if guess:
        lo, hi = 0.98 * guess, 1.02 * guess
        if g(lo) < 0 < g(hi):
            return float(brentq(g, lo, hi, xtol=1e-10 * hi, rtol=1e-13))
    hi = _bracket(f, target, what)
    return float(brentq(g, 0.0, hi, xtol=1e-10 * hi, rtol=1e-13))


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


@functools.lru_cache(maxsize=32)  # GasModel is frozen: the same model, the same answer
def load_solution(m: GasModel, step: float = 0.5) -> tuple[float, float]:
    """The heat released per cycle [J] and the factor on the wall heat-transfer coefficient
    (0 without wall heat loss) that give the model's load.

    Parameters
    ----------
    m : GasModel
    step : float
        Crank-angle step [deg] of the trace whose IMEP is a target.

    Returns
    -------
    (float, float)

    Raises
    ------
    ValueError
        A target out of reach (naming it and why).

    Examples
    --------
    >>> load_solution(GasModel(**CRF450R, heat_fraction=0.0))
    (0.0, 0.0)
    """
    fine = _fine(m)
    psi = np.arange(0.0, 720.0 + step / 2, step)
    wall = m.heat_transfer != "none"
    scale = (1.0 if m.heat_transfer_scale is None else m.heat_transfer_scale) if wall else 0.0
    solve = _root if wall else _bisect

    def peak(q: float, c: float) -> float:
        return float(_closed_cycle(m, fine, q, c).max())

    def work(q: float, c: float) -> float:
        return imep(psi, _assemble(m, psi, fine, _closed_cycle(m, fine, q, c)), m)

    if m.load == "peak_pressure":
        return solve(lambda q: peak(q, scale), m.peak_pressure, "peak_pressure"), scale
    if m.load == "imep":
        return solve(lambda q: work(q, scale), m.imep, "imep"), scale
    if m.load == "peak_pressure and imep":
        return _fit_both(m, peak, work)
    return m.fuel_heat(), scale


def _fit_both(m: GasModel, peak, work) -> tuple[float, float]:
    """Heat and heat-transfer factor with both the peak pressure and the IMEP: for a factor,
    the heat is solved for the peak; the factor for the IMEP (which falls as the factor
    rises: more of the heat leaves through the walls before it does work)."""
    from scipy.optimize import brentq

    last: list[float] = []

    def heat(c: float) -> float:
        q = _root(lambda q: peak(q, c), m.peak_pressure, "peak_pressure", last[-1] if last else None)
        last.append(q)
        return q

    def excess(c: float) -> float:
        return work(heat(c), c) - m.imep

    top = excess(0.0)
    what = f"peak_pressure, imep: {m.imep / 1e5:.4g} bar IMEP with a {m.peak_pressure / 1e5:.4g} bar peak"
    if top < 0:
        raise ValueError(
            f"{what} is out of reach: without wall heat loss that peak gives {(top + m.imep) / 1e5:.3f} bar "
            "IMEP at most; a later or longer combustion (soc, duration) gives more IMEP for the peak"
        )
    c_max = MAX_HEAT_TRANSFER_SCALE
    if excess(c_max) > 0:
        raise ValueError(
            f"{what} is out of reach: even {c_max:g} times the {m.heat_transfer} heat loss leaves more "
            "IMEP; an earlier or shorter combustion (soc, duration) gives less IMEP for the peak"
        )
    c = float(brentq(excess, 0.0, c_max, xtol=1e-8, rtol=1e-10))
    return heat(c), c


def heat_released(m: GasModel, step: float = 0.5) -> float:
    """Total heat released per cycle [J] for the model's load.

    Parameters
    ----------
    m : GasModel
    step : float
        Crank-angle step [deg] of the trace whose IMEP is the target.

    Examples
    --------
    >>> heat_released(GasModel(**CRF450R, heat_fraction=0.0))
    0.0
    """
    return load_solution(m, step)[0]


def wall_heat(m: GasModel, step: float = 0.5) -> float:
    """Heat lost to the walls over the closed cycle [J] (0 without wall heat loss).

    Parameters
    ----------
    m : GasModel
    step : float
        Crank-angle step [deg] of the trace whose IMEP is a target.

    Examples
    --------
    >>> wall_heat(GasModel(**CRF450R, peak_pressure=50e5))
    0.0
    """
    q, c = load_solution(m, step)
    if m.heat_transfer == "none" or c == 0:
        return 0.0
    return float(_closed_cycle_wall(m, _fine(m), q, c)[1][-1])


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
    q, c = load_solution(m, step)
    pc = _closed_cycle(m, fine, q, c)
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
    return [
        m.soc + (-math.log(1.0 - x) / m.wiebe_a) ** (1.0 / (m.wiebe_m + 1)) * m.duration for x in fractions
    ]
