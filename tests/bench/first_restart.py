"""Benchmark (not a test): the ring pack's restart after a first cycle that is not periodic only
where the ring pack lies beyond cycle_tol of its periodic state (``&numerics first_restart =
'away'``, the default) against a restart after every such cycle ('always', the rule before), on
designs of the three 'gas' decks starved.

For each deck, reading of the tension (N, and N/m with ``calibration_n_per_m.nml``), ring width
and tension: the cycles computed with each rule, whether the run converged, and its largest
distance from a run to ``cycle_tol`` 1e-6 (``max_cycles`` 60) in units of the deck's cycle_tol:
the largest of the relative energy and blowby, the mixed share (percentage points / 100) and h0
at every crank step relative to h0's largest value. A rule that accepted a run whose state had
not settled would show a distance above 1. Run from the project folder:

    .venv/bin/python tests/bench/first_restart.py
"""

from __future__ import annotations

import itertools
from pathlib import Path

import numpy as np

import ringlube

ROOT = Path(__file__).resolve().parents[2]
DECKS = ("crf450r_4000rpm_full_hot_gas", "crf450r_8000rpm_full_hot_gas", "crf450r_12000rpm_full_hot_gas")
TENSIONS = {"N": (6.0, 12.0), "N/m": (5.0, 15.0)}
WIDTHS = (0.8e-3, 1.2e-3)


def distance(r: ringlube.CycleResult, ref: ringlube.CycleResult) -> float:
    """The run's largest distance from the reference (relative; the mixed share in points / 100)."""
    return max(
        abs(r.energy_loss / ref.energy_loss - 1),
        abs(r.blowby / ref.blowby - 1),
        np.abs(r.h0 - ref.h0).max() / np.abs(ref.h0).max(),
        abs(r.mixed_share - ref.mixed_share) / 100,
    )


def main() -> None:
    head = f"{'deck':30s} {'unit':4s} {'width':>5s} {'tens':>5s}"
    print(head + " | away: comp conv dist/tol | always: comp conv dist/tol")
    worst = {"away": 0.0, "always": 0.0}
    for deck, unit in itertools.product(DECKS, TENSIONS):
        for width, tension in itertools.product(WIDTHS, TENSIONS[unit]):
            case = ringlube.Case.from_namelist(ROOT / "inputs" / f"{deck}.nml")
            case = case.with_ring(tension_unit=unit, width=width, tension=tension)
            case = case.with_physics(cavitation="jfo", inlet="starved")
            if unit == "N/m":
                case = case.with_("calibration", file="calibration_n_per_m.nml")
            tol = case.value("numerics", "cycle_tol")
            ref = ringlube.run(case.with_numerics(cycle_tol=1e-6, max_cycles=60))
            line = f"{deck:30s} {unit:4s} {width * 1e3:5.2f} {tension:5.1f}"
            for rule in ("away", "always"):
                r = ringlube.run(case.with_numerics(first_restart=rule))
                d = distance(r, ref) / tol
                if r.converged and ref.converged:
                    worst[rule] = max(worst[rule], d)
                line += f" | {r.cycles_computed:10.2f} {'yes' if r.converged else 'no':>4s} {d:8.3f}"
            print(line, flush=True)
    print(
        f"\nlargest distance of a converged run (its reference converged), in cycle_tol: "
        f"away {worst['away']:.3f}, always {worst['always']:.3f}"
    )


if __name__ == "__main__":
    main()
