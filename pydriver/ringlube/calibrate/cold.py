"""Calibration of the uncertain inputs against the cold Table 2 case only.

The study's result for its optimum ring at 4000 r/min full load, cold (348 K), gives two
targets: 1.92 J per cycle and 8.47 % of the cycle in mixed/boundary lubrication. Two
targets determine at most two continuous inputs, so exactly two are fitted, within
declared physical bounds:

* ``&surface zeta_kappa_sigma`` (roughness parameter; the energy target is most sensitive
  to it through the asperity load and boundary friction),
* ``&operating pressure_scale`` (scale of the synthetic gas-pressure trace, which stands
  for the unpublished measured one; the mixed share is most sensitive to it).

The discrete modelling choices the study leaves open are enumerated, each with its own
fit: ``&physics contact_area`` ('local' / 'lumped') and ``&physics outlet`` ('reynolds' /
'ambient'). The combination with the smallest score wins (a fit may end on a bound; the file
says so); ties within the mixed-share quantum (one crank step) go to the one whose continuous
inputs lie closest to their nominal values (0.04 and 1.0). The score is the fit's misfit in
units of the goal (:data:`GOAL`, the same as ``ringlube readings``): the friction's relative
error over 5 %, the mixed share's error over 1.5 points.

The tension unit (``&ring tension_unit``, 'N' or 'N/m') is not chosen by the fit: it says what
the deck's tension means (a tangential force on the ring's drawing, or a force per unit of
circumference), so it is the deck's own, or ``tension_unit`` (``ringlube calibrate
--tension-unit``). The fits of the other unit are made too and listed beside (the readings the
file does not ship), so one command shows both.
The hot case is never used: it is the prediction the validation checks.

**Your own engine's targets.** The friction target may be given as the energy per cycle
(``energy_loss``, J), as a friction test measures it, the mean friction power
(``friction_power``, W) or the ring's FMEP (``fmep``, kPa) (one of the three: at one speed and
displacement they are proportional), and the mixed share is optional, for no engine test
measures it. With the friction alone, one target determines one input: only
``zeta_kappa_sigma`` is fitted (method 'brent'), ``pressure_scale`` and the modelling options
are the deck's own (nothing is enumerated), and the calibration file holds
``zeta_kappa_sigma`` alone.

The mixed share varies continuously with the inputs (a crossing of lambda = 4 inside a crank
step counts the part of the step below it) but only piecewise smoothly; the fit is
therefore nested: for a pressure scale, zeta_kappa_sigma is solved by Brent's method for
the energy target (energy is continuous and increasing in it); the pressure scale is then
found by bisection on the mixed share (increasing in it). That is method 'bracket' of the one
calibrator, :func:`ringlube.calibrate.calibrator.calibrate_inputs` (``ringlube readings`` uses its
method 'least_squares'); each :class:`Fit` keeps its :class:`scipy.optimize.OptimizeResult`.
"""

from __future__ import annotations

import dataclasses
import itertools
import math
import os
from pathlib import Path

import numpy as np

from ..case import Case
from ..errors import InputError
from ..outputs import write_text
from ..solve import run
from .calibrator import Param, calibrate_inputs

__all__ = [
    "FITTED",
    "GOAL",
    "FRICTION",
    "BOUNDS",
    "NOMINAL",
    "PARAMS",
    "DISCRETE",
    "Fit",
    "calibrate",
    "write_calibration",
    "cold_targets",
]

#: The two target quantities of the shipped fit (read from the targets file).
FITTED = ("energy_loss", "mixed_share")
#: The friction target: one of these (proportional at one speed and displacement); the
#: mixed share is the optional second target.
FRICTION = ("energy_loss", "friction_power", "fmep")
#: How a target is named and printed in the calibration file (its unit is the result's).
_SHOWN = {
    "energy_loss": ("energy", "{:.4f} J"),
    "friction_power": ("friction power", "{:.4f} W"),
    "fmep": ("FMEP", "{:.4f} kPa"),
    "mixed_share": ("mixed share", "{:.3f} %"),
}
#: Declared bounds of the fitted inputs.
BOUNDS = {"zeta_kappa_sigma": (0.02, 0.10), "pressure_scale": (0.8, 1.2)}
NOMINAL = {"zeta_kappa_sigma": 0.04, "pressure_scale": 1.0}
#: The goal a fit is measured in (the score; the same as ``ringlube readings``): the friction
#: (any of :data:`FRICTION`) within 5 % (relative), the mixed share within 1.5 points.
GOAL = {"energy_loss": 0.05, "mixed_share": 1.5}
#: The fitted inputs with their bounds, in the order of :data:`FITTED` (the first is solved for
#: the energy, the second for the mixed share).
PARAMS = [
    Param("zeta_kappa_sigma", "surface:zeta_kappa_sigma", *BOUNDS["zeta_kappa_sigma"]),
    Param("pressure_scale", "operating:pressure_scale", *BOUNDS["pressure_scale"]),
]
#: Discrete options: (group, variable) -> choices.
DISCRETE = {
    ("ring", "tension_unit"): ("N", "N/m"),
    ("physics", "contact_area"): ("local", "lumped"),
    ("physics", "outlet"): ("reynolds", "ambient"),
}


def cold_targets(targets: str | os.PathLike | None = None, condition: str = "cold"):
    """(deck, {quantity: target}) of the calibrated condition in a targets file: its friction
    target (one of :data:`FRICTION`) and, if given, its mixed share.

    Parameters
    ----------
    targets : path, optional
        Targets CSV (default: the shipped Table 2).
    condition : str
        The condition fitted.

    Returns
    -------
    (Path, dict)

    Raises
    ------
    InputError
        If the condition or its friction target is missing, the friction is given twice
        (say, as energy and as FMEP), or a target is not positive.

    Examples
    --------
    >>> cold_targets()[1]
    {'energy_loss': 1.92, 'mixed_share': 8.47}
    """
    from ..targets import DEFAULT_TARGETS, read_targets

    path = Path(targets) if targets else DEFAULT_TARGETS
    conds = read_targets(path)
    if condition not in conds:
        raise InputError(f"{path}: no condition '{condition}' (has: {', '.join(conds)})")
    c = conds[condition]
    friction = [q for q in FRICTION if q in c.values]
    if not friction:
        raise InputError(
            f"{path}: condition '{condition}' lacks its friction: energy_loss (J per cycle), "
            "friction_power (W) or fmep (kPa)"
        )
    if len(friction) > 1:
        raise InputError(
            f"{path}: condition '{condition}' gives the friction twice ({', '.join(friction)}); "
            "keep one row (the fit matches one friction target)"
        )
    chosen = [friction[0]] + (["mixed_share"] if "mixed_share" in c.values else [])
    for q in chosen:
        if not c.values[q] > 0:
            raise InputError(
                f"{path}: condition '{condition}' {q} = {c.values[q]:g}: must be positive "
                "(the fit matches each target relative to its value)"
            )
    return c.deck, {q: c.values[q] for q in chosen}


@dataclasses.dataclass
class Fit:
    """One fit of the two continuous inputs for one combination of discrete options.

    Examples
    --------
    >>> f = Fit({}, 0.04, 1.0, 1.92, 8.47, 1, True, {"energy_loss": 1.92, "mixed_share": 8.47})
    >>> f.residual
    0.0
    """

    options: dict
    zeta_kappa_sigma: float
    pressure_scale: float
    energy_loss: float
    mixed_share: float
    runs: int
    within_bounds: bool
    targets: dict = dataclasses.field(default_factory=dict)
    #: what :func:`ringlube.calibrate.calibrator.calibrate_inputs` returned
    result: object = dataclasses.field(default=None, compare=False, repr=False)
    #: the fitted run's value of each target quantity (default: its energy and mixed share)
    reached: dict = dataclasses.field(default_factory=dict)

    @property
    def fitted(self) -> tuple[str, ...]:
        """The inputs fitted: ``zeta_kappa_sigma``, and ``pressure_scale`` with a mixed-share
        target."""
        if "mixed_share" in self.targets:
            return ("zeta_kappa_sigma", "pressure_scale")
        return ("zeta_kappa_sigma",)

    def value_of(self, quantity: str) -> float:
        """The fitted run's value of a target quantity."""
        reached = {"energy_loss": self.energy_loss, "mixed_share": self.mixed_share, **self.reached}
        return reached[quantity]

    @property
    def residual(self) -> float:
        """Root-sum-square of the relative misfits of the targets."""
        return math.hypot(*((self.value_of(q) - t) / t for q, t in self.targets.items()))

    @property
    def score(self) -> float:
        """Root-sum-square of the misfits in units of the goal (:data:`GOAL`): the friction's
        relative error over 5 %, the mixed share's error over 1.5 points.

        Examples
        --------
        >>> t = {"energy_loss": 1.92, "mixed_share": 8.47}
        >>> round(Fit({}, 0.1, 0.8, 1.92 * 1.05, 8.47 + 1.5, 1, False, t).score ** 2, 9)
        2.0
        """
        return math.hypot(*(self.misfit(q) for q in self.targets))

    def misfit(self, quantity: str) -> float:
        """The misfit of one target in units of the goal (:data:`GOAL`)."""
        t = self.targets[quantity]
        if quantity == "mixed_share":
            return (self.value_of(quantity) - t) / GOAL["mixed_share"]
        return (self.value_of(quantity) - t) / t / GOAL["energy_loss"]

    @property
    def distance_from_nominal(self) -> float:
        return math.hypot(
            math.log(self.zeta_kappa_sigma / NOMINAL["zeta_kappa_sigma"]),
            math.log(self.pressure_scale / NOMINAL["pressure_scale"]),
        )

    def case(self, base: Case) -> Case:
        return apply(base, self.options, self.zeta_kappa_sigma, self.pressure_scale)

    def values(self) -> dict:
        out = {k: getattr(self, k) for k in self.fitted}
        if len(self.targets) > 1:  # with one target the options are the deck's, not chosen
            out.update({f"{g}.{k}": v for (g, k), v in self.options.items()})
        return out


def apply(base: Case, options: dict, zks: float, scale: float) -> Case:
    c = base.with_("surface", zeta_kappa_sigma=float(zks)).with_("operating", pressure_scale=float(scale))
    for (group, name), value in options.items():
        c = c.with_(group, **{name: value})
    return c


def strip_calibrated(case: Case) -> Case:
    """The case without its calibration file (every fit sets the calibrated inputs and
    the discrete options explicitly)."""
    return case.with_("calibration", file="")


def fit_options(base: Case, options: dict, targets: dict) -> Fit:
    """Fit of the continuous inputs for one combination of options (the one calibrator,
    :func:`ringlube.calibrate.calibrator.calibrate_inputs`): with a mixed-share target both inputs,
    nested (method 'bracket'); with the friction alone ``zeta_kappa_sigma`` (method 'brent'),
    ``pressure_scale`` the deck's own."""
    results: dict[tuple, object] = {}
    friction = next(q for q in targets if q != "mixed_share")

    def result(x: tuple):
        r = results[x] = run(apply(base, options, *x))
        return r

    if "mixed_share" in targets:

        def misfits(x) -> tuple[float, float]:
            r = result(tuple(x))
            return getattr(r, friction) - targets[friction], r.mixed_share - targets["mixed_share"]

        sol = calibrate_inputs(
            misfits, PARAMS, "bracket", xtol=1e-5, rtol=1e-6, nominal=NOMINAL["pressure_scale"]
        )
        z, s = sol.x
    else:
        s = float(base.value("operating", "pressure_scale"))

        def misfit(x) -> tuple[float]:
            return (getattr(result((x[0], s)), friction) - targets[friction],)

        sol = calibrate_inputs(misfit, PARAMS[:1], "brent", xtol=1e-5, rtol=1e-6)
        z = sol.x[0]
    r = results[(z, s)]
    return Fit(
        dict(options),
        float(z),
        float(s),
        r.energy_loss,
        r.mixed_share,
        sol.nfev,
        sol.within_bounds,
        dict(targets),
        sol,
        {q: getattr(r, q) for q in targets},
    )


def calibrate(
    deck: str | os.PathLike | None = None,
    progress: bool = True,
    targets: str | os.PathLike | None = None,
    tension_unit: str | None = None,
) -> tuple[Fit, list[Fit]]:
    """Fit every combination of discrete options; returns (chosen fit, all fits).

    Parameters
    ----------
    deck : path, optional
        The deck of the calibrated condition (default: the targets file's 'cold' deck).
    progress : bool
        Show a progress bar.
    targets : path, optional
        Targets file (default: the shipped Table 2, ``inputs/targets_table2.csv``).
    tension_unit : {'N', 'N/m'}, optional
        The reading of the tension fitted (default: the deck's ``&ring tension_unit``); the
        chosen fit has it, the fits of the other unit are made and returned too.

    Returns
    -------
    (Fit, list of Fit)
        The chosen fit and every fit.

    Raises
    ------
    InputError
        For a tension unit other than 'N' and 'N/m'.

    Examples
    --------
    >>> fit, fits = calibrate(progress=False)  # doctest: +SKIP
    >>> len(fits)  # doctest: +SKIP
    8
    """
    from tqdm.auto import tqdm

    target_deck, tvals = cold_targets(targets)
    base = strip_calibrated(Case.from_namelist(deck or target_deck))
    unit_key = ("ring", "tension_unit")
    if tension_unit is not None:
        if tension_unit not in DISCRETE[unit_key]:
            raise InputError(f"--tension-unit '{tension_unit}': one of 'N', 'N/m'")
        base = base.with_ring(tension_unit=tension_unit)
    unit = base.value(*unit_key)
    if "mixed_share" in tvals:
        combos = [dict(zip(DISCRETE, values)) for values in itertools.product(*DISCRETE.values())]
    else:  # one target cannot tell the options apart: the deck's own
        combos = [{key: base.value(*key) for key in DISCRETE}]
    fits = [fit_options(base, o, tvals) for o in tqdm(combos, desc="calibration", disable=not progress)]
    return choose(fits, unit), fits


def choose(fits: list[Fit], unit: str) -> Fit:
    """The fit of tension unit ``unit`` with the smallest score; of those within one crank
    step's mixed share (in goal units) of it, the one closest to the nominal inputs.

    Examples
    --------
    >>> t = {"energy_loss": 1.92, "mixed_share": 8.47}
    >>> a = Fit({("ring", "tension_unit"): "N"}, 0.1, 0.8, 1.92, 9.9, 1, False, t)
    >>> b = Fit({("ring", "tension_unit"): "N/m"}, 0.1, 0.9, 1.84, 8.47, 1, True, t)
    >>> choose([a, b], "N") is a, choose([a, b], "N/m") is b
    (True, True)
    """
    mine = [f for f in fits if f.options.get(("ring", "tension_unit"), unit) == unit]
    quantum = 100.0 / 720.0 / GOAL["mixed_share"] if "mixed_share" in mine[0].targets else 0.0
    # the bounds are hard limits of each fit; a fit that ends on a bound is reported as such
    best = min(f.score for f in mine)
    near = [f for f in mine if f.score <= best + quantum]
    return min(near, key=lambda f: f.distance_from_nominal)


def correlation(base: Case, fit: Fit, rel_step: float = 0.05) -> tuple[np.ndarray, float]:
    """Sensitivity matrix d(targets)/d(log inputs) by central differences, and the
    correlation of the two fitted inputs implied by it (from (J^T J)^-1; NaN with one)."""
    cols = []
    for name in fit.fitted:
        vals = []
        for sgn in (-1, 1):
            z = fit.zeta_kappa_sigma * (1 + sgn * rel_step * (name == "zeta_kappa_sigma"))
            s = fit.pressure_scale * (1 + sgn * rel_step * (name == "pressure_scale"))
            r = run(apply(base, fit.options, z, s))
            vals.append([getattr(r, q) / t for q, t in fit.targets.items()])
        cols.append((np.array(vals[1]) - np.array(vals[0])) / (2 * rel_step))
    jac = np.column_stack(cols)
    if jac.shape[1] < 2:
        return jac, float("nan")
    cov = np.linalg.pinv(jac.T @ jac)
    corr = float(cov[0, 1] / math.sqrt(cov[0, 0] * cov[1, 1]))
    return jac, corr


def write_calibration(
    path: str | os.PathLike,
    fit: Fit,
    fits: list[Fit],
    jac: np.ndarray,
    corr: float,
    deck: str,
    command: str | None = None,
) -> Path:
    """The one calibration file every shipped deck includes (&calibration file = ...).

    It holds the two fitted uncertain inputs only; the chosen discrete options are
    modelling choices, written in each deck (where a reader sees them) and listed here.

    Parameters
    ----------
    path : path
        Written atomically.
    fit, fits : Fit, list of Fit
        The chosen fit and every fit.
    jac, corr : ndarray, float
        Sensitivity matrix and correlation of the fitted inputs.
    deck : str
        The deck fitted (named in the header).
    command : str, optional
        The command that regenerates the file (default: ``ringlube calibrate DECK``).

    Returns
    -------
    Path

    Examples
    --------
    >>> write_calibration("inputs/calibration.nml", fit, fits, jac, corr, deck)  # doctest: +SKIP
    """
    t = fit.targets

    def shown(q: str, v: float) -> str:
        name, form = _SHOWN[q]
        return f"{name} {form.format(v)}"

    rows = ", ".join(
        f"{_SHOWN[q][0].split()[0]} [{', '.join(f'{x:.3f}' for x in jac[i])}]" for i, q in enumerate(t)
    )
    units = {"energy_loss": "J", "mixed_share": "%", "friction_power": "W", "fmep": "kPa"}
    unit = fit.options.get(("ring", "tension_unit"))
    read = f", tension read in '{unit}'" if len(fit.fitted) > 1 else ""
    lines = [
        f"! ringlube calibration: fitted to the COLD case only "
        f"({', '.join(f'{v} {units[q]}' for q, v in t.items())}){read}.",
        f"! Regenerate: {command or f'ringlube calibrate {deck}'}",
        f"! Fit: {', '.join(shown(q, fit.value_of(q)) for q in t)} "
        f"(score {fit.score:.3f}, residual {fit.residual:.2e}); {sum(f.runs for f in fits)} runs.",
        "! Bounds: " + ", ".join(f"{k} {BOUNDS[k]}" for k in fit.fitted) + ".",
        f"! Sensitivity d(target/target0)/d(ln input): {rows}; "
        + (f"correlation of the fitted inputs {corr:+.3f}." if len(fit.fitted) > 1 else "one fitted input."),
    ]
    if len(fit.fitted) > 1:
        lines += [
            "! The decks using this file must set the chosen options themselves: "
            + ", ".join(f"&{g} {k} = '{v}'" for (g, k), v in fit.options.items())
            + ".",
            "! Score: the misfits in units of the goal (energy 5 %, mixed share 1.5 points), "
            "root-sum-square; the smallest of the tension unit fitted wins.",
            f"! Every combination of the discrete options (tension_unit, contact_area, outlet), "
            f"the '{unit}' reading first (the other unit's fits for comparison):",
        ]
        for f in sorted(fits, key=lambda f: (f.options.get(("ring", "tension_unit")) != unit, f.score)):
            opts = ", ".join(f"{k[1]}={v}" for k, v in f.options.items())
            lines.append(
                f"!   {opts}: zks {f.zeta_kappa_sigma:.4f}, scale {f.pressure_scale:.4f}, "
                f"E {f.energy_loss:.4f} J, mixed {f.mixed_share:.3f} %, score {f.score:.3f}"
                f"{'' if f.within_bounds else ' (at a bound)'}"
            )
        lines += [
            f"&surface   zeta_kappa_sigma = {fit.zeta_kappa_sigma!r} /",
            f"&operating pressure_scale = {fit.pressure_scale!r} /",
            "",
        ]
    else:
        lines += [
            f"! One target fits one input: pressure_scale ({fit.pressure_scale:g}) and the modelling "
            "options ("
            + ", ".join(f"{k} = '{v}'" for (_, k), v in fit.options.items())
            + ") are the deck's own, not fitted"
            + ("" if fit.within_bounds else "; the fit ends on a bound")
            + ".",
            f"&surface   zeta_kappa_sigma = {fit.zeta_kappa_sigma!r} /",
            "",
        ]
    return write_text(path, "\n".join(lines), [deck], "--out")
