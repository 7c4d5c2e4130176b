"""Benchmark (not a test): what the ring pack's pilot cycle (``&numerics pilot_cycle``) costs
against one of the run's own cycles.

The shipped 'gas' decks without a distorted bore, each with the Swift-Stieber film and the
mass-conserving film flooded (vapour and 'trailing_gas' cavities), read in N: the pilot's work
is the deck run at 4 times its crank step over its warm-up and one cycle (``max_cycles`` 1,
which is what the pilot runs, but for its closing step); one of the run's cycles is the second
cycle of a run with the pilot (2 cycles against 1). Film solves (``total_film_solves``) and
kernel time (best of --repeats; a difference of two run times, unreliable on a loaded
machine), each as a share of one cycle, beside the pilot's crank steps in cycles. Run from the project folder:

    .venv/bin/python tests/bench/pilot_cost.py [--repeats 3]
"""

from __future__ import annotations

import argparse
from pathlib import Path

import ringlube

ROOT = Path(__file__).resolve().parents[2]
FILMS = {
    "swift_stieber": {},
    "flooded": {"cavitation": "jfo"},
    "flooded_tg": {"cavitation": "jfo", "cavity_pressure": "trailing_gas"},
}


def best(case: ringlube.Case, key: str, repeats: int) -> float:
    """The least of `repeats` runs' scalar `key`."""
    return min(ringlube.run(case).scalars[key] for _ in range(repeats))


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeats", type=int, default=3)
    args = ap.parse_args()
    decks = sorted((ROOT / "inputs").glob("*_gas.nml"))
    print(f"{'deck':32s} {'film':14s} {'steps':>6s} {'solves':>7s} {'time':>6s}")
    for deck in decks:
        for film, physics in FILMS.items():
            case = ringlube.Case.from_namelist(deck).with_physics(**physics)
            step = case.value("numerics", "dpsi_deg")
            pilot = case.with_numerics(dpsi_deg=4 * step, max_cycles=1)
            run = case.with_numerics(pilot_cycle=True)
            two, one = run.with_numerics(max_cycles=2), run.with_numerics(max_cycles=1)
            solves = best(pilot, "total_film_solves", 1) / (
                best(two, "total_film_solves", 1) - best(one, "total_film_solves", 1)
            )
            time = best(pilot, "run_time", args.repeats) / (
                best(two, "run_time", args.repeats) - best(one, "run_time", args.repeats)
            )
            # (the pilot's warm-up: the ring pack's 270 deg)
            steps = (270 / (4 * step) + 720 / (4 * step)) / (720 / step)
            print(f"{deck.stem:32s} {film:14s} {steps:6.2f} {solves:7.2f} {time:6.2f}", flush=True)


if __name__ == "__main__":
    main()
