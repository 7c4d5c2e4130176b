"""Validation, computed: every run ``docs/validation.md`` reports, as numbers.

:func:`compute_validation` runs the shipped decks, the calibration re-run, the one-at-a-time
sensitivity, the gas-trace shifts, the modelling options, the published trends, the readings
of the open choices, the ring pack and the oil sensitivity, and returns them in a
:class:`ValidationData` (no file is written; :mod:`ringlube.validate.render` turns it into
Markdown).
"""

from __future__ import annotations

import os
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .. import gas
from ..calibrate import apply, calibrate, choose, correlation, strip_calibrated
from ..case import Case
from ..errors import InputError
from ..readings.reading import READINGS
from ..solve import run, run_many
from ..trends import TRENDS, trend_verdicts
from .bore import bore_validation

__all__ = [
    "PUBLISHED",
    "ASSUMED",
    "OPTIONS",
    "TRENDS",
    "ValidationData",
    "compute_validation",
]


def published(targets: str | os.PathLike | None = None) -> dict[str, dict[str, float]]:
    """{condition: {quantity: value}} of a targets file (default: Table 2 of the study)."""
    from ..targets import DEFAULT_TARGETS, read_targets

    return {k: c.values for k, c in read_targets(targets or DEFAULT_TARGETS).items()}


#: Table 2 of the study, 4000 r/min full load, optimum ring (inputs/targets_table2.csv).
PUBLISHED = published()
#: Assumed inputs varied +/-10 % one at a time: (group, variable).
ASSUMED = [
    ("surface", "zeta_kappa_sigma"),
    ("surface", "sigma_over_kappa"),
    ("surface", "tau0"),
    ("surface", "boundary_coefficient"),
    ("operating", "pressure_scale"),
    ("operating", "crankcase_pressure"),
    ("surface", "e_ring"),
    ("surface", "nu_liner"),
    ("ring", "radial_depth"),
    ("ring", "density"),
]
#: Modelling options flipped one at a time: (group, variable, alternative).
OPTIONS = [
    ("physics", "contact_area", {"lumped": "local", "local": "lumped"}),
    ("physics", "outlet", {"reynolds": "ambient", "ambient": "reynolds"}),
    ("ring", "tension_unit", {"N": "N/m", "N/m": "N"}),
    ("physics", "gt_functions", {"exact": "fit", "fit": "exact"}),
    ("physics", "roelands", {True: False, False: True}),
    ("physics", "squeeze", {True: False, False: True}),
]


def reading_rows(cases: dict[str, Case], points: int = 5) -> list[dict]:
    """For every reading (film model x contact area x tension unit): Table 2 numbers cold
    and hot and the four published trends on the cold case, with the shipped calibration.

    Returns
    -------
    list of dict
        One per reading: 'film', 'area', 'unit', 'cold', 'hot' (results), 'verdicts'.
    """
    import os

    plan, rows = [], []
    for film, physics in READINGS.items():
        for area in ("lumped", "local"):
            for unit in ("N/m", "N"):
                c = {
                    k: v.with_physics(**physics, contact_area=area).with_ring(tension_unit=unit)
                    for k, v in cases.items()
                }
                rows.append({"film": film, "area": area, "unit": unit})
                plan.append((len(rows) - 1, "cold", None, None, c["cold"]))
                plan.append((len(rows) - 1, "hot", None, None, c["hot"]))
                for t in TRENDS:
                    for x in np.linspace(*t.range, points):
                        plan.append(
                            (len(rows) - 1, "sweep", t.name, x, c["cold"].with_ring(**{t.name: float(x)}))
                        )
    results = run_many([p[-1] for p in plan], workers=os.cpu_count() or 1, progress=False, on_error="return")
    sweeps: dict[int, dict] = {}
    for (i, kind, name, x, _), r in zip(plan, results):
        if kind in ("cold", "hot"):
            rows[i][kind] = r
        else:
            xs, es = sweeps.setdefault(i, {}).setdefault(name, ([], []))
            xs.append(x)
            es.append(getattr(r, "energy_loss", np.nan))
    for i, row in enumerate(rows):
        row["verdicts"] = trend_verdicts({k: (np.array(v[0]), np.array(v[1])) for k, v in sweeps[i].items()})
    return rows


def _value(case: Case, group: str, name: str, calibration: Case):
    """The effective value (deck, calibration file or kernel default)."""
    return case.value(group, name)


def trend_sweeps(case: Case, points: int = 9) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    out = {}
    for t in TRENDS:
        xs = np.linspace(*t.range, points)
        rs = run_many([case.with_ring(**{t.name: float(x)}) for x in xs], workers=1, progress=False)
        out[t.name] = (xs, np.array([r.energy_loss for r in rs]))
    return out


@dataclass
class ValidationData:
    """Everything ``docs/validation.md`` reports, computed by :func:`compute_validation` and
    turned into Markdown by :func:`~ringlube.validate.render.render_validation`
    (computed apart from the rendering).

    Numbers only: ``results`` and the other run results are :class:`ringlube.result.Result`
    objects of the shipped decks; the tables are lists of plain rows (see each field).

    Examples
    --------
    >>> data = compute_validation(".")  # doctest: +SKIP
    >>> data.results["cold"].energy_loss  # doctest: +SKIP
    1.83...
    """

    #: shipped decks {'cold', 'hot'}: path and case
    decks: dict[str, Path]
    cases: dict[str, Case]
    #: the shipped decks' results (labelled 'cold (348 K)', ...)
    results: dict
    #: radial depth [m] that would give the study's 24 g ring
    depth_24g: float
    #: the calibration re-run: the chosen fit, every fit, Jacobian, correlation, and whether
    #: it reproduces the shipped file
    fit: object
    fits: list
    jac: np.ndarray
    corr: float
    same: bool
    #: one-at-a-time +/-10 %: (group, name, value, {k: (runs at 0.9, runs at 1.1)}, masses|None)
    sensitivity: list
    #: gas trace shifted: (shift deg, {k: result})
    shifts: list
    #: modelling options flipped: (group, name, shipped, flipped, {k: result})
    options: list
    #: published trends: {k: {variable: (xs, energies)}} and their verdicts
    sweeps: dict
    verdicts: dict
    #: readings of the open choices (reading_rows)
    readings: list
    #: the ring pack: see ring_pack_validation
    ring_pack: dict
    #: the two readings of the tension, each with its own calibration: see tension_readings
    tension: dict
    #: oil to the chamber against the supply film: see oil_sensitivity
    oil: dict
    #: wall time of the whole regeneration [s] (set by validate)
    seconds: float = 0.0
    #: the distorted bore's runs (:func:`ringlube.validate.bore.bore_validation`)
    bore: dict = field(default_factory=dict)


#: The two readings of the ring's tension (``&ring tension_unit``) and what each means.
TENSION_READINGS = {
    "N": "tangential force F_T, p_e = F_T/(b r0)",
    "N/m": "force per unit circumference, p_e = tension/b",
}


def tension_readings(cases: dict[str, Case], fits: list, shipped_unit: str) -> dict:
    """Both readings of the tension on the shipped decks, each with its own calibration (the
    best fit of that unit among ``fits``, the calibration re-run): Table 2 cold and hot, the
    trend sweeps cold and hot, and the starved film (1 um, the decks' preset) cold and hot.

    Parameters
    ----------
    cases : dict
        The shipped 'cold' and 'hot' cases.
    fits : list of Fit
        Every fit of the calibration re-run (both units).
    shipped_unit : str
        The shipped decks' tension unit (listed first).

    Returns
    -------
    dict
        {unit: {'fit', 'elastic_pressure' (Pa, of the shipped ring), 'results', 'sweeps',
        'verdicts', 'starved' ({k: result})}}, the shipped unit first.
    """
    out = {}
    units = [shipped_unit] + [u for u in TENSION_READINGS if u != shipped_unit]
    for unit in units:
        fit = choose(fits, unit)
        cs = {
            k: apply(strip_calibrated(c), fit.options, fit.zeta_kappa_sigma, fit.pressure_scale)
            for k, c in cases.items()
        }
        sweeps = {k: trend_sweeps(cs[k]) for k in ("cold", "hot")}
        starved = [cs[k].with_physics(cavitation="jfo", inlet="starved") for k in ("cold", "hot")]
        rs = run_many(starved, workers=1, progress=False, on_error="return")
        b, r0, t = (
            cs["cold"].value(*k) for k in (("ring", "width"), ("engine", "bore_radius"), ("ring", "tension"))
        )
        out[unit] = {
            "fit": fit,
            "elastic_pressure": t / (b * r0) if unit == "N" else t / b,
            "results": {k: run(cs[k]) for k in ("cold", "hot")},
            "sweeps": sweeps,
            "verdicts": {k: trend_verdicts(sweeps[k]) for k in ("cold", "hot")},
            "starved": dict(zip(("cold", "hot"), rs)),
        }
    return out


#: Supply films [m] of the oil-sensitivity table.
SUPPLY_FILMS = (0.5e-6, 1e-6, 2e-6, 5e-6, 10e-6)
#: Shipped decks of the oil-sensitivity table: label, deck file.
OIL_DECKS = {
    "4000 r/min full, cold": "crf450r_4000rpm_full_cold.nml",
    "4000 r/min full, hot": "crf450r_4000rpm_full_hot.nml",
    "3000 r/min half, cold": "crf450r_3000rpm_half_cold.nml",
    "3000 r/min half, hot": "crf450r_3000rpm_half_hot.nml",
}
#: Ring variants of the ring engineer's story (from the study's ranges).
STORY_RINGS = {
    "study optimum (1.004 mm, tension 8)": {},
    "narrowest (0.54 mm)": {"width": 0.54e-3},
    "widest (1.34 mm)": {"width": 1.34e-3},
    "tension 26": {"tension": 26.0},
}
#: Engine speeds of the story: the study's and the CRF450R's rev limit [r/min].
STORY_SPEEDS = (4000.0, 12000.0)


def oil_sensitivity(root: str | os.PathLike = ".") -> dict:
    """Oil to the chamber and energy against the supply film on the shipped decks, starved
    JFO film, the decks' own preset.

    Returns
    -------
    dict
        {deck label: [(supply film m, result), ...]} in SUPPLY_FILMS order.
    """
    out = {}
    for label, name in OIL_DECKS.items():
        case = Case.from_namelist(Path(root) / "inputs" / name).with_physics(
            cavitation="jfo", inlet="starved"
        )
        cases = [case.with_("lubricant", supply_film=h) for h in SUPPLY_FILMS]
        out[label] = list(zip(SUPPLY_FILMS, run_many(cases, workers=1, progress=False, on_error="return")))
    return out


def ring_pack_validation(cases: dict[str, Case]) -> dict:
    """The ring pack on the shipped decks and the ring engineer's story.

    Returns
    -------
    dict
        'decks': {k: result} of the cold and hot decks with ``ring_pack = 'gas'``; 'story':
        [(speed, ring name, result)] on the cold deck with the ring pack.
    """
    gas = {k: c.with_physics(ring_pack="gas") for k, c in cases.items()}
    story_cases, story = [], []
    for speed in STORY_SPEEDS:
        for name, ring in STORY_RINGS.items():
            story.append((speed, name))
            story_cases.append(gas["cold"].with_operating(speed_rpm=speed).with_ring(**ring))
    rs = run_many(story_cases, workers=1, progress=False, on_error="return")
    return {
        "decks": {k: run(c) for k, c in gas.items()},
        "story": [(speed, name, r) for (speed, name), r in zip(story, rs)],
    }


def compute_validation(root: str | os.PathLike = ".") -> ValidationData:
    """Run everything ``docs/validation.md`` reports (no file is written).

    Parameters
    ----------
    root : path
        Project folder (with ``inputs/``).

    Returns
    -------
    ValidationData

    Raises
    ------
    InputError
        If a shipped deck or the targets file is bad, or the cold deck names no calibration.

    Examples
    --------
    >>> data = compute_validation(".")  # doctest: +SKIP
    >>> data.same  # the calibration re-run reproduces the shipped file  # doctest: +SKIP
    True
    """
    root = Path(root)
    decks = {
        "cold": root / "inputs" / "crf450r_4000rpm_full_cold.nml",
        "hot": root / "inputs" / "crf450r_4000rpm_full_hot.nml",
    }
    cases = {k: Case.from_namelist(p) for k, p in decks.items()}
    calib_file = cases["cold"]["calibration", "file"]
    if not calib_file:
        raise InputError(
            f"{decks['cold']}: &calibration file: not given; validate compares the calibration "
            "file the cold deck includes with a fresh fit (ringlube calibrate writes one)"
        )
    calibration = Case.from_namelist(calib_file)
    results = {k: run(c) for k, c in cases.items()}
    for k, r in results.items():
        r.label = f"{k} ({cases[k]['operating', 'liner_temperature']:.0f} K)"

    # calibration, re-run from scratch and compared with the shipped file
    fit, fits = calibrate(decks["cold"], progress=False)
    base = strip_calibrated(cases["cold"])
    jac, corr = correlation(base, fit)
    shipped = {
        "zeta_kappa_sigma": calibration.get("surface", "zeta_kappa_sigma"),
        "pressure_scale": calibration.get("operating", "pressure_scale"),
    }
    same = all(abs(shipped[k] - getattr(fit, k)) <= 1e-9 * max(1.0, abs(shipped[k])) for k in shipped)

    # sensitivity, one at a time
    sensitivity = []
    for group, name in ASSUMED:
        v0 = _value(cases["cold"], group, name, calibration)
        runs = {
            k: [run(_with(cases[k], calibration, group, name, v0 * f)) for f in (0.9, 1.1)]
            for k in ("cold", "hot")
        }
        mass = (
            [run(_with(cases["cold"], calibration, group, name, v0 * f)).ring_mass for f in (0.9, 1.1)]
            if group == "ring"
            else None
        )
        sensitivity.append((group, name, v0, runs, mass))

    # the gas trace: its crank angle, shifting the closed cycle
    psi, p = gas.read_csv(Path(cases["cold"]["operating", "pressure_file"]))
    shifts = []
    with tempfile.TemporaryDirectory() as tmpdir:
        tmp = Path(tmpdir) / "_shifted.csv"
        for shift in (-5.0, 5.0):
            closed = (psi > 200) & (psi < 490)
            q = p.copy()
            q[closed] = np.interp(psi[closed] - shift, psi, p)
            gas.write_csv(tmp, psi, q)
            shifts.append(
                (
                    shift,
                    {
                        k: run(cases[k].with_operating(pressure_file=str(tmp.resolve())))
                        for k in ("cold", "hot")
                    },
                )
            )

    # modelling options
    options = []
    for group, name, alt in OPTIONS:
        v0 = _value(cases["cold"], group, name, calibration)
        v1 = alt[v0]
        options.append(
            (
                group,
                name,
                v0,
                v1,
                {k: run(_with(cases[k], calibration, group, name, v1)) for k in ("cold", "hot")},
            )
        )

    # trends
    sweeps = {k: trend_sweeps(cases[k]) for k in ("cold", "hot")}
    verdicts = {k: trend_verdicts(sweeps[k]) for k in ("cold", "hot")}

    return ValidationData(
        decks=decks,
        cases=cases,
        results=results,
        depth_24g=_depth_for_mass(cases["cold"], 24.0),
        fit=fit,
        fits=fits,
        jac=jac,
        corr=corr,
        same=same,
        sensitivity=sensitivity,
        shifts=shifts,
        options=options,
        sweeps=sweeps,
        verdicts=verdicts,
        readings=reading_rows({"cold": cases["cold"], "hot": cases["hot"]}),
        ring_pack=ring_pack_validation(cases),
        oil=oil_sensitivity(root),
        tension=tension_readings(cases, fits, cases["cold"].value("ring", "tension_unit")),
        bore=bore_validation(root),
    )


def _depth_for_mass(case: Case, grams: float) -> float:
    """Radial depth [m] that would give the ring ``grams`` (by bisection on the kernel's mass)."""
    from scipy.optimize import brentq

    coarse = case.with_numerics(preset="fast", max_cycles=1)
    return brentq(lambda a: run(coarse.with_ring(radial_depth=a)).ring_mass - grams, 1e-3, 0.04, xtol=1e-6)


def _with(case: Case, calibration: Case, group: str, name: str, value) -> Case:
    """The case with one input changed (a calibrated input is first inlined)."""
    if calibration.get(group, name) is not None and case.get(group, name) is None:
        case = case.inline_calibration()
    return case.with_(group, **{name: value})
