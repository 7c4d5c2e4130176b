"""Validation report: the shipped calibration against the study's Table 2 (SPEC 11).

``ringlube validate`` regenerates ``docs/validation.md`` and its figures from scratch:
published vs computed (cold = calibration target, hot = prediction), the calibration
re-run and compared with the shipped file, one-at-a-time sensitivity (+/-10 %) of each
compared number to each assumed input, the effect of each modelling option, the gas
trace's peak and its crank angle, the published trends, and the study's Figs 2 and 11.
"""

from __future__ import annotations

import os
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from . import gas
from .calibrate import BOUNDS, calibrate, correlation, strip_calibrated
from .case import Case
from .errors import InputError
from .outputs import check_output, save_figure, write_text
from .plot import gas_figure, plot_results, save_metadata
from .solve import run, run_many
from .study_variables import DESIGN_RANGES

__all__ = [
    "PUBLISHED",
    "ASSUMED",
    "OPTIONS",
    "TRENDS",
    "ValidationData",
    "compute_validation",
    "render_validation",
    "validate",
]


def published(targets: str | os.PathLike | None = None) -> dict[str, dict[str, float]]:
    """{condition: {quantity: value}} of a targets file (default: Table 2 of the study)."""
    from .targets import DEFAULT_TARGETS, read_targets

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
#: The study's stated trends: variable, range, what the study says.
TRENDS = [
    ("tension", DESIGN_RANGES["tension"], "energy loss rises with tension"),
    ("crown_height", DESIGN_RANGES["crown_height"], "energy loss falls as crown height rises"),
    (
        "crown_offset",
        DESIGN_RANGES["crown_offset"],
        "a negative offset gives lower energy loss than a positive one",
    ),
    ("width", DESIGN_RANGES["width"], "energy loss has an interior optimum in width"),
]
#: The film models of SPEC 13, read one at a time (the other open choices crossed with them).
READINGS = {
    "Swift-Stieber (the study)": {},
    "JFO flooded": {"cavitation": "jfo"},
    "JFO flooded, trailing gas": {"cavitation": "jfo", "cavity_pressure": "trailing_gas"},
    "JFO starved": {"cavitation": "jfo", "inlet": "starved"},
    "JFO starved, trailing gas": {"cavitation": "jfo", "inlet": "starved", "cavity_pressure": "trailing_gas"},
}


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
                for name, (lo, hi), _ in TRENDS:
                    for x in np.linspace(lo, hi, points):
                        plan.append(
                            (len(rows) - 1, "sweep", name, x, c["cold"].with_ring(**{name: float(x)}))
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
    for name, (lo, hi), _ in TRENDS:
        xs = np.linspace(lo, hi, points)
        rs = run_many([case.with_ring(**{name: float(x)}) for x in xs], workers=1, progress=False)
        out[name] = (xs, np.array([r.energy_loss for r in rs]))
    return out


def trend_verdicts(sweeps: dict) -> dict[str, bool]:
    """Does ringlube agree with each stated trend (on one sweep)?"""
    v = {}
    x, e = sweeps["tension"]
    v["tension"] = bool(np.all(np.diff(e) > 0))
    x, e = sweeps["crown_height"]
    v["crown_height"] = bool(np.all(np.diff(e) < 0))
    x, e = sweeps["crown_offset"]
    v["crown_offset"] = bool(e[0] < e[-1])
    x, e = sweeps["width"]
    i = int(np.argmin(e))
    v["width"] = 0 < i < len(e) - 1
    return v


@dataclass
class ValidationData:
    """Everything ``docs/validation.md`` reports, computed by :func:`compute_validation` and
    turned into Markdown by :func:`render_validation` (issue 19: compute apart from render).

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
    #: the ring pack (SPEC 14, issue 17): see ring_pack_validation
    ring_pack: dict
    #: oil to the chamber against the supply film (issue 16): see oil_sensitivity
    oil: dict
    #: wall time of the whole regeneration [s] (set by validate)
    seconds: float = 0.0


#: Supply films [m] of the oil-sensitivity table (issue 16).
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
    "study optimum (1.004 mm, 8 N/m)": {},
    "narrowest (0.54 mm)": {"width": 0.54e-3},
    "widest (1.34 mm)": {"width": 1.34e-3},
    "26 N/m tension": {"tension": 26.0},
}
#: Engine speeds of the story: the study's and the CRF450R's rev limit [r/min].
STORY_SPEEDS = (4000.0, 12000.0)


def oil_sensitivity(root: str | os.PathLike = ".") -> dict:
    """Oil to the chamber and energy against the supply film on the shipped decks, starved
    JFO film, the decks' own preset (issue 16).

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
    """The ring pack on the shipped decks and the ring engineer's story (issue 17).

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
    )


def write_figures(data: ValidationData, root: str | os.PathLike, figdir: str | os.PathLike) -> list[Path]:
    """The study's Figs 2 (gas traces) and 11 (cold against hot) into ``figdir``."""
    figdir = Path(figdir)
    files = plot_results([data.results["cold"], data.results["hot"]], figdir, stem="fig11_cold_vs_hot")
    traces = {}
    for name in ("crf450r_4000rpm_full", "crf450r_3000rpm_half"):
        traces[name] = gas.read_csv(Path(root) / "inputs" / "pressure" / f"{name}.csv")
    fig = gas_figure(traces)
    for fmt in ("png", "pdf"):
        path = figdir / f"fig2_gas_pressure.{fmt}"
        files.append(save_figure(fig, path, dpi=150, metadata=save_metadata(fmt)))
    return files


def validate(root: str | os.PathLike = ".", out: str | os.PathLike = "docs") -> Path:
    """Regenerate ``OUT/validation.md`` and ``OUT/figures/`` from the shipped decks.

    Parameters
    ----------
    root : path
        Project folder (with ``inputs/``).
    out : path
        Output folder.

    Returns
    -------
    Path
        The Markdown file written.

    Raises
    ------
    InputError
        If a shipped deck or the targets file is bad.

    Examples
    --------
    >>> validate(".", "docs")  # doctest: +SKIP
    PosixPath('docs/validation.md')
    """
    t0 = time.perf_counter()
    root, out = Path(root), Path(out)
    figdir = out / "figures"
    figdir.mkdir(parents=True, exist_ok=True)
    check_output(
        out / "validation.md",
        [root / "inputs" / "crf450r_4000rpm_full_cold.nml", root / "inputs" / "crf450r_4000rpm_full_hot.nml"],
    )
    data = compute_validation(root)
    write_figures(data, root, figdir)
    data.seconds = time.perf_counter() - t0
    return write_text(out / "validation.md", render_validation(data))


def render_validation(data: ValidationData) -> str:
    """The Markdown of ``docs/validation.md`` from computed data (no run, no file).

    Parameters
    ----------
    data : ValidationData
        What :func:`compute_validation` returned (``seconds`` set by the caller).

    Returns
    -------
    str

    Examples
    --------
    >>> text = render_validation(compute_validation("."))  # doctest: +SKIP
    >>> text.splitlines()[0]  # doctest: +SKIP
    '# Validation against the source study (Table 2)'
    """
    cases, results = data.cases, data.results
    md: list[str] = []
    md += [
        "# Validation against the source study (Table 2)",
        "",
        "Regenerated by `ringlube validate` (this file and `docs/figures/`). "
        "4000 r/min full load, the study's optimum ring (width 1.004 mm, crown 9.31 um, "
        "offset -38.3 um, tension 8), shipped decks `inputs/crf450r_4000rpm_full_{cold,hot}.nml` "
        "with `inputs/calibration.nml`, preset 'default'.",
        "",
        "**The cold case is the calibration target; the hot case is a prediction** (nothing "
        "was fitted to it).",
        "",
        "## Published against computed",
        "",
        "| condition | quantity | published | ringlube | difference |",
        "|---|---|---|---|---|",
    ]
    for k in ("cold", "hot"):
        r, p = results[k], PUBLISHED[k]
        md.append(
            f"| {k} | energy loss (J/cycle) | {p['energy_loss']:.2f} | {r.energy_loss:.3f} | "
            f"{(r.energy_loss - p['energy_loss']) / p['energy_loss']:+.1%} |"
        )
        md.append(
            f"| {k} | mixed/boundary share (%) | {p['mixed_share']:.2f} | {r.mixed_share:.2f} | "
            f"{r.mixed_share - p['mixed_share']:+.2f} points |"
        )
        md.append(f"| {k} | ring mass (g) | {p['ring_mass']:.0f} | {r.ring_mass:.2f} | see below |")
    rc, rh = results["cold"], results["hot"]
    md += [
        "",
        f"Hot against cold: energy {rh.energy_loss / rc.energy_loss - 1:+.1%} "
        f"(study +26.6 %), mixed share {rh.mixed_share - rc.mixed_share:+.2f} points (study +4.03).",
        "",
        f"**Ring mass.** ringlube gives {rc.ring_mass:.2f} g from SPEC 8 with the assumed radial depth "
        "3.5 mm and steel density 7800 kg/m^3. The study reports 24 g, which no realistic radial depth "
        f"gives for a 1 mm wide ring in a 96 mm bore: 24 g would need a radial depth of "
        f"{data.depth_24g * 1e3:.1f} mm. We report our mass and do not tune to 24 g.",
        "",
    ]
    fit, jac, corr = data.fit, data.jac, data.corr
    md += [
        "## Calibration (cold only)",
        "",
        f"Two targets (cold energy {fit.targets['energy_loss']:g} J, cold mixed share "
        f"{fit.targets['mixed_share']:g} %) determine two continuous inputs; "
        "the discrete options the study leaves open are enumerated (see `pydriver/ringlube/calibrate.py`).",
        "",
        "| input | bounds | fitted |",
        "|---|---|---|",
        f"| `&surface zeta_kappa_sigma` | {BOUNDS['zeta_kappa_sigma']} | {fit.zeta_kappa_sigma:.4g}"
        f"{' (at the upper bound)' if fit.zeta_kappa_sigma >= BOUNDS['zeta_kappa_sigma'][1] else ''} |",
        f"| `&operating pressure_scale` | {BOUNDS['pressure_scale']} | {fit.pressure_scale:.4g} |",
    ]
    for (g, k), v in fit.options.items():
        md.append(f"| `&{g} {k}` | choice | '{v}' |")
    tg = fit.targets
    md += [
        "",
        f"Fit: energy {fit.energy_loss:.4f} J "
        f"({(fit.energy_loss - tg['energy_loss']) / tg['energy_loss']:+.1%}), "
        f"mixed share {fit.mixed_share:.3f} % ({fit.mixed_share - tg['mixed_share']:+.3f} points). "
        f"Sensitivity d(target/target)/d(ln input), rows energy and mixed, columns zeta_kappa_sigma and "
        f"pressure_scale: [[{jac[0, 0]:.3f}, {jac[0, 1]:.3f}], [{jac[1, 0]:.3f}, {jac[1, 1]:.3f}]]; "
        f"correlation of the two fitted inputs {corr:+.2f}.",
        "Re-running the fit reproduces the shipped `inputs/calibration.nml`: "
        f"{'yes' if data.same else 'NO'}.",
        "",
        "All combinations of the discrete options (each with its own two-input fit):",
        "",
        "| tension_unit | contact_area | outlet | zeta_kappa_sigma | pressure_scale | energy J "
        "| mixed % | residual |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for f in sorted(data.fits, key=lambda f: f.residual):
        o = list(f.options.values())
        md.append(
            f"| {o[0]} | {o[1]} | {o[2]} | {f.zeta_kappa_sigma:.4f} | {f.pressure_scale:.4f} | "
            f"{f.energy_loss:.4f} | {f.mixed_share:.3f} | {f.residual:.3f} |"
        )
    md += [
        "",
        "The 'N/m' reading of the tension (radial force per unit circumference, p_e = tension/b) "
        "is the one the published cold numbers support: with 'N' (tangential force, p_e = F_T/(b r0)) "
        "the elastic pressure is 20 times larger and no input within its bounds brings the mixed share "
        "and the energy to the published pair together.",
        "",
    ]

    # sensitivity, one at a time
    md += [
        "## Sensitivity to the assumed inputs (one at a time, -10 % / +10 %)",
        "",
        "Change of each compared number, in % of its value (mixed share: in points).",
        "",
        "| input | value | cold energy | cold mixed (pts) | hot energy | hot mixed (pts) | mass |",
        "|---|---|---|---|---|---|---|",
    ]
    for group, name, v0, runs, mass in data.sensitivity:
        cells = []
        for k in ("cold", "hot"):
            rs, r0 = runs[k], results[k]
            lo, hi = (r.energy_loss / r0.energy_loss - 1 for r in rs)
            cells.append(f"{lo:+.1%} / {hi:+.1%}")
            cells.append(
                f"{rs[0].mixed_share - r0.mixed_share:+.2f} / {rs[1].mixed_share - r0.mixed_share:+.2f}"
            )
        mcell = f"{mass[0] / rc.ring_mass - 1:+.1%} / {mass[1] / rc.ring_mass - 1:+.1%}" if mass else "0"
        md.append(f"| `&{group} {name}` | {v0:g} | {' | '.join(cells)} | {mcell} |")

    md += [
        "",
        "Gas trace: its peak is varied through `pressure_scale` above; its crank angle by "
        "shifting the combustion part of the trace (the closed cycle 200-490 deg) by -5 / +5 deg:",
        "",
        "| shift | cold energy | cold mixed (pts) | hot energy | hot mixed (pts) |",
        "|---|---|---|---|---|",
    ]
    for shift, rs in data.shifts:
        cells = []
        for k in ("cold", "hot"):
            r, r0 = rs[k], results[k]
            cells += [f"{r.energy_loss / r0.energy_loss - 1:+.1%}", f"{r.mixed_share - r0.mixed_share:+.2f}"]
        md.append(f"| {shift:+.0f} deg | {' | '.join(cells)} |")

    # modelling options
    md += [
        "",
        "## Modelling options (each flipped alone)",
        "",
        "| option | shipped | flipped to | cold energy | cold mixed (pts) | hot energy | hot mixed (pts) |",
        "|---|---|---|---|---|---|---|",
    ]
    for group, name, v0, v1, rs in data.options:
        cells = []
        for k in ("cold", "hot"):
            r, r0 = rs[k], results[k]
            cells += [f"{r.energy_loss / r0.energy_loss - 1:+.1%}", f"{r.mixed_share - r0.mixed_share:+.2f}"]
        md.append(f"| `&{group} {name}` | {v0!r} | {v1!r} | {' | '.join(cells)} |")

    # trends
    md += [
        "",
        "## Published trends on the calibrated model",
        "",
        "Energy loss (J/cycle) along each design variable, the others at the optimum ring, cold and hot.",
        "",
    ]
    for k in ("cold", "hot"):
        md += [
            f"**{k}**",
            "",
            "| variable | values | energy loss | study says | ringlube agrees |",
            "|---|---|---|---|---|",
        ]
        for name, _, says in TRENDS:
            xs, e = data.sweeps[k][name]
            scale = 1e6 if name != "tension" else 1.0
            md.append(
                f"| {name} | {xs[0] * scale:g} .. {xs[-1] * scale:g} | "
                f"{' '.join(f'{v:.3f}' for v in e)} | {says} | {'yes' if data.verdicts[k][name] else 'NO'} |"
            )
        md.append("")
    md += [
        "Where ringlube disagrees (see the tests in `tests/python/test_validation.py`, marked as "
        "expected failures that name the disagreement):",
        "",
        "- *crown height*: with the calibrated lumped contact area the asperity load acts over the whole "
        "face at lambda = h0/sigma; a higher crown narrows the load-carrying wedge, lowers h0 and raises "
        "the boundary friction, so energy rises with crown height. With `contact_area = 'local'` the "
        "boundary term is confined to the crown; the calibration does not select it (its cold fit is worse).",
        "- *offset*: in ringlube a positive offset (crown minimum towards the chamber) gives the "
        "lower energy, because on the high-load expansion stroke the inlet is the crankcase edge and a "
        "minimum towards the chamber gives that inlet a longer converging wedge. The study's opposite "
        "finding may reflect a different sign convention for x_s or the measured, not synthetic, gas "
        "pressure; SPEC 3 fixes the convention used here.",
        "- *width*: energy rises monotonically with width over 0.54-1.34 mm (larger wetted area, more "
        "viscous and boundary shear); the mixed share falls with width, so the study's interior optimum "
        "appears only when the mixed share is traded against energy (the optimisation, issue 5), not in "
        "energy alone.",
        "",
    ]

    # readings of the open modelling choices (issue 9)
    md += [
        "## Readings of the open choices: film model, contact area, tension unit (issue 9)",
        "",
        "Each reading with the shipped calibration (`zeta_kappa_sigma`, `pressure_scale`, fitted "
        "for the first row's reading), **not re-fitted per reading**: the per-reading calibration "
        "(cold Table 2 and trends, `supply_film` among the fitted inputs for starved readings) is "
        "[readings.md](readings.md), from `ringlube readings`. "
        "Trends on the cold case, 5 points per variable; 'yes' where the published direction "
        "appears. `conv` counts the cold and hot runs that converged (JFO runs hold h0 at its "
        "ceiling where the film carries more than the load: flagged, see docs/model.md).",
        "",
        "| film model | contact area | tension unit | cold energy J | cold mixed % | hot energy J "
        "| hot mixed % | tension | crown height | offset | width | trends | conv |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    pub = PUBLISHED
    for row in data.readings:
        c, h, v = row["cold"], row["hot"], row["verdicts"]
        if not hasattr(c, "energy_loss") or not hasattr(h, "energy_loss"):
            md.append(
                f"| {row['film']} | {row['area']} | {row['unit']} | failed: "
                f"{c if not hasattr(c, 'energy_loss') else h} |" + " |" * 9
            )
            continue
        md.append(
            f"| {row['film']} | {row['area']} | {row['unit']} | {c.energy_loss:.3f} "
            f"({(c.energy_loss / pub['cold']['energy_loss'] - 1):+.0%}) | {c.mixed_share:.2f} | "
            f"{h.energy_loss:.3f} ({(h.energy_loss / pub['hot']['energy_loss'] - 1):+.0%}) | "
            f"{h.mixed_share:.2f} | "
            + " | ".join("yes" if v[n] else "no" for n, _, _ in TRENDS)
            + f" | {sum(v.values())}/4 | {int(c.converged) + int(h.converged)}/2 |"
        )
    md += [
        "",
        "No reading gives all four published trends together with Table 2 within 5 % energy "
        "and 1.5 points mixed share (see the rows above for which comes closest and what each "
        "misses). Fitted per reading ([readings.md](readings.md)), none does either; the shipped "
        "default stays the source study's reading (Swift-Stieber, lumped contact, N/m) with the "
        "shipped calibration, for the reasons in docs/model.md ('Which reading is the default').",
        "",
    ]
    md += _render_oil(data.oil)
    md += _render_ring_pack(data.ring_pack, cases["cold"])

    md += [
        "## Figures",
        "",
        "Gas pressure (synthetic traces, study Fig 2; the decks use them times `pressure_scale`):",
        "",
        "![gas](figures/fig2_gas_pressure.png)",
        "",
        "Minimum film thickness and friction over the cycle, cold and hot (study Fig 11):",
        "",
        "![film](figures/fig11_cold_vs_hot_film.png)",
        "",
        "![friction](figures/fig11_cold_vs_hot_friction.png)",
        "",
        f"_Generated in {data.seconds:.0f} s._",
        "",
    ]
    return "\n".join(md)


def _render_oil(oil: dict) -> list[str]:
    """The oil-sensitivity section (issue 16): energy and oil to the chamber against the
    supply film on the shipped decks with the starved JFO film."""
    md = [
        "## Oil to the chamber against the supply film (issue 16)",
        "",
        "The starved JFO film (`&physics cavitation = 'jfo', inlet = 'starved'`) on the four shipped "
        "decks with their calibration and preset ('default'), `&lubricant supply_film` (the oil film "
        "the ring below leaves on the liner, assumed: default 1 um) from 0.5 to 10 um. Each cell: "
        "energy loss (J/cycle), oil left to the chamber (`oil_to_chamber`, mm^3 per cycle); "
        "'not conv.' where the run did not reach a periodic cycle.",
        "",
        "| deck | " + " | ".join(f"{h * 1e6:g} um" for h in SUPPLY_FILMS) + " |",
        "|---|" + "---|" * len(SUPPLY_FILMS),
    ]
    for label, runs in oil.items():
        cells = []
        for _, r in runs:
            if not hasattr(r, "energy_loss"):
                cells.append(f"failed: {r}")
                continue
            cells.append(
                f"{r.energy_loss:.3f} J, {r.oil_to_chamber:.3g}" + ("" if r.converged else " (not conv.)")
            )
        md.append(f"| {label} | {' | '.join(cells)} |")
    md += [
        "",
        "The oil to the chamber is the least certain result of the starved film: it grows by more "
        "than three orders of magnitude from 1 to 10 um of supply film, while the energy changes by "
        "tens of per cent, and at 0.5-1 um it sits at the same small value on several decks (the film "
        "the ring leaves near top dead centre; not investigated further). Set `supply_film` from a "
        "measurement or from a model of the ring below before comparing designs by oil "
        "(docs/own_engine.md).",
        "",
    ]
    return md


def _charge_mg(case: Case) -> float:
    """Swept volume of the case's engine at 0.1 MPa and 300 K [mg]."""
    swept = np.pi * case.value("engine", "bore_radius") ** 2 * 2 * case.value("engine", "crank_radius")
    return 1e5 * swept / (287.0 * 300.0) * 1e6


def _render_ring_pack(rp: dict, cold: Case) -> list[str]:
    """The ring-pack section (issue 17): the shipped decks with the gas network, what published
    work says about blowby and the land pressure, and the ring engineer's story."""
    charge = _charge_mg(cold)
    md = [
        "## The gas around the ring: blowby, inter-ring pressure, ring lift (SPEC 14, issue 17)",
        "",
        "The shipped decks with `&physics ring_pack = 'gas'` (groove and second-land gas, end-gap "
        "orifices, flank channels, the ring's axial motion: docs/ring_pack.md), the `&ring_pack` "
        "defaults (all assumed for this engine: 0.1 mm^2 top and 0.15 mm^2 second gap, 40 um axial "
        "clearance, 0.1 cm^3 groove and 0.5 cm^3 land volume, gas at 450 K) and the shipped "
        "calibration (fitted without the ring pack). Charge: the swept volume at 0.1 MPa and 300 K, "
        f"{charge:.0f} mg.",
        "",
        "| deck | energy J/cycle | mixed % | blowby L/min | blowby mg/cycle | % of charge "
        "| blowback mg/cycle | ring lift % of cycle | flutter events | peak land pressure | at | "
        "peak land / peak chamber | gas balance |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for k, r in rp["decks"].items():
        kl = int(np.argmax(r.land_pressure))
        md.append(
            f"| {k} | {r.energy_loss:.3f} | {r.mixed_share:.2f} | {r.blowby:.2f} | {r.blowby_mass:.2f} | "
            f"{r.blowby_mass / charge:.2%} | {r.blowback_mass:.2f} | {r.ring_lift_share:.1f} | "
            f"{r.flutter_events:.0f} | {r.land_pressure[kl] / 1e5:.2f} bar | "
            f"{r.crank_angle_deg[kl]:.0f} deg | {r.land_pressure.max() / r.gas_pressure.max():.3f} | "
            f"{r.gas_balance_error:.1e} |"
        )
    cold = rp["decks"]["cold"]
    lag = (
        cold.crank_angle_deg[np.argmax(cold.land_pressure)]
        - cold.crank_angle_deg[np.argmax(cold.gas_pressure)]
    )
    ratio = cold.land_pressure.max() / cold.gas_pressure.max()
    md += [
        "",
        "**Against published measurements and model results.** No digitised blowby or second-land "
        "pressure of an engine of this bore (96 mm) and speed (4000-12,000 r/min) was found in the "
        "sources searched for this work; what they give, and how the model compares:",
        "",
        "- Blowby is about 0.5-2 % of the gas volume even with good sealing, and the leakage loss "
        "below 1 % in engines in good condition (the 'Blowby' article of the German Wikipedia, English "
        f"mirror https://de.zxc.wiki/wiki/Blowby). The model gives {cold.blowby_mass / charge:.2%} of "
        "the charge at 4000 r/min full load: the right order, at the low end, as it should be for a "
        "perfectly conforming ring on a round bore (no bore distortion, no ring-face leakage, the "
        "second ring always on its lower flank: a lower bound).",
        "- Namazian and Heywood (1982, SAE 820088; known here from its summaries, not read) measured "
        "and modelled the crevice pressures of a spark-ignition engine: the pressure between the rings "
        "rises after the chamber's and peaks "
        "well after it, at a fraction of it, and stays above the chamber late in the cycle so that "
        "gas flows back (their Fig. 15 network is reproduced in the ANSYS Forte theory manual, ch. 9, "
        "https://ansyshelp.ansys.com/public/Views/Secured/corp/v242/en/forte_th/pgfId-1077450.html). "
        f"The model's land pressure peaks {lag:.0f} deg after the chamber at {ratio:.1%} of its peak, "
        "and the blowback exceeds the blowby: the same behaviour. The ratio depends on the gap areas "
        "and volumes, which are assumed here.",
        "- A military maintenance manual allows at most 6 m^3/h (100 L/min) of blowby at rated speed "
        "and load for a run-in engine (TM 9-2815-255-24, para. 3-6, "
        "http://automotiveenginemechanics.tpub.com/TM-9-2815-255-24/css/TM-9-2815-255-24_45.htm; a "
        "large multi-cylinder diesel, so an upper bound far above a 450 cm^3 single).",
        "",
        "Inputs assumed for the comparison, since the sources do not give them for this engine: the "
        "gap areas, volumes, clearance and gas temperature above, and the synthetic gas trace. Open: "
        "a measured blowby of a 450 cm^3 single-cylinder engine at full load, and a measured "
        "second-land pressure trace with the engine's gap areas and volumes.",
        "",
        "**For a ring engineer** (cold deck with the ring pack, the 4000 r/min full-load trace at "
        "both speeds: the synthetic trace is in crank angle and does not change with speed; ring "
        "variants from the study's ranges):",
        "",
        "| speed r/min | ring | energy J/cycle | friction power W | blowby L/min | ring lift % "
        "| flutter events | converged |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for speed, name, r in rp["story"]:
        if not hasattr(r, "energy_loss"):
            md.append(f"| {speed:.0f} | {name} | failed: {r} |" + " |" * 5)
            continue
        md.append(
            f"| {speed:.0f} | {name} | {r.energy_loss:.3f} | {r.friction_power:.1f} | {r.blowby:.2f} | "
            f"{r.ring_lift_share:.1f} | {r.flutter_events:.0f} | {'yes' if r.converged else 'no'} |"
        )
    md += [
        "",
        "Blowby hardly depends on the ring's face (the end gaps decide it); a narrow ring saves "
        "friction at both speeds; at the rev limit the heavier rings leave their lower flank against "
        "the gas (flutter) and the narrowest one does not. The tension (8 vs 26 N/m, both small "
        "against the gas load in the shipped 'N/m' reading) changes nothing the ring pack sees. The "
        "readings of the open choices re-run with the ring pack, and why the shipped default stays "
        "`ring_pack = 'none'`: docs/ring_pack.md.",
        "",
    ]
    return md


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
