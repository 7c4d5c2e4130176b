"""Speed/accuracy front of the numerics (benchmark, not a test; part of `make bench`).

For the cold and hot 4000 r/min decks: the converged reference (BDF2, 801 nodes,
0.125 deg, pressure_tol 1e-8, load_tol 1e-6, cycle_tol 1e-6), then a ladder of numerics
(time scheme x nodes x crank step x load_tol), each timed by ``build/bench_kernel``
(CPU time of the kernel, best of N runs) with its relative energy error against the
reference, film solves per crank step, and whether it lies on the Pareto front of
(ms per cycle, worst error of the two decks). Ends with the three presets as shipped.

    python3 tests/bench/front.py [--repeats 5] [--quick]
"""

from __future__ import annotations

import argparse
import itertools
import subprocess
from pathlib import Path

import ringlube.convergence

ROOT = Path(__file__).resolve().parents[2]
BENCH = ROOT / "build" / "bench_kernel"
DECKS = {d: ROOT / "inputs" / f"crf450r_4000rpm_full_{d}.nml" for d in ("cold", "hot")}
# the reference numerics of `ringlube convergence` (one place), tight periodicity, BDF2
REFERENCE = " ".join(
    f"{k}={v!r}" if isinstance(v, str) else f"{k}={v}"
    for k, v in {**ringlube.convergence.REFERENCE, "cycle_tol": 1e-6, "time_scheme": "bdf2"}.items()
)


def bench(deck: Path, numerics: str, repeats: int, exe: Path = BENCH) -> dict:
    """The key=value line of `bench_kernel` (exe) for one deck and numerics, as numbers."""
    out = subprocess.run(
        [str(exe), str(deck), f"&numerics {numerics} /", str(repeats)],
        check=True,
        capture_output=True,
        text=True,
        cwd=ROOT,
    ).stdout
    first = out.splitlines()[0].replace("= ", "=")
    return {k: float(v) for k, v in (kv.split("=") for kv in first.split())}


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--quick", action="store_true", help="a smaller ladder")
    args = ap.parse_args()
    ref = {d: bench(p, REFERENCE, 1)["energy"] for d, p in DECKS.items()}
    print("reference energy [J] (" + REFERENCE + "): " + ", ".join(f"{d} {e:.7f}" for d, e in ref.items()))
    schemes = ("bdf2", "euler")
    nodes = (31, 51) if args.quick else (31, 41, 51, 71)
    steps = (1.0, 2.0, 3.0) if args.quick else (0.5, 1.0, 1.5, 2.0, 2.5, 3.0, 4.0)
    tols = ("1e-3",) if args.quick else ("1e-3", "3e-3")
    rows = []
    for scheme, n, dpsi, tol in itertools.product(schemes, nodes, steps, tols):
        num = f"time_scheme='{scheme}' nodes={n} dpsi_deg={dpsi} load_tol={tol}"
        r = {d: bench(p, num, args.repeats) for d, p in DECKS.items()}
        err = {d: abs(r[d]["energy"] - ref[d]) / ref[d] for d in DECKS}
        ms = max(r[d]["ms_per_cycle"] for d in DECKS)
        solves = r["cold"]["film_solves"] / (r["cold"]["cycles_computed"] * 720 / dpsi)
        rows.append((scheme, n, dpsi, tol, ms, err["cold"], err["hot"], solves))
    print(
        f"\n{'scheme':6s} {'nodes':>5s} {'dpsi':>5s} {'load_tol':>8s} {'ms/cycle':>9s} "
        f"{'err cold':>9s} {'err hot':>9s} {'solves/step':>11s} front"
    )
    for row in sorted(rows, key=lambda r: r[4]):
        worst = max(row[5], row[6])
        front = not any(o[4] < row[4] and max(o[5], o[6]) < worst for o in rows)
        print(
            f"{row[0]:6s} {row[1]:5d} {row[2]:5.2f} {row[3]:>8s} {row[4]:9.2f} {row[5]:9.1e} "
            f"{row[6]:9.1e} {row[7]:11.2f} {'*' if front else ''}"
        )
    print("\npresets as shipped (ms per computed cycle, worst of the two decks; error vs reference)")
    for preset in ("fast", "default", "accurate"):
        r = {
            d: bench(p, f"preset='{preset}'", 1 if preset == "accurate" else args.repeats)
            for d, p in DECKS.items()
        }
        print(
            f"{preset:9s} ms/run {max(r[d]['ms_per_run'] for d in DECKS):8.2f}  ms/cycle "
            f"{max(r[d]['ms_per_cycle'] for d in DECKS):8.2f}  error cold "
            f"{abs(r['cold']['energy'] - ref['cold']) / ref['cold']:.1e}, hot "
            f"{abs(r['hot']['energy'] - ref['hot']) / ref['hot']:.1e}"
        )


if __name__ == "__main__":
    main()
