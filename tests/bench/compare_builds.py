"""Benchmark (not a test): how a kernel change that is not bit-identical moves the shipped
decks' answers. Runs every shipped engine deck with the ring pack ('gas') under each film model
(Swift-Stieber; JFO flooded, starved, 'trailing_gas') and preset ('fast', 'default', 'accurate';
not 'accurate' for the starved film) with two builds of `bench_kernel`, and prints the cycles
computed, the energy and `converged` of each, the runs whose cycles differ first, then the largest
relative energy differences. Used for the ring pack's faster start (docs/ring_pack.md, "Start":
66 runs, one cycle count changed, energies within 3e-4 but 'trailing_gas' at 'fast'). Build the
base with `git worktree add --detach /tmp/base COMMIT` and `cmake -S /tmp/base -B /tmp/base/build
-G Ninja -DCMAKE_BUILD_TYPE=Release && cmake --build /tmp/base/build --target bench_kernel`.
Run from the project folder (about two minutes):

    .venv/bin/python tests/bench/compare_builds.py BASE_BUILD_DIR [NEW_BUILD_DIR]
"""

import re
import subprocess
import sys
from pathlib import Path

from ring_pack_cost import DECKS  # the engine decks of the ring pack's benchmarks (this folder)

ROOT = Path(__file__).resolve().parents[2]
BASE = Path(sys.argv[1])
NEW = Path(sys.argv[2]) if len(sys.argv) > 2 else ROOT / "build"
MODELS = {
    "Swift-Stieber": "",
    "flooded JFO": "cavitation='jfo',",
    "starved JFO": "cavitation='jfo', inlet='starved',",
    "trailing_gas": "cavitation='jfo', cavity_pressure='trailing_gas',",
}


def run(build: Path, deck: str, physics: str, preset: str) -> tuple[float, float, int]:
    """Cycles computed, energy [J] and converged of one run."""
    overrides = f"&physics {physics} ring_pack='gas' / &numerics preset='{preset}' /"
    out = subprocess.run(
        [str(build / "bench_kernel"), str(ROOT / "inputs" / f"crf450r_{deck}.nml"), overrides, "1"],
        capture_output=True,
        text=True,
        check=True,
    ).stdout
    cycles = float(re.search(r"cycles_computed=\s*([0-9.]+)", out).group(1))
    energy = float(re.search(r"energy=\s*(\S+)", out).group(1))
    return cycles, energy, int(re.search(r"converged=(\d)", out).group(1))


rows = []
for deck in DECKS:
    for model, physics in MODELS.items():
        for preset in ("fast", "default", "accurate"):
            if preset == "accurate" and model == "starved JFO":
                continue
            a, b = run(BASE, deck, physics, preset), run(NEW, deck, physics, preset)
            rows.append((deck, model, preset, a, b, abs(b[1] / a[1] - 1)))
            print(
                f"{deck} | {model} | {preset} | cycles {a[0]:.3f} {b[0]:.3f} | energy {a[1]:.7e} "
                f"{b[1]:.7e} | converged {a[2]} {b[2]}",
                flush=True,
            )
changed = [r for r in rows if r[3][0] != r[4][0] or r[3][2] != r[4][2]]
print(f"\n{len(rows)} runs; cycles or converged differ in {len(changed)}:")
for r in changed:
    print(f"  {r[0]} {r[1]} {r[2]}: cycles {r[3][0]:.3f} -> {r[4][0]:.3f}, converged {r[3][2]} -> {r[4][2]}")
print("largest relative energy differences:")
for r in sorted(rows, key=lambda r: -r[5])[:5]:
    print(f"  {r[5]:.1e}  {r[0]} {r[1]} {r[2]}")
