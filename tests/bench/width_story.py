"""The width story of docs/width.md, "Width: the crown at the edges or over a gauge length"
(not a test; every number of that page is printed by this script). Run from the project
folder:

    .venv/bin/python tests/bench/width_story.py readings [--preset default|accurate]
    .venv/bin/python tests/bench/width_story.py mechanism
    .venv/bin/python tests/bench/width_story.py gas [--supply-film 2e-6]
    .venv/bin/python tests/bench/width_story.py doe

The source ring (width 1.004 mm, crown 9.31 um) on the shipped 4000 r/min full-load decks,
in both readings of the tension ('N/m', 'N'), each with its own calibration: the cold Table 2
fit ``ringlube calibrate`` makes in that unit with the decks' contact area and outlet
('lumped', 'reynolds'), computed first (``--calibration FILE`` takes that file's values for
both units instead); in two face profiles:

- 'edge' (the default, the source study's): the crown height reached at the face's edges, so a
  wider ring with the same crown is a flatter ring;
- 'gauge': the same barrel given as a drop (9.31 um) at a fixed gauge length (0.502 mm, half the
  source ring's width) from the crown point, as ring drawings give it, so a wider ring keeps the
  barrel's curvature and grows at its edges.

At 1.004 mm the two are the same face (checked here run by run, to the bit).

``readings``: every reading of the open choices (film model x contact area x tension unit,
``ringlube.readings.all_readings``), the calibration of its tension unit (not re-fitted per
film model or contact area), the
width swept over the study's range (9 points, 0.54-1.34 mm; every other point is the 5-point
sweep of the readings' published-trend verdict) on the cold and hot decks, in both profiles:
the shape of each sweep, and how many readings give the width optimum.

``mechanism``: the source study's film model and contact (Swift-Stieber, lumped), cold, in
both tension units: per width the peak load on the ring's back (elastic + gas), the film at
that crank angle and at mid-intake (little gas), the viscous and boundary parts of the energy.

``gas``: the shipped decks as they are (their tension unit and calibration file) with the
starved mass-conserving film (on ``--supply-film``, default 2 um) and the ring pack's gas: per
width and profile the energy, mixed share, oil to the chamber, blowby and least film, and the
shape of each against the width.

``doe``: the source study's procedure, ``ringlube optimise`` (Sobol DOE of 1025 runs per
case over the study's four variables, full quadratic surfaces, NSGA-II 100 x 100 x 5, the
chosen designs re-run by the true model) on the cold and hot decks with the 'edge' face, in
both tension units; then the surface and the true model along the width through the
reference ring and through the study's chosen lowest-energy design.
"""

from __future__ import annotations

import argparse
import contextlib
import io
import os
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np

import ringlube
from ringlube import Case
from ringlube.readings import all_readings
from ringlube.study.variables import DESIGN_RANGES

ROOT = Path(__file__).resolve().parents[2]
DECKS = {
    "cold": ROOT / "inputs" / "crf450r_4000rpm_full_cold.nml",
    "hot": ROOT / "inputs" / "crf450r_4000rpm_full_hot.nml",
}
SOURCE_WIDTH = 1.004e-3
SOURCE_CROWN = 9.31e-6
#: the source ring's crown as a drop at half its width (the 'gauge' reading of the same face)
GAUGE = {
    "profile": "gauge",
    "gauge_length": SOURCE_WIDTH / 2,
    "gauge_drop_top": SOURCE_CROWN,
    "gauge_drop_bottom": SOURCE_CROWN,
}
PROFILES = {"edge": {}, "gauge": GAUGE}
#: the width sweep: the readings' 5 points (the study's range) and their midpoints
WIDTHS = np.linspace(*DESIGN_RANGES["width"], 9)
WIDTHS[::2] = np.linspace(*DESIGN_RANGES["width"], 5)


UNITS = ("N/m", "N")


def calibrations(calibration: str | None) -> dict[str, dict]:
    """The calibrated inputs of each tension reading: by default each unit's own cold fit with
    the decks' contact area and outlet ('lumped', 'reynolds'), the fit ``ringlube calibrate``
    makes for that reading (:func:`ringlube.calibrate.cold.fit_options` on the cold Table 2
    targets); with ``calibration`` the values of that file for both units."""
    from ringlube.calibrate.cold import cold_targets, fit_options, strip_calibrated

    out = {}
    if calibration:
        c = Case.from_namelist(calibration)
        values = {k: c.get(*k) for k in (("surface", "zeta_kappa_sigma"), ("operating", "pressure_scale"))}
        return {u: {**values, "source": str(calibration)} for u in UNITS}
    cold = Case.from_namelist(DECKS["cold"])
    _, targets = cold_targets()
    for u in UNITS:
        options = {
            ("ring", "tension_unit"): u,
            ("physics", "contact_area"): "lumped",
            ("physics", "outlet"): "reynolds",
        }
        fit = fit_options(strip_calibrated(cold), options, targets)
        out[u] = {
            ("surface", "zeta_kappa_sigma"): fit.zeta_kappa_sigma,
            ("operating", "pressure_scale"): fit.pressure_scale,
            "source": f"cold fit in {u} (energy {fit.energy_loss:.4f} J, mixed {fit.mixed_share:.3f} %)",
        }
    return out


def calibration_text(cal: dict) -> str:
    return "; ".join(
        f"{u}: zeta_kappa_sigma {v[('surface', 'zeta_kappa_sigma')]:.4g}, "
        f"pressure_scale {v[('operating', 'pressure_scale')]:.4g} ({v['source']})"
        for u, v in cal.items()
    )


def decks(cal: dict, unit: str, preset: str | None = None) -> dict[str, Case]:
    """The shipped cold and hot decks read in ``unit`` with that unit's calibrated inputs (the
    calibration file replaced by its values)."""
    from ringlube.calibrate.cold import strip_calibrated

    out = {}
    for k, path in DECKS.items():
        c = strip_calibrated(Case.from_namelist(path)).with_ring(tension_unit=unit)
        for (group, name), value in ((k_, v) for k_, v in cal[unit].items() if k_ != "source"):
            c = c.with_(group, **{name: float(value)})
        if preset:
            c = c.with_numerics(preset=preset)
        out[k] = c
    return out


def shape(w: np.ndarray, e: np.ndarray) -> str:
    """A sweep's shape in words: 'rises', 'falls', the interior minimum (its width and how far
    below the lower end it lies), or 'not monotone' with where its lowest point is."""
    e = np.asarray(e, float)
    if not np.all(np.isfinite(e)):
        return "failed"
    d = np.diff(e)
    if np.all(d > 0):
        return "rises"
    if np.all(d < 0):
        return "falls"
    i = int(np.argmin(e))
    if 0 < i < len(e) - 1:
        return f"min {w[i] * 1e3:.2f} mm ({e[i] / min(e[0], e[-1]) - 1:+.1%})"
    return f"not monotone, lowest at {w[i] * 1e3:.2f} mm"


def interior(e: np.ndarray) -> bool:
    """The readings' verdict on a width sweep: its lowest point is not at an end."""
    i = int(np.argmin(e))
    return bool(np.all(np.isfinite(e))) and 0 < i < len(e) - 1


def _energies(results) -> np.ndarray:
    return np.array([getattr(r, "energy_loss", np.nan) for r in results])


def readings(cal: dict, preset: str, workers: int) -> None:
    t0 = time.perf_counter()
    base = {u: decks(cal, u, preset) for u in UNITS}
    plan, keys = [], []
    for rd in all_readings():
        for k, case in base[rd.unit].items():
            for prof, ring in PROFILES.items():
                c = rd.apply(case).with_ring(**ring)
                keys.append((rd, k, prof))
                plan += [c.with_ring(width=float(w)) for w in WIDTHS]
                plan.append(c.with_ring(width=SOURCE_WIDTH))  # the same face in both profiles
    rs = ringlube.run_many(plan, workers=workers, progress=False, on_error="return")
    n = len(WIDTHS) + 1
    sweeps = {}
    for j, key in enumerate(keys):
        part = rs[j * n : (j + 1) * n]
        sweeps[key] = (_energies(part[:-1]), part[-1], sum(not getattr(r, "converged", False) for r in part))
    print(f"preset '{preset}'; widths (mm) {' '.join(f'{w * 1e3:.2f}' for w in WIDTHS)}")
    print()
    print("| film model | contact area | tension unit | edge, cold | edge, hot | gauge, cold | gauge, hot |")
    print("|---|---|---|---|---|---|---|")
    counts = {(p, k, n): 0 for p in PROFILES for k in DECKS for n in (9, 5)}
    rises = {(p, k): 0 for p in PROFILES for k in DECKS}
    same = True
    for rd in all_readings():
        cells = [rd.film, rd.area, rd.unit]
        for prof in PROFILES:
            for k in DECKS:
                e, at_source, bad = sweeps[(rd, k, prof)]
                cells.append(shape(WIDTHS, e) + (f" ({bad} not conv.)" if bad else ""))
                counts[(prof, k, 9)] += interior(e)
                counts[(prof, k, 5)] += interior(e[::2])
                rises[(prof, k)] += bool(np.all(np.diff(e) > 0))
        for k in DECKS:
            a, b = sweeps[(rd, k, "edge")][1], sweeps[(rd, k, "gauge")][1]
            same &= getattr(a, "energy_loss", 1.0) == getattr(b, "energy_loss", 2.0)
        print("| " + " | ".join(cells) + " |")
    print()
    for prof in PROFILES:
        for k in DECKS:
            print(
                f"{prof}, {k}: rises in {rises[(prof, k)]} of 20; interior minimum in "
                f"{counts[(prof, k, 9)]} of 20 (9 points), {counts[(prof, k, 5)]} of 20 "
                "(the readings' 5 points)"
            )
    print(f"'edge' and 'gauge' at {SOURCE_WIDTH * 1e3:.3f} mm: the same energy in every reading: {same}")
    print("\nenergy loss (J) at the widths above:")
    for (rd, k, prof), (e, _, _) in sweeps.items():
        print(f"  {rd.id:32s} {k:4s} {prof:5s} " + " ".join(f"{x:.3f}" for x in e))
    print(f"{len(plan)} runs, {time.perf_counter() - t0:.0f} s on {workers} workers")


def shipped(supply_film: float) -> dict[str, Case]:
    """The shipped cold and hot decks as they are (their tension unit and calibration file) with
    the film that reports oil and the gas that reports blowby: the starved mass-conserving film
    on ``supply_film`` of oil and the ring pack's gas."""
    return {
        k: Case.from_namelist(path)
        .with_("physics", cavitation="jfo", inlet="starved", ring_pack="gas")
        .with_("lubricant", supply_film=supply_film)
        for k, path in DECKS.items()
    }


def gas(supply_film: float, workers: int) -> None:
    t0 = time.perf_counter()
    base = shipped(supply_film)
    plan, keys = [], []
    for k, case in base.items():
        for prof, ring in PROFILES.items():
            keys.append((k, prof))
            plan += [case.with_ring(**ring).with_ring(width=float(w)) for w in WIDTHS]
    rs = ringlube.run_many(plan, workers=workers, progress=False, on_error="return")
    cold = base["cold"]
    print(
        f"shipped decks (tension {cold.get('ring', 'tension'):g} {cold.get('ring', 'tension_unit')}, "
        f"their calibration), cavitation 'jfo', inlet 'starved', supply_film {supply_film * 1e6:g} um, "
        "ring_pack 'gas'"
    )
    n = len(WIDTHS)
    got = {key: rs[j * n : (j + 1) * n] for j, key in enumerate(keys)}

    def cell(r, what: str, fmt: str) -> str:
        if not hasattr(r, "energy_loss"):
            return "failed"
        return format(getattr(r, what), fmt) + ("" if r.converged else " (not conv.)")

    for k in base:
        print(f"\n{k} (each cell: 'edge' / 'gauge')\n")
        print(
            "| width mm | energy J | mixed % | oil to the chamber mm3/cycle | blowby L/min | least film um |"
        )
        print("|---|---|---|---|---|---|")
        for i, w in enumerate(WIDTHS):
            e, g = got[(k, "edge")][i], got[(k, "gauge")][i]
            cells = [f"{w * 1e3:.2f}"]
            for what, fmt in (
                ("energy_loss", ".3f"),
                ("mixed_share", ".2f"),
                ("oil_to_chamber", ".3g"),
                ("blowby", ".3f"),
            ):
                cells.append(f"{cell(e, what, fmt)} / {cell(g, what, fmt)}")
            cells.append(
                " / ".join(f"{r.min_film * 1e6:.3f}" if hasattr(r, "min_film") else "failed" for r in (e, g))
            )
            print("| " + " | ".join(cells) + " |")
        for what in ("energy_loss", "oil_to_chamber", "blowby"):
            print(
                f"{what}: "
                + "; ".join(
                    f"'{p}' {shape(WIDTHS, [getattr(r, what, np.nan) for r in got[(k, p)]])}"
                    for p in PROFILES
                )
            )
    print(f"\n{len(plan)} runs, {time.perf_counter() - t0:.0f} s on {workers} workers")


def _energy_split(r) -> tuple[float, float]:
    """The viscous and boundary parts of the energy loss (shares of |F U| over the cycle)."""
    u = np.abs(r.sliding_speed)
    v, b = np.sum(np.abs(r.viscous_friction) * u), np.sum(np.abs(r.boundary_friction) * u)
    return r.energy_loss * v / (v + b), r.energy_loss * b / (v + b)


def mechanism(cal: dict, workers: int) -> None:
    print("cold deck, Swift-Stieber film, lumped contact")
    for unit in UNITS:
        cold = decks(cal, unit)["cold"]
        for prof, ring in PROFILES.items():
            case = cold.with_ring(**ring)
            rs = ringlube.run_many(
                [case.with_ring(width=float(w)) for w in WIDTHS], workers=workers, progress=False
            )
            print(f"\ntension in {unit}, '{prof}'\n")
            print(
                "| width mm | peak load on the back N | at deg | film there um | film at 90 deg um "
                "| mean film 360-540 deg um | viscous J | boundary J | energy J | mixed % |"
            )
            print("|---|---|---|---|---|---|---|---|---|---|")
            for w, r in zip(WIDTHS, rs):
                psi = r.crank_angle_deg
                i = int(np.argmax(r.applied_load))
                expansion = (psi >= 360) & (psi <= 540)
                ev, eb = _energy_split(r)
                print(
                    f"| {w * 1e3:.2f} | {r.applied_load[i]:.0f} | {psi[i]:.0f} | {r.h0[i] * 1e6:.3f} "
                    f"| {np.interp(90.0, psi, r.h0) * 1e6:.2f} | {r.h0[expansion].mean() * 1e6:.3f} "
                    f"| {ev:.3f} | {eb:.3f} | {r.energy_loss:.3f} | {r.mixed_share:.2f} |"
                )


STUDY = """&study
  name = 'width_{tag}'
  cases = 'cold.nml', 'hot.nml'
  labels = 'cold', 'hot'
  variables = 'width', 'crown_height', 'crown_offset', 'tension'
  lower = 0.54e-3, 6e-6, -54e-6, 8.0
  upper = 1.34e-3, 13e-6, 67e-6, 26.0
  reference = 1.004e-3, 9.31e-6, -38.3e-6, 8.0
  objectives = 'energy_loss', 'mixed_share'
  sampler = 'sobol'
  samples = 1025
  surrogate = 'quadratic'
  population = 100, generations = 100, repeats = 5
  seed = 1
/
"""


def doe(cal: dict, workers: int) -> None:
    from ringlube.cli import main as cli
    from ringlube.study.deck import read_study
    from ringlube.study.store import Study
    from ringlube.study.surfaces import predict

    fine = np.linspace(*DESIGN_RANGES["width"], 161)
    print(
        "| tension unit | case | energy surface R² | along the width through | surface | true model "
        "| energy at that design J | true at 0.54 mm J |"
    )
    print("|---|---|---|---|---|---|---|---|")
    notes = []
    for unit in UNITS:
        with tempfile.TemporaryDirectory() as tmp:
            tmp = Path(tmp)
            for k, case in decks(cal, unit).items():
                case.with_("output", file=f"{k}.h5").to_namelist(tmp / f"{k}.nml")
            tag = unit.replace("/", "_per_")
            (tmp / "study.nml").write_text(STUDY.format(tag=tag))
            t0 = time.perf_counter()
            with contextlib.redirect_stdout(io.StringIO()):  # its 'written ...' line
                status = cli(
                    [
                        "optimise",
                        str(tmp / "study.nml"),
                        "--out",
                        str(tmp / "out"),
                        "-q",
                        "--workers",
                        str(workers),
                    ]
                )
            assert status == 0, f"ringlube optimise failed ({status})"
            notes.append(f"tension in {unit}: ringlube optimise {time.perf_counter() - t0:.0f} s")
            s = read_study(tmp / "study.nml")
            st = Study.open(s, tmp / "out" / f"width_{tag}.h5")
            j = s.outputs.index("energy_loss")
            for k in ("cold", "hot"):
                c = st.cases[k]
                best = np.asarray(c.chosen.x)[c.chosen.names.index("min energy_loss")]
                base = Case.from_namelist(tmp / f"{k}.nml")
                for what, x0 in (
                    ("reference ring", np.asarray(s.reference, float)),
                    ("chosen lowest energy", best),
                ):
                    xs = np.tile(x0, (len(fine), 1))
                    xs[:, 0] = fine
                    surf = predict(st, k, xs)[:, j]
                    xt = np.tile(x0, (len(WIDTHS), 1))
                    xt[:, 0] = WIDTHS
                    true, _, _ = ringlube.run_designs(base, s.variables, xt, ["energy_loss"])
                    at, _, _ = ringlube.run_designs(base, s.variables, x0[None, :], ["energy_loss"])
                    design = ", ".join(
                        f"{v} {x:.4g}" for v, x in zip(("b", "c", "x_s", "T"), x0 * [1e3, 1e6, 1e6, 1])
                    )
                    print(
                        f"| {unit} | {k} | {c.surfaces['energy_loss'].r2:.3f} | {what} ({design}) "
                        f"| {shape(fine, surf)} | {shape(WIDTHS, true[:, 0])} | {at[0, 0]:.3f} "
                        f"| {true[0, 0]:.3f} |"
                    )
    print()
    print("\n".join(notes))
    print("designs: b width mm, c crown height um, x_s crown offset um, T tension in the reading's unit")


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("part", choices=["readings", "mechanism", "gas", "doe"])
    p.add_argument(
        "--supply-film",
        type=float,
        default=2e-6,
        help="gas: the starved film's supply film, m (default 2e-6)",
    )
    p.add_argument(
        "--preset", default="default", help="numerics preset of the readings (default: the decks')"
    )
    p.add_argument(
        "--calibration",
        help="one calibration file for both tension readings (default: each reading's own cold fit)",
    )
    p.add_argument("--workers", type=int, default=os.cpu_count() or 1)
    a = p.parse_args()
    warnings.simplefilter("ignore", UserWarning)  # inputs a profile does not use are said, not errors
    if a.part == "gas":  # the shipped decks as they are: no calibration of its own
        gas(a.supply_film, a.workers)
        return
    t0 = time.perf_counter()
    cal = calibrations(a.calibration)
    print(f"calibration: {calibration_text(cal)} [{time.perf_counter() - t0:.0f} s]\n")
    {
        "readings": lambda: readings(cal, a.preset, a.workers),
        "mechanism": lambda: mechanism(cal, a.workers),
        "doe": lambda: doe(cal, a.workers),
    }[a.part]()


if __name__ == "__main__":
    main()
