"""ringlube benchmark (make bench; never part of the tests). Prints:

* ms per cycle (kernel time / cycles of crank steps computed) for each preset on the
  shipped decks;
* the damped / safeguarded time ratio at equal accuracy (same load_tol, errors against
  the 'accurate' preset shown beside);
* runs per second through run_many on 1 worker and on all cores, and the parallel
  efficiency;
* the wall time of a 10,001-run sweep (Sobol sample of the study's four design variables
  on the cold deck, preset 'default', all cores).

    python3 tests/bench/bench.py [--sweep N]
"""

from __future__ import annotations

import argparse
import os
import time
from pathlib import Path

import numpy as np

import ringlube
from ringlube import Case

ROOT = Path(__file__).resolve().parents[2]
DECKS = sorted((ROOT / "inputs").glob("crf450r_*.nml"))
VARS = {"width": (0.54e-3, 1.34e-3), "crown_height": (6e-6, 13e-6),
        "crown_offset": (-54e-6, 67e-6), "tension": (8.0, 26.0)}


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
    from scipy.stats import qmc

    lo = np.array([v[0] for v in VARS.values()])
    hi = np.array([v[1] for v in VARS.values()])

    def cases(base: Case, n: int, seed: int = 0) -> list[Case]:
        x = qmc.scale(qmc.Sobol(d=4, seed=seed).random(n), lo, hi)
        return [base.with_ring(**dict(zip(VARS, row))) for row in x]

    if not args.only_sweep:
        tables(cold, cases, cores)
    for preset in args.sweep_presets.split(","):
        print(f"\n== sweep of {args.sweep} runs on {cores} cores (preset '{preset}')")
        sweep = cases(preset_case(cold, preset), args.sweep, seed=2)
        t = time.perf_counter()
        res = ringlube.run_many(sweep, workers=cores, progress=True)
        wall = time.perf_counter() - t
        print(f"{args.sweep} runs: {wall:.1f} s wall ({args.sweep / wall:.1f} runs/s); "
              f"{sum(not r.converged for r in res)} not converged")


def tables(cold: Path, cases, cores: int) -> None:

    print("== ms per cycle by preset (kernel time / cycles computed incl. warm-up; "
          "error vs 'accurate')")
    print(f"{'deck':34s} {'preset':9s} {'ms/run':>8s} {'ms/cycle':>9s} {'energy J':>9s} "
          f"{'err':>9s} {'mixed %':>8s}")
    for deck in DECKS:
        ref = best(preset_case(deck, "accurate"), 1)
        for preset in ("fast", "default", "accurate"):
            r = best(preset_case(deck, preset), 1 if preset == "accurate" else 3)
            err = abs(r.energy_loss - ref.energy_loss) / ref.energy_loss
            print(f"{deck.stem:34s} {preset:9s} {r.run_time * 1e3:8.1f} "
                  f"{r.run_time * 1e3 / r.cycles_computed:9.2f} {r.energy_loss:9.4f} {err:9.1e} "
                  f"{r.mixed_share:8.2f}")

    print("\n== damped vs safeguarded h0 update (cold deck, preset 'default', load_tol 1e-3)")
    ref = best(preset_case(cold, "accurate"), 1)
    rows = {}
    for upd in ("safeguarded", "damped"):
        r = best(preset_case(cold, "default").with_numerics(h0_update=upd), 3)
        rows[upd] = r
        print(f"{upd:12s} {r.run_time * 1e3:8.1f} ms  film solves {int(r.film_solves.sum()):7d}  "
              f"energy {r.energy_loss:.5f} J  err vs accurate "
              f"{abs(r.energy_loss - ref.energy_loss) / ref.energy_loss:.2e}")
    print(f"damped / safeguarded time ratio: {rows['damped'].run_time / rows['safeguarded'].run_time:.1f}")

    print("\n== runs per second through run_many (cold deck variants, preset 'default')")
    sample = cases(preset_case(cold, "default"), 200, seed=1)
    t = time.perf_counter()
    ringlube.run_many(sample, workers=1, progress=False)
    t1 = time.perf_counter() - t
    t = time.perf_counter()
    ringlube.run_many(sample, workers=cores, progress=False)
    tn = time.perf_counter() - t
    print(f"1 worker: {len(sample) / t1:.1f} runs/s; {cores} workers: {len(sample) / tn:.1f} runs/s; "
          f"parallel efficiency {t1 / tn / cores:.0%}")



if __name__ == "__main__":
    main()
