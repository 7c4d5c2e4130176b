"""Benchmark (not a test): what a distorted bore costs and how its sector count trades accuracy.

Three tables (markdown), each on the CRF450R decks with the tension read in N and a bore of
orders 2 and 4 (12 and 8 um, beyond the source ring's order-4 limit of 5.5 um):

1. Cost per sector-cycle against a round cycle of the same film model (Swift-Stieber, flooded
   and starved JFO; the 4000 r/min cold deck, and the hot deck with the ring pack), 24
   sectors, one thread: `build/bench_kernel` CPU ms per run (best of 3), divided by the cycles
   computed and the sectors. Also the film solves per sector-step against the round bore's
   per step.
2. Speed-up of two threads (`&numerics threads = 2`) against one: wall time of
   `build/ringlube-solve` (best of 3). Meaningful on a quiet machine only (threads that wait
   for a busy core spin): the load average is printed.
3. Sector count: energy, face leakage, light gaps and blowby at M = 8, 12, 24, 48 against
   M = 96 (starved film, ring pack, hot deck), with the cost.

Run from the project folder (about 10 minutes on a quiet 2-core machine):

    .venv/bin/python tests/bench/bore_cost.py
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import tempfile
import time
from pathlib import Path

import h5py

ROOT = Path(__file__).resolve().parents[2]
BENCH = ROOT / "build" / "bench_kernel"
SOLVE = ROOT / "build" / "ringlube-solve"
BORE = "&bore order = 2, 4, amplitude = 12e-6, 8e-6, phase = 0.0, 0.4, sectors = {m} /"
READ_IN_N = "&ring tension_unit = 'N' /"
MODELS = (
    ("Swift-Stieber", "", 10),
    ("flooded JFO", "cavitation='jfo',", 5),
    ("starved JFO", "cavitation='jfo', inlet='starved',", 2),
)
DECKS = (
    ("4000 cold", "crf450r_4000rpm_full_cold.nml"),
    ("4000 hot, ring pack", "crf450r_4000rpm_full_hot_gas.nml"),
)


def bench(deck: Path, overrides: str, runs: int) -> dict[str, float]:
    """bench_kernel's key=value line (best of 3 of its ms per run)."""
    best: dict[str, float] = {}
    for _ in range(3):
        out = subprocess.run(
            [str(BENCH), str(deck), overrides, str(runs)], capture_output=True, text=True, check=True
        )
        vals = {k: float(v) for k, v in re.findall(r"(\w+)=\s*([-+0-9.eE]+)", out.stdout)}
        if not best or vals["ms_per_run"] < best["ms_per_run"]:
            best = vals
    return best


def cost_table() -> None:
    print(
        "| deck | film | round ms/cycle | distorted ms per sector-cycle | ratio |"
        " film solves per sector-step / round's per step |"
    )
    print("|---|---|---|---|---|---|")
    for label, name in DECKS:
        deck = ROOT / "inputs" / name
        for model, phys, runs in MODELS:
            r = bench(deck, f"{READ_IN_N} &physics {phys} /", runs)
            d = bench(
                deck, f"{READ_IN_N} &physics {phys} bore='distorted' / {BORE.format(m=24)}", max(1, runs // 5)
            )
            per_r = r["ms_per_run"] / r["cycles_computed"]
            per_d = d["ms_per_run"] / d["cycles_computed"] / 24
            fs_r = r["film_solves"] / (r["steps"] * r["cycles_computed"])
            fs_d = d["film_solves"] / (d["steps"] * d["cycles_computed"]) / 24
            row = f"| {label} | {model} | {per_r:.2f} | {per_d:.2f} | {per_d / per_r:.2f}"
            print(f"{row} | {fs_d:.2f} / {fs_r:.2f} |", flush=True)


def solve(deck: Path, extra: str, folder: Path) -> tuple[float, dict]:
    """Wall time of ringlube-solve on `deck` with `extra` appended (best of 3) and its root attributes."""
    # the deck's own reading, if it writes one, gives way to READ_IN_N (a variable may be
    # given once only)
    text = re.sub(r"tension_unit\s*=\s*'[^']*'\s*,?", "", deck.read_text()) + "\n" + extra + "\n"
    path = folder / "case.nml"
    path.write_text(text)
    best = float("inf")
    for _ in range(3):
        t0 = time.perf_counter()
        subprocess.run([str(SOLVE), "-q", str(path), "-o", str(folder / "r.h5")], check=True)
        best = min(best, time.perf_counter() - t0)
    with h5py.File(folder / "r.h5") as f:
        return best, dict(f.attrs)


def copy_inputs(folder: Path) -> None:
    shutil.copytree(ROOT / "inputs" / "pressure", folder / "pressure")
    shutil.copy(ROOT / "inputs" / "calibration.nml", folder / "calibration.nml")


def thread_table(folder: Path) -> None:
    print(f"\nload average before: {os.getloadavg()[0]:.2f}")
    print("| deck | film | 1 thread s | 2 threads s | speed-up |")
    print("|---|---|---|---|---|")
    for label, name in DECKS:
        deck = folder / name
        shutil.copy(ROOT / "inputs" / name, deck)
        for model, phys, _ in MODELS[::2]:
            base = f"{READ_IN_N}\n{BORE.format(m=24)}"
            phys_d = f"&physics {phys} bore='distorted' /"
            t1, a1 = solve(deck, f"{base}\n{phys_d}\n&numerics threads = 1 /", folder)
            t2, a2 = solve(deck, f"{base}\n{phys_d}\n&numerics threads = 2 /", folder)
            same = a1["energy_loss_J"] == a2["energy_loss_J"]
            note = "" if same else " (energies differ!)"
            print(f"| {label} | {model} | {t1:.2f} | {t2:.2f} | {t1 / t2:.2f}{note} |")
    print(f"load average after: {os.getloadavg()[0]:.2f}")


def sector_table(folder: Path) -> None:
    name = "crf450r_4000rpm_full_hot_gas.nml"
    deck = folder / name
    shutil.copy(ROOT / "inputs" / name, deck)
    phys = "&physics cavitation='jfo', inlet='starved', bore='distorted' /"
    rows = {}
    for m in (8, 12, 24, 48, 96):
        t, a = solve(deck, f"{READ_IN_N}\n{phys}\n{BORE.format(m=m)}", folder)
        rows[m] = (t, a)
    ref = rows[96][1]
    keys = ("energy_loss_J", "face_leakage_mg_per_cycle", "light_gap_share_pct", "blowby_l_min")
    print(
        "\n| sectors | energy J | face leakage mg | light gaps % | blowby L/min |"
        " energy vs 96 | leakage vs 96 | s |"
    )
    print("|---|---|---|---|---|---|---|---|")
    for m, (t, a) in rows.items():
        e, f, lg, bb = (float(a[k]) for k in keys)
        de = e / float(ref[keys[0]]) - 1
        df = f / float(ref[keys[1]]) - 1 if float(ref[keys[1]]) else float("nan")
        print(
            f"| {m} | {e:.4f} | {f:.3f} | {lg:.1f} | {bb:.3f} | {de:+.2%} | {df:+.2%} | {t:.1f} |", flush=True
        )


if __name__ == "__main__":
    cost_table()
    with tempfile.TemporaryDirectory(prefix="ringlube_bore_") as tmp:
        copy_inputs(Path(tmp))
        thread_table(Path(tmp))
        sector_table(Path(tmp))
