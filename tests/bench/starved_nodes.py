"""Benchmark (not a test): the starved film's cost against nodes
(docs/performance.md "The starved film's cost against nodes"). The cold 4000 r/min deck at 2 deg
with &numerics nodes = N: starved JFO without and with the ring pack's gas, and Swift-Stieber
for scale. Kernel CPU time per run (`build/bench_kernel`, best of REPEATS runs in one process;
one run at 2001 nodes and above), computed cycles, solver iterations per film solve (JFO
Newton iterations, Swift-Stieber Reynolds solves), whether the run converged, and the energy.
Run from the project folder:

    .venv/bin/python tests/bench/starved_nodes.py [--nodes 51,201,1001,2001,5001] [--repeats 3]
"""

import argparse
import re
import subprocess
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
BENCH = str(ROOT / "build" / "bench_kernel")
DECK = ROOT / "inputs" / "crf450r_4000rpm_full_cold.nml"
MODELS = (
    ("starved", "cavitation='jfo', inlet='starved'"),
    ("starved + ring pack gas", "cavitation='jfo', inlet='starved', ring_pack='gas'"),
    ("Swift-Stieber", ""),
)


def run(physics: str, nodes: int, repeats: int) -> dict:
    over = f"&physics {physics} / &numerics nodes = {nodes}, dpsi_deg = 2 /"
    out = subprocess.run([BENCH, str(DECK), over, str(repeats)], capture_output=True, text=True, check=True)
    v = dict(re.findall(r"(\w+)=\s*([-+0-9.eE]+)", out.stdout))
    return {k: float(x) for k, x in v.items()}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--nodes", default="51,201,1001,2001,5001")
    ap.add_argument("--repeats", type=int, default=3)
    a = ap.parse_args()
    nodes = [int(n) for n in a.nodes.split(",")]
    print("| nodes | model | s per run | cycles | its/solve | converged | energy J |")
    print("|---:|---|---:|---:|---:|---:|---:|")
    for n in nodes:
        for label, phys in MODELS:
            r = run(phys, n, a.repeats if n < 2000 else 1)
            its = r["reynolds_solves"] / r["film_solves"]
            print(
                f"| {n} | {label} | {r['ms_per_run'] / 1e3:.3f} | {r['cycles_computed']:.2f} | "
                f"{its:.1f} | {int(r['converged'])} | {r['energy']:.6f} |",
                flush=True,
            )


if __name__ == "__main__":
    main()
