"""Benchmark (not a test): what the progress line costs a run. The cold 4000 r/min deck
(Swift-Stieber, and starved) through ringlube-solve, its standard error a terminal (a pseudo
terminal: the kernel reads the clock at every crank step and rewrites the line after 2 s) and
with -q (one call per step that returns at once), alternately, --repeats times each; kernel
ms per computed cycle (run_time_s / cycles_computed), the median and the best. With --base, a
build without the progress line (e.g. of an earlier commit) the same way, with -q. Run from the
project folder:

    .venv/bin/python tests/bench/progress_cost.py [--base BASE/ringlube-solve] [--repeats 7]
"""

from __future__ import annotations

import argparse
import os
import pty
import subprocess
import tempfile
from pathlib import Path

import h5py
import numpy as np

import ringlube

ROOT = Path(__file__).resolve().parents[2]
INPUTS = ROOT / "inputs"


def once(solver: str, deck: Path, out: Path, terminal: bool) -> float:
    """One run; kernel ms per computed cycle."""
    if terminal:
        master, slave = pty.openpty()
        proc = subprocess.Popen([solver, str(deck), "-o", str(out)], stdout=subprocess.DEVNULL, stderr=slave)
        os.close(slave)
        while True:  # drain the terminal until the process closes it
            try:
                if not os.read(master, 65536):
                    break
            except OSError:
                break
        proc.wait()
        os.close(master)
    else:
        subprocess.run([solver, str(deck), "-o", str(out), "-q"], check=False)
    with h5py.File(out) as f:
        return 1e3 * float(f.attrs["run_time_s"]) / float(f.attrs["cycles_computed"])


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--solver", default=str(ROOT / "build" / "ringlube-solve"))
    ap.add_argument("--base")
    ap.add_argument("--repeats", type=int, default=7)
    args = ap.parse_args()
    cold = ringlube.Case.from_namelist(INPUTS / "crf450r_4000rpm_full_cold.nml")
    cases = {
        "swift_stieber 201 nodes, 0.5 deg": cold.with_numerics(nodes=201, dpsi_deg=0.5),
        "starved, default": cold.with_physics(cavitation="jfo", inlet="starved"),
    }
    variants = [("terminal (line on)", args.solver, True), ("-q (line off)", args.solver, False)]
    if args.base:
        variants.append(("base build, -q", args.base, False))
    for label, case in cases.items():
        fd, name = tempfile.mkstemp(suffix=".nml", prefix="_progress_cost", dir=INPUTS)
        os.close(fd)
        deck = Path(name)
        out = deck.with_suffix(".h5")
        case.to_namelist(deck)
        try:
            times: dict[str, list[float]] = {v[0]: [] for v in variants}
            for _ in range(args.repeats):
                for vlabel, solver, terminal in variants:
                    times[vlabel].append(once(solver, deck, out, terminal))
        finally:
            deck.unlink()
            out.unlink(missing_ok=True)
        print(label)
        for vlabel, t in times.items():
            print(f"  {vlabel:22s} ms per computed cycle: median {np.median(t):8.2f}, best {min(t):8.2f}")


if __name__ == "__main__":
    main()
