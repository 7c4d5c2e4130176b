"""Benchmark (not a test): what the ring pack's pilot cycle (``&numerics pilot_cycle``) costs
against one of the run's own cycles.

The shipped 'gas' decks without a distorted bore, each with the Swift-Stieber film and the
mass-conserving film flooded (vapour and 'trailing_gas' cavities), read in N: one of the run's
cycles is the second cycle of a run with the pilot (2 cycles against 1); the pilot's work is
the run with the pilot stopped after its first cycle less that cycle and the film's own
warm-up, each taken as the second cycle's share (1 + warm-up / 720 of it: approximate, the
first cycle's steps may take more trials than the second's). The pilot runs at 8 times the
crank step (the kernel's pilot_stride; a crank step the inputs do not allow, 16 deg, so it
cannot be run alone). Film solves (``total_film_solves``) and
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
            run = case.with_numerics(pilot_cycle=True)
            two, one = run.with_numerics(max_cycles=2), run.with_numerics(max_cycles=1)
            # (the film's own warm-up: 270 deg flooded with a vapour cavity, else 90)
            warm = 270 if physics.get("cavitation") == "jfo" and "cavity_pressure" not in physics else 90
            share = 1 + warm / 720
            cycle = best(two, "total_film_solves", 1) - best(one, "total_film_solves", 1)
            solves = best(one, "total_film_solves", 1) / cycle - share
            cycle_t = best(two, "run_time", args.repeats) - best(one, "run_time", args.repeats)
            time = best(one, "run_time", args.repeats) / cycle_t - share
            # (the pilot's warm-up: the ring pack's 270 deg, whole steps)
            steps = (round(270 / (8 * step)) + 720 / (8 * step)) / (720 / step)
            print(f"{deck.stem:32s} {film:14s} {steps:6.2f} {solves:7.2f} {time:6.2f}", flush=True)


if __name__ == "__main__":
    main()
