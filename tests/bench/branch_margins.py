"""Branch risk on the shipped decks: the margins' sweeps and their cost (docs/model.md, "Branch
risk").

Prints three tables:

1. ``pressure_scale`` swept across the intake stroke's lift-off threshold on the cold deck read
   in N/m (the reading whose intake stroke sits at the threshold; its calibrated
   zeta_kappa_sigma) with the starved film: ``lift_margin``, the lifted share and the energy of
   each run;
2. the crank step swept across the switch of the cold deck's 'trailing_gas' face (read in N/m,
   with ``inputs/calibration_n_per_m.nml``) between sealed and blown after firing TDC:
   ``seal_margin`` (and its angle) and the energy;
3. each run's ``lift_margin`` read in N (the shipped decks) and in N/m, and the cost: the film
   solves for ``lift_margin`` (one per step of the intake stroke not held at the ceiling, on a
   copy of the film) per reported cycle against the run's film solves per
   cycle, and with ``--base-solver`` (a ``ringlube-solve`` built before the margins) the CPU
   time of a run of both builds (``ringlube-solve`` with its HDF5 file) and the kernel's own
   (wall) time, each the best of ``--repeats`` interleaved runs.

Usage::

    .venv/bin/python tests/bench/branch_margins.py [--base-solver PATH] [--repeats 5]

A benchmark script (not run by the tests): it needs the kernel built (``make``).
"""

from __future__ import annotations

import argparse
import re
import resource
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import h5py

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tests" / "bench"))
from identical import write_deck  # noqa: E402  (the shipped decks with &physics added)

SOLVER = ROOT / "build" / "ringlube-solve"
COLD = "crf450r_4000rpm_full_cold.nml"
STARVED = "cavitation = 'jfo', inlet = 'starved'"
TRAILING = "cavitation = 'jfo', cavity_pressure = 'trailing_gas'"
#: (label, deck, &physics) of the cost table
COST = [
    ("cold, Swift-Stieber", COLD, ""),
    ("cold, flooded 'vapour'", COLD, "cavitation = 'jfo'"),
    ("cold, starved", COLD, STARVED),
    ("cold, 'trailing_gas'", COLD, TRAILING),
    ("hot, starved", "crf450r_4000rpm_full_hot.nml", STARVED),
    ("hot, ring pack, starved", "crf450r_4000rpm_full_hot_gas.nml", STARVED),
    ("12,000 r/min, ring pack", "crf450r_12000rpm_full_hot_gas.nml", ""),
]


def run(solver: Path, deck: Path, out: Path) -> dict:
    """The run's root attributes, and its CPU time (user + system, s) as ``cpu``."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    subprocess.run([str(solver), "-q", str(deck), "-o", str(out)], check=False, capture_output=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    with h5py.File(out) as f:
        a = dict(f.attrs)
    a["cpu"] = after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime
    return a


def variant(
    folder: Path, deck: str, physics: str, numerics: str = "", operating: str = "", per_length: bool = False
) -> Path:
    path = write_deck(folder, deck, physics)
    text = path.read_text()
    if numerics:
        text = text.replace("&numerics ", f"&numerics {numerics}, ", 1)
    if operating:
        # the calibrated pressure_scale given here instead of by the calibration file
        text = text.replace("&calibration file = 'calibration.nml' /", "")
        text = text.replace("&surface ", "&surface zeta_kappa_sigma = 0.1, ", 1)
        text = text.replace("&operating ", f"&operating {operating}, ", 1)
    if per_length:
        # the tension read in N/m, with that reading's calibration (zeta_kappa_sigma 0.1 above)
        shutil.copy(ROOT / "inputs" / "calibration_n_per_m.nml", folder / "calibration_n_per_m.nml")
        text, n = re.subn(r"tension_unit\s*=\s*'N'", "tension_unit = 'N/m'", text)
        assert n == 1, deck
        text = text.replace("file = 'calibration.nml'", "file = 'calibration_n_per_m.nml'")
    name = f"{path.stem}_{abs(hash((numerics, operating, per_length)))}.nml"
    (folder / name).write_text(text)
    return folder / name


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--base-solver", type=Path, help="a ringlube-solve without the margins")
    ap.add_argument("--repeats", type=int, default=5)
    args = ap.parse_args(argv)
    with tempfile.TemporaryDirectory(prefix="ringlube_margins_") as tmp:
        tmp = Path(tmp)
        out = tmp / "out.h5"
        print("1. cold deck read in N/m, starved film: pressure_scale across the intake threshold\n")
        print("| pressure_scale | lift_margin | lifted share % | energy J |")
        print("|---:|---:|---:|---:|")
        for s in (0.92, 0.925, 0.929004, 0.931, 0.932, 0.9325, 0.9328, 0.933, 0.934, 0.937, 0.94):
            deck = variant(tmp, COLD, STARVED, operating=f"pressure_scale = {s}", per_length=True)
            a = run(SOLVER, deck, out)
            share, e = a["liner_lift_share_pct"], a["energy_loss_J"]
            print(f"| {s:g} | {a['lift_margin']:+.5f} | {share:.2f} | {e:.4f} |")
        print("\n2. cold deck read in N/m, flooded 'trailing_gas': the crank step across the switch\n")
        print("| dpsi_deg | seal_margin | at deg | energy J |")
        print("|---:|---:|---:|---:|")
        for d in (2.0, 1.8, 1.6, 1.5, 1.25, 1.2, 1.0, 0.8, 0.5, 0.25):
            a = run(SOLVER, variant(tmp, COLD, TRAILING, numerics=f"dpsi_deg = {d}", per_length=True), out)
            angle, e = a["seal_margin_angle_deg"], a["energy_loss_J"]
            print(f"| {d:g} | {a['seal_margin']:+.4f} | {angle:.2f} | {e:.4f} |")
        print("\n3. cost at 'default'\n")
        head = "| run | lift_margin read in N | read in N/m | margin solves / film solves per cycle |"
        if args.base_solver:
            head += " CPU ms, before | after | after / before | kernel ms, before | after | after / before |"
        print(head)
        print("|" + "---|" * (head.count("|") - 1))
        for label, deck, physics in COST:
            path = variant(tmp, deck, physics)
            m = run(SOLVER, variant(tmp, deck, physics, per_length=True), out)["lift_margin"]
            a = run(SOLVER, path, out)
            per_cycle = a["film_solves"] / a["cycles_computed"]
            share = a["margin_film_solves"] / per_cycle
            line = f"| {label} | {a['lift_margin']:+.4f} | {m:+.4f} | {share:.1%} |"
            if args.base_solver:
                # interleaved, the best of each (the machine's load changes between runs)
                t = {"base": float("inf"), "new": float("inf")}
                k = dict(t)
                for _ in range(args.repeats):
                    for tag, solver in (("base", args.base_solver), ("new", SOLVER)):
                        a = run(solver, path, out)
                        t[tag] = min(t[tag], a["cpu"])
                        k[tag] = min(k[tag], a["run_time_s"])
                line += f" {1e3 * t['base']:.1f} | {1e3 * t['new']:.1f} | {t['new'] / t['base']:.3f} |"
                line += f" {1e3 * k['base']:.1f} | {1e3 * k['new']:.1f} | {k['new'] / k['base']:.3f} |"
            print(line, flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
