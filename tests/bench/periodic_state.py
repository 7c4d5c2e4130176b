"""Benchmark (not a test): how many cycles the shipped decks need to reach their periodic state,
what that costs, and how far the answer accepted lies from the periodic state.

Every shipped case deck (``inputs/*.nml`` but the ``&study`` decks) with each film model
(Swift-Stieber, the mass-conserving film flooded and starved, each with vapour and trailing-gas
cavities), the tension read in N and in N/m: ``cycles_run``, ``cycles_computed``, kernel ms per
run (best of --repeats), whether the run converged, and with --ref the energy's and blowby's
relative difference to the same run at ``cycle_tol`` 1e-6 (``max_cycles`` 60). With a second
solver (--base, e.g. a build of an earlier commit, which has no &numerics accelerate) the same
for it side by side, and the means per film model and reading; --no-accelerate runs --solver
without the liner film's extrapolation, --pilot with the ring pack's pilot cycle
(``&numerics pilot_cycle``), --bdc-start with the starved warm-up's BDC start (``&numerics
bdc_start``, the default), --no-bdc-start without it, --liner-window N with the liner film's
change judged over N cells too (``&numerics liner_window``); --skip leaves out decks whose name
has one of the parts given (e.g. ``distorted``). Run from the project folder:

    .venv/bin/python tests/bench/periodic_state.py [--base BASE/ringlube-solve] [--ref]
        [--unit N] [--films starved,...] [--decks 12000,...] [--skip distorted] [--repeats 3]
        [--no-accelerate] [--pilot] [--bdc-start | --no-bdc-start] [--liner-window 50]
"""

from __future__ import annotations

import argparse
import os
import subprocess
import tempfile
from pathlib import Path

import h5py
import numpy as np

import ringlube

ROOT = Path(__file__).resolve().parents[2]
INPUTS = ROOT / "inputs"
FILMS = {
    "swift_stieber": {},
    "flooded": {"cavitation": "jfo"},
    "flooded_tg": {"cavitation": "jfo", "cavity_pressure": "trailing_gas"},
    "starved": {"cavitation": "jfo", "inlet": "starved"},
    "starved_tg": {"cavitation": "jfo", "inlet": "starved", "cavity_pressure": "trailing_gas"},
}
KEYS = ("cycles_run", "cycles_computed", "converged", "energy_loss_J", "blowby_l_min", "run_time_s")


def decks() -> list[Path]:
    """The shipped case decks (not the study decks nor the calibration files)."""
    return [
        p
        for p in sorted(INPUTS.glob("*.nml"))
        if "&study" not in p.read_text() and not p.name.startswith("calibration")
    ]


def run(solver: str, case: ringlube.Case, repeats: int) -> dict:
    """One case through one solver (the deck written beside the shipped ones, so that its
    relative paths hold): its results, the run time the best of `repeats`."""
    fd, name = tempfile.mkstemp(suffix=".nml", prefix="_periodic_state", dir=INPUTS)
    os.close(fd)
    deck = Path(name)
    out = deck.with_suffix(".h5")
    case.to_namelist(deck)
    best = None
    try:
        for _ in range(repeats):
            subprocess.run([solver, str(deck), "-o", str(out), "-q"], check=False)
            with h5py.File(out) as f:
                r = {k: float(f.attrs[k]) if k in f.attrs else np.nan for k in KEYS}
            if best is None or r["run_time_s"] < best["run_time_s"]:
                best = r
    finally:
        deck.unlink()
        out.unlink(missing_ok=True)
    return best


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--solver", default=str(ROOT / "build" / "ringlube-solve"))
    ap.add_argument("--base", help="a second ringlube-solve to compare with")
    ap.add_argument("--ref", action="store_true", help="also the distance to cycle_tol 1e-6")
    ap.add_argument("--unit", default="N,N/m", help="tension readings, comma-separated")
    ap.add_argument("--films", default=",".join(FILMS))
    ap.add_argument("--decks", default="", help="deck name parts, comma-separated (default all)")
    ap.add_argument("--repeats", type=int, default=1)
    ap.add_argument("--no-accelerate", action="store_true", help="--solver's runs without extrapolation")
    ap.add_argument("--pilot", action="store_true", help="--solver's runs with pilot_cycle")
    ap.add_argument("--bdc-start", action="store_true", help="--solver's runs with bdc_start")
    ap.add_argument("--no-bdc-start", action="store_true", help="--solver's runs with bdc_start .false.")
    ap.add_argument("--liner-window", type=int, default=0, help="--solver's runs with this liner_window")
    ap.add_argument("--skip", default="", help="deck name parts to leave out, comma-separated")
    args = ap.parse_args()
    solvers = [("new", args.solver)] + ([("base", args.base)] if args.base else [])
    parts = [d for d in args.decks.split(",") if d]
    skip = [d for d in args.skip.split(",") if d]
    chosen = [
        p
        for p in decks()
        if (not parts or any(d in p.name for d in parts)) and not any(d in p.name for d in skip)
    ]
    head = f"{'deck':34s} {'unit':4s} {'film':14s}"
    for label, _ in solvers:
        head += f" | {label}: cyc  comp   ms/run conv   energy J"
        head += "  dE ref  dBb ref" if args.ref else ""
    print(head)
    sums: dict = {}
    for unit in args.unit.split(","):
        for film in args.films.split(","):
            for deck in chosen:
                case = ringlube.Case.from_namelist(deck).with_ring(tension_unit=unit)
                if FILMS[film]:
                    case = case.with_physics(**FILMS[film])
                line = f"{deck.stem:34s} {unit:4s} {film:14s}"
                for label, solver in solvers:
                    plain = args.no_accelerate and label == "new"
                    own = case.with_numerics(accelerate=False) if plain else case
                    if args.pilot and label == "new":
                        own = own.with_numerics(pilot_cycle=True)
                    if args.bdc_start and label == "new":
                        own = own.with_numerics(bdc_start=True)
                    if args.no_bdc_start and label == "new":
                        own = own.with_numerics(bdc_start=False)
                    if args.liner_window and label == "new":
                        own = own.with_numerics(liner_window=args.liner_window)
                    r = run(solver, own, args.repeats)
                    line += (
                        f" | {r['cycles_run']:7.0f} {r['cycles_computed']:5.2f} {r['run_time_s'] * 1e3:8.1f} "
                        f"{'yes' if r['converged'] else 'no':>4s} {r['energy_loss_J']:10.5f}"
                    )
                    row = [r["cycles_run"], r["cycles_computed"], r["run_time_s"] * 1e3]
                    if args.ref:
                        t = run(solver, own.with_numerics(cycle_tol=1e-6, max_cycles=60), 1)
                        de = r["energy_loss_J"] / t["energy_loss_J"] - 1
                        db = r["blowby_l_min"] / t["blowby_l_min"] - 1
                        line += f" {de:+8.1e} {db:+8.1e}"
                        row += [abs(de), 0.0 if np.isnan(db) else abs(db)]
                    sums.setdefault((label, unit, film), []).append(row)
                print(line, flush=True)
    print(
        "\nmeans per film model and reading (cycles run, cycles computed, ms per run"
        + (", largest |dE|, |dBb| against cycle_tol 1e-6)" if args.ref else ")")
    )
    for (label, unit, film), rows in sums.items():
        a = np.array(rows)
        means = a[:, :3].mean(axis=0)
        text = f"{label:5s} {unit:4s} {film:14s} {means[0]:6.2f} {means[1]:6.2f} {means[2]:8.1f}"
        if args.ref:
            text += f" {a[:, 3].max():8.1e} {a[:, 4].max():8.1e}"
        print(text)


if __name__ == "__main__":
    main()
