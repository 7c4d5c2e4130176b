"""Benchmark (make bench; not a test): cost of the film models at the 'default' preset on
the shipped cold and hot decks: Swift-Stieber (the source study), the mass-conserving JFO
film flooded and starved, each with vapour and trailing-gas cavities. Kernel time per run
(best of N), cycles computed, ms per computed cycle and the ratio to Swift-Stieber.

    python3 tests/bench/film_models.py [--repeats N]
"""

from __future__ import annotations

import argparse
import os
import platform
from pathlib import Path

import ringlube

ROOT = Path(__file__).resolve().parents[2]
MODELS = {
    "swift_stieber": {},
    "jfo flooded": {"cavitation": "jfo"},
    "jfo flooded, trailing_gas": {"cavitation": "jfo", "cavity_pressure": "trailing_gas"},
    "jfo starved": {"cavitation": "jfo", "inlet": "starved"},
    "jfo starved, trailing_gas": {"cavitation": "jfo", "inlet": "starved", "cavity_pressure": "trailing_gas"},
}


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeats", type=int, default=5)
    args = ap.parse_args()
    print(
        f"machine: {platform.processor() or platform.machine()}, {os.cpu_count()} cores; "
        f"kernel time best of {args.repeats}"
    )
    print(
        f"{'deck':28s} {'film model':28s} {'ms/run':>8s} {'cycles':>7s} {'ms/cycle':>9s} "
        f"{'x SS':>6s} {'energy J':>9s} {'mixed %':>8s} {'conv':>5s}"
    )
    for stem in ("crf450r_4000rpm_full_cold", "crf450r_4000rpm_full_hot"):
        base = ringlube.Case.from_namelist(ROOT / "inputs" / f"{stem}.nml")
        ref = None
        for label, physics in MODELS.items():
            case = base.with_physics(**physics) if physics else base
            runs = [ringlube.run(case) for _ in range(args.repeats)]
            r = min(runs, key=lambda x: x.run_time)
            per_cycle = r.run_time * 1e3 / r.cycles_computed
            ref = ref or r.run_time
            print(
                f"{stem:28s} {label:28s} {r.run_time * 1e3:8.1f} {r.cycles_computed:7.2f} "
                f"{per_cycle:9.2f} {r.run_time / ref:6.1f} {r.energy_loss:9.4f} "
                f"{r.mixed_share:8.2f} {'yes' if r.converged else 'no':>5s}",
                flush=True,
            )


if __name__ == "__main__":
    main()
