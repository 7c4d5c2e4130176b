"""ringlube benchmark (make bench; never part of the tests). Prints:

* ms per cycle (kernel time / cycles of crank steps computed) for each preset on the
  shipped decks;
* the damped / safeguarded time ratio at equal accuracy (same load_tol, errors against
  the 'accurate' preset shown beside);
* the roofline pieces (bench_kernel --micro: one Thomas solve, one Roelands evaluation of
  every node, one film solve) against the cost per film solve of a whole run;
* the speed/accuracy front of the numerics (front.py), the cost of the film models
  (film_models.py) and their convergence in nodes and crank step (film_presets.py --convergence);
* a 10,001-run DOE through ringlube.run_designs batches on all cores (doe.py), for the
  presets 'default' and 'fast'.

    python3 tests/bench/bench.py [--sweep N] [--only-sweep]
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
from pathlib import Path

import ringlube
from ringlube import Case

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[1]
DECKS = sorted((ROOT / "inputs").glob("crf450r_*.nml"))


def preset_case(deck: Path, preset: str) -> Case:
    case = Case.from_namelist(deck)
    for k in ("nodes", "dpsi_deg", "pressure_tol", "load_tol"):
        case._nml.get("numerics", {}).pop(k, None)
    return case.with_numerics(preset=preset)


def best(case: Case, repeats: int = 3) -> ringlube.CycleResult:
    rs = [ringlube.run(case) for _ in range(repeats)]
    return min(rs, key=lambda r: r.run_time)


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--sweep", type=int, default=10_001, help="runs in the sweep")
    ap.add_argument("--sweep-presets", default="default,fast", help="presets of the sweeps")
    ap.add_argument("--only-sweep", action="store_true", help="skip the tables, run the sweeps")
    args = ap.parse_args()
    cores = os.cpu_count() or 1
    cold = DECKS[[d.stem for d in DECKS].index("crf450r_4000rpm_full_cold")]

    if not args.only_sweep:
        tables(cold)
        roofline(cold)
        for script in ("front.py", "film_models.py", "film_presets.py --convergence"):
            print(f"\n== {script}", flush=True)
            name, *opts = script.split()
            subprocess.run([sys.executable, str(HERE / name), *opts], check=True)
    for preset in args.sweep_presets.split(","):
        print(f"\n== DOE of {args.sweep} runs on {cores} cores (preset '{preset}', doe.py)", flush=True)
        subprocess.run(
            [sys.executable, str(HERE / "doe.py"), "--runs", str(args.sweep), "--preset", preset], check=True
        )


def roofline(cold: Path) -> None:
    """Cost per film solve in a whole 'default' run against its pieces alone."""
    exe = ROOT / "build" / "bench_kernel"
    print("\n== roofline (bench_kernel, CPU time)", flush=True)
    micro = subprocess.run(
        [str(exe), "--micro", "51"], check=True, capture_output=True, text=True, cwd=ROOT
    ).stdout.strip()
    print(micro)
    run = subprocess.run(
        [str(exe), str(cold), "", "20"], check=True, capture_output=True, text=True, cwd=ROOT
    ).stdout.strip()
    print(run)
    r = {k: float(v) for k, v in (kv.split("=") for kv in run.splitlines()[0].replace("= ", "=").split())}
    m = {k: float(v) for k, v in (kv.split("=") for kv in micro.split()[:5])}
    per_solve = r["ms_per_run"] * 1e6 / r["film_solves"]
    steps = r["cycles_computed"] * r["steps"]
    print(
        f"whole run: {per_solve:.0f} ns per film solve ({r['reynolds_solves'] / r['film_solves']:.2f} "
        f"Thomas solves each); floor of one Thomas solve + one Roelands pass: "
        f"{m['thomas_ns'] + m['roelands_all_nodes_ns']:.0f} ns; film solves per step "
        f"{r['film_solves'] / steps:.2f} (floor 1)"
    )


def tables(cold: Path) -> None:
    print("== ms per cycle by preset (kernel time / cycles computed incl. warm-up; error vs 'accurate')")
    print(
        f"{'deck':34s} {'preset':9s} {'ms/run':>8s} {'ms/cycle':>9s} {'energy J':>9s} "
        f"{'err':>9s} {'mixed %':>8s}"
    )
    for deck in DECKS:
        ref = best(preset_case(deck, "accurate"), 1)
        for preset in ("fast", "default", "accurate"):
            r = best(preset_case(deck, preset), 1 if preset == "accurate" else 3)
            err = abs(r.energy_loss - ref.energy_loss) / ref.energy_loss
            print(
                f"{deck.stem:34s} {preset:9s} {r.run_time * 1e3:8.1f} "
                f"{r.run_time * 1e3 / r.cycles_computed:9.2f} {r.energy_loss:9.4f} {err:9.1e} "
                f"{r.mixed_share:8.2f}"
            )

    print("\n== damped vs safeguarded h0 update (cold deck, preset 'default', load_tol 1e-3)")
    ref = best(preset_case(cold, "accurate"), 1)
    rows = {}
    for upd in ("safeguarded", "damped"):
        r = best(preset_case(cold, "default").with_numerics(h0_update=upd), 3)
        rows[upd] = r
        print(
            f"{upd:12s} {r.run_time * 1e3:8.1f} ms  film solves {int(r.film_solves.sum()):7d}  "
            f"energy {r.energy_loss:.5f} J  err vs accurate "
            f"{abs(r.energy_loss - ref.energy_loss) / ref.energy_loss:.2e}"
        )
    print(f"damped / safeguarded time ratio: {rows['damped'].run_time / rows['safeguarded'].run_time:.1f}")


if __name__ == "__main__":
    main()
