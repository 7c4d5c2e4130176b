"""Benchmark (not a test): how many cycles the ring pack's runs need over the ring-pack study's
box (inputs/study_ring_pack.nml: 9 widths x 3 tensions) on the hot 'gas' decks at 4000, 8000
and 12,000 r/min: mean and largest `cycles_run`, designs not periodic, kernel ms per run (a
fresh process each, so it includes the one-time set-up of about 2.7 ms) and, with --ref, the
largest energy difference to the same design run to `cycle_tol` 1e-6. Run from the project
folder (about a minute; --ref about three):

    .venv/bin/python tests/bench/ring_pack_box.py [--ref] [build/ringlube-solve]
"""

import subprocess
import sys
import tempfile
from pathlib import Path

import f90nml
import h5py
import numpy as np

ROOT = Path(__file__).resolve().parents[2]
args = [a for a in sys.argv[1:] if a != "--ref"]
SOLVER = args[0] if args else str(ROOT / "build" / "ringlube-solve")
REF = "--ref" in sys.argv


def run(nml: f90nml.Namelist, folder: Path) -> dict:
    """One run of the patched deck (written beside the shipped ones: its relative paths hold)."""
    deck = ROOT / "inputs" / "_ring_pack_box.nml"
    nml.write(deck, force=True)
    try:
        subprocess.run([SOLVER, str(deck), "-o", str(folder / "o.h5"), "-q"], check=False)
    finally:
        deck.unlink()
    with h5py.File(folder / "o.h5") as f:
        return {k: f.attrs[k] for k in ("cycles_run", "converged", "run_time_s", "energy_loss_J")}


with tempfile.TemporaryDirectory() as tmp:
    for rpm in (4000, 8000, 12000):
        nml = f90nml.read(ROOT / "inputs" / f"crf450r_{rpm}rpm_full_hot_gas.nml")
        cycles, bad, ms, err = [], 0, [], []
        for width in np.linspace(0.54e-3, 1.34e-3, 9):
            for tension in (8.0, 17.0, 26.0):
                nml["ring"]["width"], nml["ring"]["tension"] = float(width), tension
                nml["numerics"].pop("cycle_tol", None)
                nml["numerics"].pop("max_cycles", None)
                r = run(nml, Path(tmp))
                cycles.append(r["cycles_run"])
                bad += int(r["converged"]) == 0
                ms.append(r["run_time_s"] * 1e3)
                if REF:
                    nml["numerics"]["cycle_tol"], nml["numerics"]["max_cycles"] = 1e-6, 30
                    tight = run(nml, Path(tmp))
                    err.append(abs(r["energy_loss_J"] / tight["energy_loss_J"] - 1))
        line = (
            f"{rpm} r/min: cycles_run mean {np.mean(cycles):.2f}, largest {max(cycles)}; not periodic "
            f"{bad} of 27; {np.mean(ms):.2f} ms per run"
        )
        print(line + (f"; energy within {max(err):.1e} of cycle_tol 1e-6" if REF else ""), flush=True)
