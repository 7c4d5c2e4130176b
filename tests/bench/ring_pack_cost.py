"""Benchmark (not a test): the ring pack's cost, `&physics ring_pack` 'gas' against 'none', on
every shipped engine deck with Swift-Stieber, flooded and starved JFO, at the decks' numerics
('default' preset). Measured as a study sees it: the steady state of many runs in one process
(`build/bench_kernel DECK OVERRIDES RUNS`, CPU ms per run, best of 3). A fresh process's single
run also pays the kernel's one-time set-up (about 0.6 ms: tables built on first use), which
dilutes the ratio; it is not measured here. Prints a markdown table (docs/performance.md, "The
ring pack's cost"; its run time: "Run times"). Run from the project folder:

    .venv/bin/python tests/bench/ring_pack_cost.py [build/bench_kernel]
"""

import re
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
BENCH = sys.argv[1] if len(sys.argv) > 1 else str(ROOT / "build" / "bench_kernel")
DECKS = (
    "4000rpm_full_cold",
    "4000rpm_full_hot",
    "3000rpm_half_cold",
    "3000rpm_half_hot",
    "8000rpm_full_hot_gas",
    "12000rpm_full_hot_gas",
)
MODELS = (
    ("Swift-Stieber", "", 20),
    ("flooded JFO", "cavitation='jfo',", 20),
    ("starved JFO", "cavitation='jfo', inlet='starved',", 4),
)


def steady(deck: Path, physics: str, runs: int) -> tuple[float, float]:
    """Best of 3 of bench_kernel's ms per run, and the cycles computed per run."""
    best, cycles = float("inf"), 0.0
    for _ in range(3):
        out = subprocess.run(
            [BENCH, str(deck), f"&physics {physics} /", str(runs)], capture_output=True, text=True, check=True
        ).stdout
        best = min(best, float(re.search(r"ms_per_run=\s*([0-9.]+)", out).group(1)))
        cycles = float(re.search(r"cycles_computed=\s*([0-9.]+)", out).group(1))
    return best, cycles


if __name__ == "__main__":
    print("| deck | film | cycles computed none / gas | ms per run none / gas | ratio |")
    print("|---|---|---|---|---|")
    for deck in DECKS:
        path = ROOT / "inputs" / f"crf450r_{deck}.nml"
        for model, phys, runs in MODELS:
            (t0, c0), (t1, c1) = (steady(path, f"{phys} ring_pack='{rp}'", runs) for rp in ("none", "gas"))
            print(
                f"| {deck} | {model} | {c0:.2f} / {c1:.2f} | {t0:.2f} / {t1:.2f} | {t1 / t0:.2f} |",
                flush=True,
            )
