"""Benchmark (not a test): import-to-first-result time and per-run cost through Python
against the standalone program, on the shipped cold deck at default numerics; and the
Python overhead per run of a batch call (ringlube.run_designs: the case parsed once,
designs as an array, scalars returned in an array, no files).

    python3 tests/bench/python_overhead.py
"""

from __future__ import annotations

import statistics
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
DECK = ROOT / "inputs" / "crf450r_4000rpm_full_cold.nml"
SOLVER = ROOT / "build" / "ringlube-solve"
REPEAT = 5

first = subprocess.run(
    [
        sys.executable,
        "-c",
        "import time; t=time.perf_counter(); import ringlube; "
        f"r=ringlube.run({str(DECK)!r}); print(time.perf_counter()-t, r.run_time)",
    ],
    check=True,
    capture_output=True,
    text=True,
).stdout.split()
print(
    f"import + first result (fresh interpreter): {float(first[0]) * 1e3:.0f} ms "
    f"(kernel {float(first[1]) * 1e3:.0f} ms)"
)

import ringlube  # noqa: E402

case = ringlube.Case.from_namelist(DECK)
py, kern = [], []
for _ in range(REPEAT):
    t = time.perf_counter()
    r = ringlube.run(case)
    py.append(time.perf_counter() - t)
    kern.append(r.run_time)
cli = []
for _ in range(REPEAT):
    t = time.perf_counter()
    subprocess.run([str(SOLVER), "-q", str(DECK), "-o", "/tmp/ringlube_bench.h5"], check=True)
    cli.append(time.perf_counter() - t)
m = statistics.median
print(
    f"per run, median of {REPEAT}: ringlube.run {m(py) * 1e3:.1f} ms "
    f"(kernel {m(kern) * 1e3:.1f} ms, Python overhead {(m(py) - m(kern)) * 1e3:.1f} ms); "
    f"ringlube-solve process {m(cli) * 1e3:.1f} ms"
)
print(
    f"cycles computed per run (warm-up included): {r.cycles_computed:.2f}; kernel time per "
    f"cycle {m(kern) / r.cycles_computed * 1e3:.1f} ms"
)

import numpy as np  # noqa: E402

BATCH = 200
x = np.column_stack([np.linspace(0.8e-3, 1.2e-3, BATCH), np.linspace(8.0, 20.0, BATCH)])
wall, kern_b = [], []
for _ in range(REPEAT):
    t = time.perf_counter()
    v, ok, err = ringlube.run_designs(case, ["width", "tension"], x, ["run_time"])
    wall.append(time.perf_counter() - t)
    kern_b.append(float(np.sum(v[:, 0])))
over = [(w - k) / BATCH for w, k in zip(wall, kern_b)]
print(
    f"batch of {BATCH} designs through ringlube.run_designs, median of {REPEAT}: "
    f"{m(wall) / BATCH * 1e3:.2f} ms per run (kernel {m(kern_b) / BATCH * 1e3:.2f} ms, "
    f"Python and batch overhead {m(over) * 1e3:.3f} ms per run)"
)
