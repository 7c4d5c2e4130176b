"""A design of experiments at scale (benchmark, not a test; part of `make bench`).

N runs (default 10,001: the source study's DOE size) of one condition (the shipped cold
deck, preset 'default' or --preset), a Sobol sample of the study's four design variables,
through :func:`ringlube.run_designs` (the case parsed once per batch, designs as arrays)
in batches spread over worker processes. Prints the wall time and runs/s on 1 worker
(a subset, --serial runs) and on --workers, the parallel efficiency, the kernel time's
share of the wall time, and each worker's resident memory (RSS) after every batch, so
that growth per run would show.

    python3 tests/bench/doe.py [--runs 10001] [--workers 2] [--batch 200] [--preset default]
"""

from __future__ import annotations

import argparse
import os
import time
import warnings
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np
from scipy.stats import qmc

import ringlube
from ringlube.study.variables import DESIGN_RANGES

ROOT = Path(__file__).resolve().parents[2]
COLD = ROOT / "inputs" / "crf450r_4000rpm_full_cold.nml"
VARS = DESIGN_RANGES  # the study's design box
OUTPUTS = ["energy_loss", "mixed_share", "converged", "run_time"]


def rss_mb() -> float:
    """Resident set size of this process now [MB] (from /proc/self/statm)."""
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE") / 2**20


def base_case(preset: str) -> ringlube.Case:
    case = ringlube.Case.from_namelist(COLD)
    return case.with_numerics(preset=preset)


def batch(args: tuple[str, np.ndarray]) -> tuple[np.ndarray, float, int]:
    preset, x = args
    values, _, errors = ringlube.run_designs(base_case(preset), list(VARS), x, OUTPUTS)
    return values, rss_mb(), os.getpid()


def sample(n: int, seed: int = 2) -> np.ndarray:
    lo = np.array([v[0] for v in VARS.values()])
    hi = np.array([v[1] for v in VARS.values()])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        return qmc.scale(qmc.Sobol(d=4, seed=seed).random(n), lo, hi)


def run(x: np.ndarray, workers: int, size: int, preset: str):
    """Wall time, results, RSS per worker and batch, and the CPU time the workers got."""
    chunks = [(preset, x[i : i + size]) for i in range(0, len(x), size)]
    t = time.perf_counter()
    c0 = os.times()
    with ProcessPoolExecutor(max_workers=workers) as pool:
        out = list(pool.map(batch, chunks))
    c1 = os.times()  # the workers have been joined: their CPU time is in children_*
    wall = time.perf_counter() - t
    cpu = (c1.children_user + c1.children_system) - (c0.children_user + c0.children_system)
    values = np.vstack([o[0] for o in out])
    rss: dict[int, list[float]] = {}
    for _, r, pid in out:
        rss.setdefault(pid, []).append(r)
    return wall, values, rss, cpu


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--runs", type=int, default=10_001)
    ap.add_argument("--serial", type=int, default=1000, help="runs of the 1-worker measurement")
    ap.add_argument("--workers", type=int, default=os.cpu_count() or 1)
    ap.add_argument("--batch", type=int, default=200, help="designs per run_designs call")
    ap.add_argument("--preset", default="default")
    args = ap.parse_args()
    print(
        f"machine: {os.cpu_count()} cores, load average {os.getloadavg()[0]:.1f} before the "
        f"runs; preset '{args.preset}'; batches of {args.batch}"
    )

    x = sample(args.runs)  # (n need not be a power of 2: the balance warning is silenced)
    wall1, v1, _, cpu1 = run(x[: args.serial], 1, args.batch, args.preset)
    rate1 = args.serial / wall1
    print(
        f"1 worker: {args.serial} runs in {wall1:.2f} s wall, {rate1:.1f} runs/s "
        f"(kernel {np.nansum(v1[:, 3]) / wall1:.0%} of the wall time; the worker had the CPU "
        f"{cpu1 / wall1:.0%} of the time)"
    )

    wall, v, rss, cpu = run(x, args.workers, args.batch, args.preset)
    rate = args.runs / wall
    print(
        f"{args.workers} workers: {args.runs} runs in {wall:.1f} s wall, {rate:.1f} runs/s; "
        f"parallel efficiency {rate / (args.workers * rate1):.0%}; kernel time "
        f"{np.nansum(v[:, 3]):.1f} s in all, {np.nanmean(v[:, 3]) * 1e3:.2f} ms per run"
    )
    print(
        f"CPU time of the workers {cpu:.1f} s: they had {cpu / wall:.2f} of the {args.workers} "
        f"cores; CPU time per run {cpu / args.runs * 1e3:.2f} ms (1 worker: "
        f"{cpu1 / args.serial * 1e3:.2f} ms)"
    )
    print(
        f"not converged: {int(np.sum(v[:, 2] < 0.5))}, failed: {int(np.sum(np.isnan(v[:, 0])))}; "
        f"energy {np.nanmin(v[:, 0]):.3f}-{np.nanmax(v[:, 0]):.3f} J, mixed share "
        f"{np.nanmin(v[:, 1]):.2f}-{np.nanmax(v[:, 1]):.2f} %"
    )
    print(f"load average after the runs: {os.getloadavg()[0]:.1f} (other sessions share the machine)")
    for pid, r in rss.items():
        print(
            f"worker {pid}: RSS after its {len(r)} batches: first {r[0]:.1f} MB, "
            f"largest {max(r):.1f} MB, last {r[-1]:.1f} MB "
            f"(growth {(r[-1] - r[0]) / max(1, (len(r) - 1) * args.batch) * 1e3:.2f} kB per run)"
        )


if __name__ == "__main__":
    main()
