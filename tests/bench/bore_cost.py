"""Benchmark (not a test): what a distorted bore costs and how its sector count trades accuracy.

Three tables (markdown), with the tension read in N and the shipped calibration:

1. Cost per sector-cycle against a round cycle of the same film model, on the shipped
   distorted decks (inputs/*distorted*.nml: orders 2, 3 and 4 of 6.5 um, 24 sectors, the ring
   pack) with each film model (Swift-Stieber, flooded and starved JFO; the round cycle: the
   same deck with `bore = 'round'`), one thread: `build/bench_kernel` CPU ms per run (best of
   3), divided by the cycles computed and the sectors. Also the film solves per sector-step of
   the load balance and of the lift-off margin against the round bore's per step.
2. Speed-up of two threads (`&numerics threads = 2`) against one on the same decks: wall and
   CPU time of `build/ringlube-solve` (best of 3), with OMP_WAIT_POLICY=PASSIVE unless it is
   set (as the Python package does; a GOMP_SPINCOUNT in the environment overrides the policy's
   spin count: libgomp spins that many times before a waiting thread sleeps), the CPU time of
   two threads over one's, and the load average beside every row. The speed-up is meaningful
   on a quiet machine only (load average below 1.5 before the run); the CPU times on any.
3. Sector count: energy, face leakage, light gaps and blowby at M = 8, 12, 24, 48 against
   M = 96 (starved film, ring pack, the hot 4000 r/min deck with orders 2 and 4 of 12 and
   8 um), with the cost.

`--moves BASE/build/ringlube-solve` instead: how far a kernel change that is not
bit-identical moves a distorted bore's answers (the shipped distorted decks as shipped and
identical.py's `distorted_starved` variant, this build against BASE): energy, blowby, face
leakage and light gaps, the largest relative change of a step's h0 (the smallest sector's)
and the largest load residual over the steps not held at a bound (in both runs), and the
cycles run.

Run from the project folder (4 minutes on the shared 2-core machine at a load average of 8-13;
the cost table alone 35 s at a load of 2-4):

    .venv/bin/python tests/bench/bore_cost.py
    .venv/bin/python tests/bench/bore_cost.py --cost-only --bench OTHER/build/bench_kernel
    .venv/bin/python tests/bench/bore_cost.py --threads-only   # at a quiet moment
    .venv/bin/python tests/bench/bore_cost.py --threads-only --solve OTHER/build/ringlube-solve
    .venv/bin/python tests/bench/bore_cost.py --moves BASE/build/ringlube-solve   # 30 s
    OMP_WAIT_POLICY=ACTIVE .venv/bin/python tests/bench/bore_cost.py --threads-only
    GOMP_SPINCOUNT=20000 .venv/bin/python tests/bench/bore_cost.py --threads-only
"""

from __future__ import annotations

import argparse
import os
import re
import resource
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
    ("Swift-Stieber", "cavitation='swift_stieber', inlet='flooded',", 10),
    ("flooded JFO", "cavitation='jfo', inlet='flooded',", 5),
    ("starved JFO", "cavitation='jfo', inlet='starved',", 2),
)
DECKS = (
    ("CRF450R 4000 hot", "crf450r_4000rpm_full_hot_distorted.nml"),
    ("CRF450R 12000 hot", "crf450r_12000rpm_full_hot_distorted.nml"),
    ("own 86 3000", "own86_3000rpm_full_distorted.nml"),
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
    print(f"load average at the start: {os.getloadavg()[0]:.2f}")
    print(
        "| deck | film | round ms/cycle | distorted ms per sector-cycle | ratio |"
        " film solves per sector-step: balance + margin / round's per step | load |"
    )
    print("|---|---|---|---|---|---|---|")
    for label, name in DECKS:
        deck = ROOT / "inputs" / name
        for model, phys, runs in MODELS:
            r = bench(deck, f"{READ_IN_N} &physics {phys} bore='round' /", runs)
            d = bench(deck, f"{READ_IN_N} &physics {phys} /", max(1, runs // 5))
            per_r = r["ms_per_run"] / r["cycles_computed"]
            per_d = d["ms_per_run"] / d["cycles_computed"] / 24
            fs_r = r["film_solves"] / (r["steps"] * r["cycles_computed"])
            fs_d = d["film_solves"] / (d["steps"] * d["cycles_computed"]) / 24
            # (a bench_kernel older than its margin_film_solves: nan)
            ms_r = r.get("margin_film_solves", float("nan")) / r["steps"]
            ms_d = d.get("margin_film_solves", float("nan")) / d["steps"] / 24
            row = f"| {label} | {model} | {per_r:.2f} | {per_d:.2f} | {per_d / per_r:.2f}"
            solves = f"{fs_d:.2f} + {ms_d:.2f} / {fs_r:.2f} + {ms_r:.2f}"
            print(f"{row} | {solves} | {os.getloadavg()[0]:.1f} |", flush=True)


def solve(deck: Path, extra: str, folder: Path) -> tuple[float, float, dict]:
    """Wall and CPU time of ringlube-solve on `deck` with `extra` appended (the run of the best
    wall time of 3) and its root attributes."""
    # the deck's own reading, if it writes one, gives way to READ_IN_N (a variable may be
    # given once only); so does its film model where extra gives one
    text = re.sub(r"tension_unit\s*=\s*'[^']*'\s*,?", "", deck.read_text())
    if "cavitation" in extra:
        text = re.sub(r"(cavitation|inlet)\s*=\s*'[^']*'\s*,?", "", text)
    path = folder / "case.nml"
    path.write_text(text + "\n" + extra + "\n")
    env = dict(os.environ)
    env.setdefault("OMP_WAIT_POLICY", "PASSIVE")
    best, best_cpu = float("inf"), float("nan")
    for _ in range(3):
        t0, c0 = time.perf_counter(), resource.getrusage(resource.RUSAGE_CHILDREN)
        subprocess.run([str(SOLVE), "-q", str(path), "-o", str(folder / "r.h5")], check=False, env=env)
        wall = time.perf_counter() - t0
        c1 = resource.getrusage(resource.RUSAGE_CHILDREN)
        if wall < best:
            best = wall
            best_cpu = c1.ru_utime + c1.ru_stime - c0.ru_utime - c0.ru_stime
    with h5py.File(folder / "r.h5") as f:
        return best, best_cpu, dict(f.attrs)


def copy_inputs(folder: Path) -> None:
    shutil.copytree(ROOT / "inputs" / "pressure", folder / "pressure")
    shutil.copy(ROOT / "inputs" / "calibration.nml", folder / "calibration.nml")


def thread_table(folder: Path) -> None:
    spin = os.environ.get("GOMP_SPINCOUNT")
    spin_note = f", GOMP_SPINCOUNT={spin}" if spin else ""
    print(f"\nOMP_WAIT_POLICY={os.environ.get('OMP_WAIT_POLICY', 'PASSIVE')}{spin_note}")
    print(
        "| deck | film | 1 thread wall s | CPU s | 2 threads wall s | CPU s | speed-up (wall) |"
        " CPU 2 / 1 | load before | load after |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|")
    for label, name in DECKS:
        deck = folder / name
        shutil.copy(ROOT / "inputs" / name, deck)
        for model, phys, _ in MODELS[::2]:
            load0 = os.getloadavg()[0]
            phys_d = f"&physics {phys} /"
            t1, c1, a1 = solve(deck, f"{READ_IN_N}\n{phys_d}\n&numerics threads = 1 /", folder)
            t2, c2, a2 = solve(deck, f"{READ_IN_N}\n{phys_d}\n&numerics threads = 2 /", folder)
            same = a1["energy_loss_J"] == a2["energy_loss_J"]
            note = "" if same else " (energies differ!)"
            row = f"| {label} | {model} | {t1:.2f} | {c1:.2f} | {t2:.2f} | {c2:.2f} | {t1 / t2:.2f}{note}"
            print(f"{row} | {c2 / c1:.2f} | {load0:.1f} | {os.getloadavg()[0]:.1f} |", flush=True)


def sector_table(folder: Path) -> None:
    name = "crf450r_4000rpm_full_hot_gas.nml"
    deck = folder / name
    shutil.copy(ROOT / "inputs" / name, deck)
    phys = "&physics cavitation='jfo', inlet='starved', bore='distorted' /"
    rows = {}
    for m in (8, 12, 24, 48, 96):
        t, _, a = solve(deck, f"{READ_IN_N}\n{phys}\n{BORE.format(m=m)}", folder)
        rows[m] = (t, a)
    ref = rows[96][1]
    keys = ("energy_loss_J", "face_leakage_mg_per_cycle", "light_gap_share_pct", "blowby_l_min")
    print(f"\nload average: {os.getloadavg()[0]:.2f}")
    print(
        "| sectors | energy J | face leakage mg | light gaps % | blowby L/min |"
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


def moves(base: Path, folder: Path) -> None:
    decks = {name[:-4]: (ROOT / "inputs" / name).read_text() for _, name in DECKS}
    # identical.py's variant: the cold deck, starved film, order 4 beyond its limit, 8 sectors
    cold = (ROOT / "inputs" / "crf450r_4000rpm_full_cold.nml").read_text()
    physics = "&physics cavitation = 'jfo', inlet = 'starved', bore = 'distorted', "
    decks["distorted_starved"] = (
        cold.replace("&physics", physics, 1) + "\n&bore order = 4, amplitude = 10e-6, sectors = 8 /\n"
    )
    print(f"load average: {os.getloadavg()[0]:.2f}; base {base}")
    print(
        "| deck | energy J | blowby L/min | face leakage mg | light gaps % | h0: largest change |"
        " largest load residual | cycles run |"
    )
    print("|---|---|---|---|---|---|---|---|")
    for name, text in decks.items():
        path = folder / f"{name}.nml"
        path.write_text(text)
        out = []
        for solver in (base, SOLVE):
            subprocess.run([str(solver), "-q", str(path), "-o", str(folder / "r.h5")], capture_output=True)
            with h5py.File(folder / "r.h5") as f:
                g = f["cycle"]
                free = g["flags"][:] & 3 == 0  # (not held at the floor or the ceiling)
                out.append((dict(f.attrs), g["h0_m"][:], free, float(abs(g["load_residual"][:][free]).max())))
        (a0, h0, f0, r0), (a1, h1, f1, r1) = out

        def pair(key: str, a0: dict = a0, a1: dict = a1) -> str:
            if key not in a0:
                return "-"
            v0, v1 = float(a0[key]), float(a1[key])
            rel = f" ({v1 / v0 - 1:+.1e})" if v0 else ""
            return f"{v0:.4g} / {v1:.4g}{rel}"

        keys = ("energy_loss_J", "blowby_l_min", "face_leakage_mg_per_cycle", "light_gap_share_pct")
        cells = " | ".join(pair(k) for k in keys)
        dh = float(abs(h1 / h0 - 1)[f0 & f1].max())
        cycles = f"{a0['cycles_run']} / {a1['cycles_run']}"
        print(f"| {name} | {cells} | {dh:.1e} | {r0:.2e} / {r1:.2e} | {cycles} |", flush=True)


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--bench", type=Path, default=BENCH, help="the bench_kernel of the cost table")
    parser.add_argument("--solve", type=Path, default=SOLVE, help="the ringlube-solve of the other tables")
    parser.add_argument("--cost-only", action="store_true", help="the cost table alone")
    parser.add_argument("--moves", type=Path, help="the answers' moves against this ringlube-solve")
    parser.add_argument("--threads-only", action="store_true", help="the speed-up table alone")
    args = parser.parse_args()
    BENCH = args.bench
    SOLVE = args.solve
    if args.moves:
        with tempfile.TemporaryDirectory(prefix="ringlube_bore_") as tmp:
            copy_inputs(Path(tmp))
            moves(args.moves, Path(tmp))
        raise SystemExit(0)
    if not args.threads_only:
        cost_table()
    if args.cost_only:
        raise SystemExit(0)
    with tempfile.TemporaryDirectory(prefix="ringlube_bore_") as tmp:
        copy_inputs(Path(tmp))
        thread_table(Path(tmp))
        if not args.threads_only:
            sector_table(Path(tmp))
