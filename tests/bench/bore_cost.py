"""Benchmark (not a test): what a distorted bore costs and how its sector count trades accuracy.

Three tables (markdown), with the tension read in N and the shipped calibration:

1. Cost per sector-cycle against a round cycle of the same film model, on the shipped
   distorted decks (inputs/*distorted*.nml: orders 2, 3 and 4 of 6.5 um, 24 sectors, the ring
   pack) with each film model (Swift-Stieber, flooded and starved JFO; the round cycle: the
   same deck with `bore = 'round'`), one thread: `build/bench_kernel` CPU ms per run (best of
   3), divided by the cycles computed and the sectors. Also the film solves per sector-step of
   the load balance and of the lift-off margin against the round bore's per step.
2. Speed-up of two threads (`&numerics threads = 2`) against one on the same decks: wall and
   CPU time of `build/ringlube-solve` (best of 3; and the speed-up of its solve alone, the
   result's `run_time_s`, without the process's start, the deck's reading and the output), with
   OMP_WAIT_POLICY=PASSIVE unless it is
   set (as the Python package does; a GOMP_SPINCOUNT in the environment overrides the policy's
   spin count: libgomp spins that many times before a waiting thread sleeps), the CPU time of
   two threads over one's, the voluntary context switches of the two-thread run per crank
   step (a thread that waited asleep and was woken: each costs the waker and the woken some
   microseconds on a virtual machine), and the load average beside every row. The speed-up is
   meaningful on a quiet machine only (load average below 1.5 before the run); the CPU times
   and the sleeps on any.
3. Sector count: energy, face leakage, light gaps and blowby at M = 8, 12, 24, 48 against
   M = 96, whether each run converged, and its CPU time: the starved film with the ring pack on
   the hot 4000 r/min deck with orders 2 and 4 of 12 and 8 um, and the shipped 12,000 r/min
   distorted deck with its sector count changed (`--sectors-only`: this table alone).

`--branches BASE/build/ringlube-solve` instead: the load balance's branch choice near a
sector's lift-off, this build against BASE (the root finder on the mean position alone: commit
3d2b88d). The shipped decks' rings whose sectors sit near lift-off (the own engine's at 8 N,
the 12,000 r/min deck's at 8 and 14 N, the 4000 r/min deck's at 8 N, and docs/bore.md's Python
example with order 4 of 20 um alone) at 2, 1 and 0.5 deg, the own engine's at 8 N with
load_tol 3e-4 and 1e-4, and the example's with load_tol 1e-4: energy, face leakage, the crank steps at
which a sector's h0 jumps by more than a factor e^0.2 against the ring's (`sector_jumps`,
counted from each file's sector series), the steps at which the two runs' sectors lie more than that factor
apart, and the largest residual of a step's equations over the steps neither run flagged
(`/cycle/flags` bits 4 and 128; bits 1 and 2, a ring held at a bound, left out), recomputed
from the file: the sectors' positions h0_j - D_j - [C (W - mean W)]_j in the orders
2..M/2, measured as the load that would bend the ring by them (C^+ applied), over load_tol q;
the centre's force over load_tol q M / 2; the load balance over load_tol (docs/bore.md,
"Solution"), the largest of the three, over all those steps and over the steps at which the
runs lie apart.

`--phases` instead: where a distorted bore's film solves go, per sector-step of every cycle computed
(`build/bench_kernel`'s phase line, one run of each shipped distorted deck with each film model):
the crank steps whose mean position `ring_solve` solved with the sectors (accepted), its attempts
that were refused (the sectors restored: the film solves wasted) and the root finder's trials that
then take those steps, and the lift-off margin's solves at the ceiling; with the steps and
`ring_solve`'s refusals by reason (not converged, of them with a line search without descent; at
a bound, a sector's jump, a light sector), the root finder's film solves per sector and refused
step by reason, and the share of them at the steps it held at a bound (the ring lifted off);
and the root finder's trials at the ceiling: how many, of them how many ended at the sectors'
Newton iteration limit, their film solves per sector and trial and Newton iterations per trial;
and the refused steps whose answer (the root finder's) moves a sector by more than `ring_solve`'s
limit (e^0.25) from the last step, not converged and refused as a jump: in ln h0, against the
ring's mean move (the mean of the sectors' changes of ln h0), and of the first those whose last
step or answer is at the ceiling (a refusal not converged at such a step would be refused as a
jump had it converged).
`--phases --tight-trials`: the same with the root finder's trials solved to the sectors' own
tolerance (RINGLUBE_LOOSE_TRIALS=0 for bench_kernel; the answers move).
`--phases --accept-jumps`: the same with `ring_solve` accepting an answer that moves a sector by
more than its limit (RINGLUBE_ACCEPT_JUMPS=1 for bench_kernel; the answers move), with the energy
and the cycles computed of both.
`bench_kernel` reads three more switches from the environment, which `--phases` and `--cost-only`
pass on: RINGLUBE_RING_SOLVE_CAP=n, `ring_solve`'s Newton iterations at most (12 without it;
the answers move), RINGLUBE_JUMP_EXIT=x, where its iteration ends once a sector is more than
x in ln h0 from the last step and moving away (0.35 without it, 0 off; docs/bore.md, "Cost"),
and RINGLUBE_RELATIVE_JUMP=1, both limits measured against the ring's mean move (off without
it; the answers move).

`--moves BASE/build/ringlube-solve` instead: how far a kernel change that is not
bit-identical moves a distorted bore's answers (the shipped distorted decks as shipped and
identical.py's `distorted_starved` variant, this build against BASE): energy, blowby, face
leakage and light gaps, the largest relative change of a step's h0 (the smallest sector's)
and the largest load residual over the steps not held at a bound (in both runs), and the
cycles run.

`--root-room` instead: whether an accepted step leaves the ring's centre within the groove's
root, |(x_c, y_c)| <= back_clearance - c (docs/bore.md, "Radial collapse"; the model imposes it
only at the clearance, where it holds the centre at 0), on the shipped distorted decks with each
film model, the tension read in N and in N/m (the same number: read in N/m the elastic pressure
is 21-23 times lower, and some rings collapse), one `build/ringlube-solve` run each, its
reported cycle read back from the file. A step's mean position c and centre are orders 0 and 1
of h0_j - D_j (the bending term has neither); a step is at the clearance where it is held there
(flag 2) or c is within 1e-3 of it. The steps, those at the clearance and their largest centre
(within the sectors' position tolerance of 0.1 load_tol c), and over the others the largest
|(x_c, y_c)| / (back_clearance - c) with its crank angle and c, and the steps where it is above
1 (the centre beyond the root).

Run from the project folder (4 minutes on the shared 2-core machine at a load average of 8-13;
the cost table alone 35 s at a load of 2-4):

    .venv/bin/python tests/bench/bore_cost.py
    .venv/bin/python tests/bench/bore_cost.py --cost-only --bench OTHER/build/bench_kernel
    .venv/bin/python tests/bench/bore_cost.py --threads-only   # at a quiet moment
    .venv/bin/python tests/bench/bore_cost.py --threads-only --solve OTHER/build/ringlube-solve
    .venv/bin/python tests/bench/bore_cost.py --moves BASE/build/ringlube-solve   # 30 s
    .venv/bin/python tests/bench/bore_cost.py --phases   # 20 s
    .venv/bin/python tests/bench/bore_cost.py --phases --accept-jumps   # 40 s
    .venv/bin/python tests/bench/bore_cost.py --phases --tight-trials   # 20 s
    RINGLUBE_RING_SOLVE_CAP=20 .venv/bin/python tests/bench/bore_cost.py --phases
    RINGLUBE_JUMP_EXIT=0 .venv/bin/python tests/bench/bore_cost.py --phases
    RINGLUBE_RELATIVE_JUMP=1 .venv/bin/python tests/bench/bore_cost.py --phases
    .venv/bin/python tests/bench/bore_cost.py --branches BASE/build/ringlube-solve   # 3 min
    .venv/bin/python tests/bench/bore_cost.py --root-room   # 40 s
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
import numpy as np

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


def phase_run(
    deck: Path, phys: str, accept_jumps: bool = False, loose: bool = True
) -> tuple[dict, list, list, list, list]:
    """bench_kernel's values, its phase line (film solves, calls, refusals) and its line of the
    root finder's film solves by refusal (by reason, held at a bound, stalled, then its trials
    at the ceiling: trials, film solves, Newton iterations, missed), one run."""
    env = dict(os.environ, RINGLUBE_ACCEPT_JUMPS="1" if accept_jumps else "0")
    env["RINGLUBE_LOOSE_TRIALS"] = "1" if loose else "0"
    out = subprocess.run(
        [str(BENCH), str(deck), f"{READ_IN_N} &physics {phys} /", "1"],
        capture_output=True,
        text=True,
        check=True,
        env=env,
    ).stdout
    vals = {k: float(v) for k, v in re.findall(r"(\w+)=\s*([-+0-9.eE]+)", out)}
    line = out.split("by phase")[1].split("\n")[0]
    solves, calls, refusals = (
        [int(x) for x in part.split(":")[1].split()] for part in re.split(r"(?= calls:| refusals)", line)
    )
    by_refusal = [int(x) for x in re.findall(r"-?\d+", out.split("by refusal")[1].split(":", 1)[1])]
    ceiling = [int(x) for x in out.split("at the ceiling")[1].split(":", 1)[1].split("\n")[0].split()]
    # (the refused steps whose answer moves a sector beyond the limit; none from an older
    # bench_kernel)
    far = out.split("beyond the limit")
    moved = []
    if len(far) > 1:
        moved = [int(x) for x in re.findall(r"\d+", far[1].split(":", 1)[1].split("\n")[0])]
    return vals, solves, calls, refusals, by_refusal[:9] + ceiling + moved


def phase_table(accept_jumps: bool = False, loose: bool = True) -> None:
    """Film solves per sector-step of every cycle computed, by phase (bench_kernel, one run),
    and the root finder's film solves per sector and refused step by the refusal's reason (not
    converged, of them with a stalled line search; the others), with the share of them at the
    steps the root finder held at a bound (lift-off), and its trials at the ceiling (their
    count, of them missed: Newton iterations at their limit; film solves per sector and
    trial, Newton iterations per trial); with accept_jumps, of the run whose
    ring_solve accepts a sector's jump, with the energy, the cycles computed and the film
    solves per sector-step of both runs; loose False: with the root finder's trials solved to
    the sectors' own tolerance (RINGLUBE_LOOSE_TRIALS=0). The refused steps (not converged,
    refused as a jump) whose answer moves a sector beyond ring_solve's limit: in ln h0 (against
    the ring's mean move; of the first at the ceiling)."""
    extra = ""
    if accept_jumps:
        extra = " | energy J: accepting / not | cycles computed | film solves per sector-step"
    print(
        "| deck | film | steps | accepted: steps, solves per sector-step | refused: steps, wasted"
        " | root finder: trials, solves per sector-step | margin | all | refusals: not converged"
        " (stalled), bound, jump, light | root finder per sector and refused step: not converged,"
        f" jump, other | of them held at a bound | root finder at the ceiling: trials (missed),"
        " solves per sector and trial, iterations per trial | refused steps whose answer moves a sector"
        f" beyond the limit: not converged, jump (against the ring's mean move; at the ceiling){extra} |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|" + ("---|---|---|" if accept_jumps else ""))
    for label, name in DECKS:
        deck = ROOT / "inputs" / name
        for model, phys, _ in MODELS:
            vals, solves, calls, refusals, by_refusal = phase_run(deck, phys, accept_jumps, loose)
            steps = round(vals["steps"] * vals["cycles_computed"])
            m = 24
            per = [x / (steps * m) for x in solves]
            rf, held, stalled = by_refusal[:4], by_refusal[4:8], by_refusal[8]
            groups = ((0,), (2,), (1, 3))
            per_refused = []
            for g in groups:
                n = sum(refusals[i] for i in g)
                per_refused.append(f"{sum(rf[i] for i in g) / (m * n):.1f}" if n else "-")
            held_share = f"{sum(held) / sum(rf):.0%}" if sum(rf) else "-"
            c_trials, c_solves, c_its, c_missed = by_refusal[9:13]
            at_ceiling = (
                f"{c_trials} ({c_missed}), {c_solves / (m * c_trials):.1f}, {c_its / c_trials:.1f}"
                if c_trials
                else "0"
            )
            moved = by_refusal[13:]
            far = "-"
            if len(moved) == 12:
                far = ", ".join(f"{moved[i]} ({moved[4 + i]}; {moved[8 + i]})" for i in (0, 2))
            row = (
                f"| {label} | {model} | {steps} | {calls[0]}, {per[0]:.2f} | {calls[1]}, {per[1]:.2f}"
                f" | {calls[2]}, {per[2]:.2f} | {per[3]:.2f} | {sum(per):.2f} |"
                f" {refusals[0]} ({stalled}), {', '.join(str(x) for x in refusals[1:])} |"
                f" {', '.join(per_refused)} | {held_share} | {at_ceiling} | {far} |"
            )
            if accept_jumps:
                v0, s0, _, _, _ = phase_run(deck, phys)
                steps0 = round(v0["steps"] * v0["cycles_computed"])
                row += (
                    f" {vals['energy']:.6f} / {v0['energy']:.6f} |"
                    f" {vals['cycles_computed']:.2f} / {v0['cycles_computed']:.2f} |"
                    f" {sum(per):.2f} / {sum(s0) / (steps0 * m):.2f} |"
                )
            print(row, flush=True)


def solve(deck: Path, extra: str, folder: Path) -> tuple[float, float, dict]:
    """Wall and CPU time of ringlube-solve on `deck` with `extra` appended (the run of the best
    wall time of 3) and its root attributes, with "sleeps_per_step" added: the run's voluntary
    context switches (a thread waiting asleep, woken later) per crank step computed."""
    # the deck's own reading, if it writes one, gives way to READ_IN_N (a variable may be
    # given once only); so does its film model where extra gives one
    text = re.sub(r"tension_unit\s*=\s*'[^']*'\s*,?", "", deck.read_text())
    if "cavitation" in extra:
        text = re.sub(r"(cavitation|inlet)\s*=\s*'[^']*'\s*,?", "", text)
    path = folder / "case.nml"
    path.write_text(text + "\n" + extra + "\n")
    env = dict(os.environ)
    env.setdefault("OMP_WAIT_POLICY", "PASSIVE")
    best, best_cpu, sleeps, kernel = float("inf"), float("nan"), 0, float("nan")
    for _ in range(3):
        t0, c0 = time.perf_counter(), resource.getrusage(resource.RUSAGE_CHILDREN)
        subprocess.run([str(SOLVE), "-q", str(path), "-o", str(folder / "r.h5")], check=False, env=env)
        wall = time.perf_counter() - t0
        c1 = resource.getrusage(resource.RUSAGE_CHILDREN)
        if wall < best:
            best = wall
            best_cpu = c1.ru_utime + c1.ru_stime - c0.ru_utime - c0.ru_stime
            sleeps = c1.ru_nvcsw - c0.ru_nvcsw
            with h5py.File(folder / "r.h5") as f:
                kernel = float(f.attrs["run_time_s"])
    with h5py.File(folder / "r.h5") as f:
        attrs = dict(f.attrs)
        steps = len(f["cycle/flags"]) * float(attrs.get("cycles_run", 1))
    attrs["sleeps_per_step"] = sleeps / steps
    # the kernel's own wall time of that run (the solve, without the deck's reading and the output)
    attrs["run_time_s"] = kernel
    return best, best_cpu, attrs


def copy_inputs(folder: Path) -> None:
    shutil.copytree(ROOT / "inputs" / "pressure", folder / "pressure")
    shutil.copy(ROOT / "inputs" / "calibration.nml", folder / "calibration.nml")


def thread_table(folder: Path) -> None:
    spin = os.environ.get("GOMP_SPINCOUNT")
    spin_note = f", GOMP_SPINCOUNT={spin}" if spin else ""
    print(f"\nOMP_WAIT_POLICY={os.environ.get('OMP_WAIT_POLICY', 'PASSIVE')}{spin_note}")
    print(
        "| deck | film | 1 thread wall s | CPU s | 2 threads wall s | CPU s | speed-up (wall) |"
        " CPU 2 / 1 | speed-up of the solve (run_time_s) | sleeps per step, 2 threads |"
        " load before | load after |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
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
            sleeps = f"{a2['sleeps_per_step']:.1f}"
            kernel = f"{a1['run_time_s'] / a2['run_time_s']:.2f}"
            load1 = os.getloadavg()[0]
            print(f"{row} | {c2 / c1:.2f} | {kernel} | {sleeps} | {load0:.1f} | {load1:.1f} |", flush=True)


def sector_table(folder: Path) -> None:
    """The sector count's table on two decks: the 4000 r/min ring pack deck with orders 2 and
    4 of 12 and 8 um (a ring that conforms while gas could pass: no face leakage to speak of),
    and the shipped 12,000 r/min distorted deck as shipped but for its sector count (its 8 N
    ring passes gas through its faces)."""
    gas = folder / "crf450r_4000rpm_full_hot_gas.nml"
    shutil.copy(ROOT / "inputs" / gas.name, gas)
    shipped = (ROOT / "inputs" / "crf450r_12000rpm_full_hot_distorted.nml").read_text()
    cases = {
        "CRF450R 4000 hot, starved, orders 2 and 4 of 12 and 8 um": (
            gas,
            "&physics cavitation='jfo', inlet='starved', bore='distorted' /\n" + BORE,
        ),
        "CRF450R 12000 hot distorted, as shipped": (folder / "distorted_m.nml", ""),
    }
    keys = ("energy_loss_J", "face_leakage_mg_per_cycle", "light_gap_share_pct", "blowby_l_min")
    for label, (deck, extra) in cases.items():
        rows = {}
        for m in (8, 12, 24, 48, 96):
            if not extra:
                deck.write_text(re.sub(r"sectors\s*=\s*\d+", f"sectors = {m}", shipped))
            t, cpu, a = solve(deck, f"{READ_IN_N}\n{extra.format(m=m)}", folder)
            rows[m] = (cpu, a)
        ref = rows[96][1]
        print(f"\n{label}; load average: {os.getloadavg()[0]:.2f}")
        print(
            "| sectors | energy J | face leakage mg | light gaps % | blowby L/min |"
            " energy vs 96 | leakage vs 96 | converged | CPU s |"
        )
        print("|---|---|---|---|---|---|---|---|---|")
        for m, (cpu, a) in rows.items():
            e, f, lg, bb = (float(a[k]) for k in keys)
            de = e / float(ref[keys[0]]) - 1
            df = f / float(ref[keys[1]]) - 1 if float(ref[keys[1]]) > 1e-3 else float("nan")
            conv = "yes" if int(a["converged"]) else "no"
            cells = f"{e:.4f} | {f:.3f} | {lg:.1f} | {bb:.3f} | {de:+.2%} | {df:+.2%}"
            print(f"| {m} | {cells} | {conv} | {cpu:.1f} |", flush=True)


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


#: a sector's jump between crank steps, in ln h0 (the kernel's result `sector_jumps`)
JUMP = 0.2


def distortion(a: dict, theta: np.ndarray) -> np.ndarray:
    """The bore's distortion D at the sectors' angles from a file's attributes (&bore's lists)."""
    orders = [int(k) for k in str(a["bore.order"]).split(",")]
    amps = [float(x) for x in str(a["bore.amplitude"]).split(",")]
    phases = (
        [float(x) for x in str(a["bore.phase"]).split(",")]
        if str(a["bore.phase"]).strip()
        else [0.0] * len(orders)
    )
    return sum(amp * np.cos(k * (theta - phi)) for k, amp, phi in zip(orders, amps, phases))


def step_residuals(path: Path) -> dict:
    """A distorted run's sectors (crank steps x sectors) and the residual of each step's
    equations recomputed from its file (see the module's description), over its tolerance."""
    with h5py.File(path) as f:
        a, g = dict(f.attrs), f["cycle"]
        h, w = g["sector_h0_m"][:], g["sector_load_N_per_m"][:]
        load, flags = g["applied_load_N"][:], g["flags"][:]
    assert not str(a["bore.distortion_file"]), "the lists of &bore only"
    m, r0, tol = int(a["bore.sectors"]), float(a["engine.bore_radius"]), float(a["numerics.load_tol"])
    theta = 2 * np.pi * np.arange(m) / m
    dist = distortion(a, theta)
    ei = float(a["surface.e_ring"]) * float(a["ring.width"]) * float(a["ring.radial_depth"]) ** 3 / 12
    comp, stiff = np.zeros((m, m)), np.zeros((m, m))  # C and C^+ on the sectors
    for k in range(2, m // 2 + 1):
        wave = (1 if 2 * k == m else 2) / m * np.cos(k * (theta[:, None] - theta[None, :]))
        ck = r0**4 / (ei * (k * k - 1) ** 2)
        comp += ck * wave
        stiff += wave / ck
    circ = 2 * np.pi * r0
    q = np.maximum(load, 1e-3) / circ
    dw = w - w.mean(axis=1)[:, None]
    bend = np.abs((h - dist - dw @ comp.T) @ stiff.T).max(axis=1) / (tol * q)
    centre = np.maximum(abs(dw @ np.cos(theta)), abs(dw @ np.sin(theta))) / (0.5 * m * q * tol)
    balance = abs(w.mean(axis=1) * circ - load) / np.maximum(load, 1e-3) / tol
    rel = np.log(h) - np.log(h).mean(axis=1)[:, None]  # (against the ring's: `sector_jumps`)
    jumps = int(np.count_nonzero(abs(np.diff(rel, axis=0)).max(axis=1) > JUMP))
    return {
        "attrs": a,
        "h": h,
        "residual": np.maximum(bend, np.maximum(centre, balance)),
        "solved": flags & (4 | 128) == 0,
        "free": flags & (1 | 2) == 0,
        "jumps": jumps,
    }


def branches(base: Path, folder: Path) -> None:
    import ringlube  # (the Python package writes the decks)

    decks = (
        ("own 86 3000", "own86_3000rpm_full_distorted.nml", 8.0),
        ("CRF450R 12000 hot", "crf450r_12000rpm_full_hot_distorted.nml", 14.0),
        ("CRF450R 12000 hot", "crf450r_12000rpm_full_hot_distorted.nml", 8.0),
        ("CRF450R 4000 hot", "crf450r_4000rpm_full_hot_distorted.nml", 8.0),
        # (docs/bore.md's Python example with order 4 of 20 um alone, 3.7 times its limit)
        ("CRF450R 4000 hot, order 4 of 20 um", "crf450r_4000rpm_full_hot_gas.nml", 8.0),
    )
    runs = [(label, name, t, step, None) for label, name, t in decks for step in (2.0, 1.0, 0.5)]
    runs += [(*decks[0], 2.0, tol) for tol in (3e-4, 1e-4)] + [(*decks[-1], 2.0, 1e-4)]
    print(f"load average: {os.getloadavg()[0]:.2f}; root finder: {base}; this build: {SOLVE}")
    print(
        "| deck | ring, crank step | energy J | face leakage mg | sector jumps | steps apart |"
        " largest residual / tolerance | at the steps apart | converged |"
    )
    print("|---|---|---|---|---|---|---|---|---|")
    for label, name, tension, step, tol in runs:
        case = ringlube.Case.from_namelist(ROOT / "inputs" / name).with_ring(tension=tension)
        if "distorted" not in name:
            case = case.with_physics(bore="distorted", cavitation="jfo", inlet="starved")
            case = case.with_("bore", order=[4], amplitude=[20e-6], sectors=24)
        case = case.with_numerics(dpsi_deg=step, **({"load_tol": tol} if tol else {}))
        deck = folder / "case.nml"
        case.to_namelist(deck)
        out = []
        for solver in (base, SOLVE):
            subprocess.run([str(solver), "-q", str(deck), "-o", str(folder / "r.h5")], capture_output=True)
            out.append(step_residuals(folder / "r.h5"))
        r0, r1 = out
        apart = abs(np.log(r1["h"] / r0["h"])).max(axis=1) > JUMP
        both = r0["solved"] & r1["solved"] & r0["free"] & r1["free"]

        cells = [
            [format(float(r["attrs"]["energy_loss_J"]), ".4f") for r in out],
            [format(float(r["attrs"]["face_leakage_mg_per_cycle"]), ".3g") for r in out],
            [str(r["jumps"]) for r in out],
            [f"{np.count_nonzero(apart)} of {apart.size}"],
            [worst(r["residual"][both]) for r in out],
            [worst(r["residual"][both & apart]) for r in out],
            [converged(r) for r in out],
        ]
        ring = f"{float(case.value('ring', 'width')) * 1e3:.3g} mm, {tension:g} N, {step:g} deg"
        ring += f", load_tol {tol:g}" if tol else ""
        print(f"| {label} | {ring} | " + " | ".join(" / ".join(c) for c in cells) + " |", flush=True)


def worst(x: np.ndarray) -> str:
    """The largest of residuals over their tolerance (how many are over it)."""
    return f"{x.max():.2f} ({np.count_nonzero(x > 1)})" if x.size else "-"


def converged(r: dict) -> str:
    a = r["attrs"]
    return "yes" if a["converged"] else f"no ({np.count_nonzero(~r['solved'])} steps, period {a['period']})"


def root_room(folder: Path) -> None:
    """The centre against the groove's root at the accepted steps (see the module's description)."""
    print(f"load average: {os.getloadavg()[0]:.2f}; {SOLVE}")
    print(
        "| deck | film | tension read in | steps | at the clearance: steps, largest centre / clearance |"
        " below it: largest centre / room (crank angle, c / clearance) | above 1 | converged |"
    )
    print("|---|---|---|---|---|---|---|---|")
    for label, name in DECKS:
        text = re.sub(r"tension_unit\s*=\s*'[^']*'\s*,?", "", (ROOT / "inputs" / name).read_text())
        text = re.sub(r"(cavitation|inlet)\s*=\s*'[^']*'\s*,?", "", text)
        for model, phys, _ in MODELS:
            for unit in ("N", "N/m"):
                path = folder / "case.nml"
                path.write_text(f"{text}\n&ring tension_unit = '{unit}' /\n&physics {phys} /\n")
                subprocess.run([str(SOLVE), "-q", str(path), "-o", str(folder / "r.h5")], capture_output=True)
                with h5py.File(folder / "r.h5") as f:
                    a, g = dict(f.attrs), f["cycle"]
                    h, flags, psi = g["sector_h0_m"][:], g["flags"][:], g["crank_angle_deg"][:]
                assert not str(a["bore.distortion_file"]), "the lists of &bore only"
                m, bc = h.shape[1], float(a["ring_pack.back_clearance"])
                theta = 2 * np.pi * np.arange(m) / m
                rel = h - distortion(a, theta)
                cc = rel.mean(axis=1)
                centre = 2 / m * np.hypot(rel @ np.cos(theta), rel @ np.sin(theta))
                held = (flags & 2 != 0) | (cc >= (1 - 1e-3) * bc)
                use = np.where(held, 0.0, centre / np.maximum(bc - cc, 1e-30))
                k = int(np.argmax(use))
                at = f"{np.count_nonzero(held)}, {centre[held].max() / bc if held.any() else 0:.1e}"
                below = f"{use[k]:.3f} ({psi[k]:g}, {cc[k] / bc:.3f})"
                over, conv = np.count_nonzero(use > 1), "yes" if int(a["converged"]) else "no"
                row = f"| {label} | {model} | {unit} | {len(h)} | {at} | {below} | {over} | {conv} |"
                print(row, flush=True)


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--bench", type=Path, default=BENCH, help="the bench_kernel of the cost table")
    parser.add_argument("--solve", type=Path, default=SOLVE, help="the ringlube-solve of the other tables")
    parser.add_argument("--cost-only", action="store_true", help="the cost table alone")
    parser.add_argument("--moves", type=Path, help="the answers' moves against this ringlube-solve")
    parser.add_argument("--threads-only", action="store_true", help="the speed-up table alone")
    parser.add_argument("--branches", type=Path, help="the branch choice against this ringlube-solve")
    parser.add_argument("--phases", action="store_true", help="the film solves by phase alone")
    parser.add_argument("--sectors-only", action="store_true", help="the sector count's table alone")
    parser.add_argument(
        "--root-room", action="store_true", help="the ring's centre against the groove's root alone"
    )
    parser.add_argument(
        "--accept-jumps", action="store_true", help="with --phases: ring_solve accepting a sector's jump"
    )
    parser.add_argument(
        "--tight-trials",
        action="store_true",
        help="with --phases: the root finder's trials solved to the sectors' own tolerance",
    )
    args = parser.parse_args()
    BENCH = args.bench
    SOLVE = args.solve
    if args.phases:
        phase_table(args.accept_jumps, not args.tight_trials)
        raise SystemExit(0)
    if args.branches:
        with tempfile.TemporaryDirectory(prefix="ringlube_bore_") as tmp:
            copy_inputs(Path(tmp))
            branches(args.branches, Path(tmp))
        raise SystemExit(0)
    if args.root_room:
        with tempfile.TemporaryDirectory(prefix="ringlube_bore_") as tmp:
            copy_inputs(Path(tmp))
            root_room(Path(tmp))
        raise SystemExit(0)
    if args.sectors_only:
        with tempfile.TemporaryDirectory(prefix="ringlube_bore_") as tmp:
            copy_inputs(Path(tmp))
            sector_table(Path(tmp))
        raise SystemExit(0)
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
