"""Benchmark (make bench; not a test): the numerics presets re-measured for every film model.
For the cold and hot 4000 r/min decks and each film model: CPU time of the kernel
call per run (process time, best of N, each run alternated with Swift-Stieber's at the same preset, and
the ratio of the two bests), cycles computed, and the error of energy loss, mixed share and (starved) oil to
the chamber against a converged reference of the same model (801 nodes, 0.125 deg, tight
tolerances, the numerics of tests/bench/front.py).

    python3 tests/bench/film_presets.py [--repeats N] [--ring-pack gas] [--tension-unit N/m]
    python3 tests/bench/film_presets.py --convergence [--ring-pack gas]
    python3 tests/bench/film_presets.py --time-order [--tension-unit N/m]
    python3 tests/bench/film_presets.py --oil-default [--tension-unit N/m] [--edge front]
    python3 tests/bench/film_presets.py --oil-nodes [--tension-unit N/m]
    python3 tests/bench/film_presets.py --oil-order [--decks hot,cold] [--edge front]
    python3 tests/bench/film_presets.py --edge-cost [--repeats N]
    python3 tests/bench/film_presets.py --front-cost [--repeats N]

`--ring-pack gas` runs every model with the gas around the ring instead of the
decks' 'none'. `--convergence` prints instead, for the JFO models, the results as the nodes double at
0.25 deg and as the crank step halves at 201 nodes (tight tolerances): whether each model
converges at all, and at what order. `--time-order` prints, for the mass-conserving film starved
(supply film 1, 2 and 5 um) and flooded at 51 nodes, the error of energy and oil to the chamber
at 2, 1, 0.5, 0.25 and 0.125 deg against 0.0625 deg (tight tolerances) and the observed slopes,
with `film_time_scheme` 'bdf2' and 'euler'. `--tension-unit N/m` reads the decks' tension in
N/m (with its calibration, inputs/calibration_n_per_m.nml) instead of their N.
`--oil-default` prints the starved film (1, 2, 5 um) at 'default' with each
`film_time_scheme` (and, with 'bdf2', each `film_edge_cells`) against the reference: energy and
oil to the chamber, and the kernel time per run (`--edge front` adds bdf2/'front'); `--oil-nodes` the
starved film's oil as the nodes double (BDF2, 0.25 deg; with each `film_edge_cells`);
`--oil-order` the starved film at 1 um (BDF2, 'edge' or `--edge front`, tight tolerances) as the nodes double
(51..801 at 0.25 deg) and as the crank step halves (2..0.125 deg at 51 nodes): energy and
oil to the chamber and the observed orders of their successive differences;
`--front-cost [--repeats N]` the starved film at 'default' with bdf2/'edge' and bdf2/'front'
(experimental): energy, oil, flagged steps, oil balance, Newton iterations and CPU time per run;
`--edge-cost [--repeats N]` the kernel time per cycle of the starved film at 'default' with
euler/face (the default), bdf2/face and bdf2/edge, interleaved, and the ratios.
"""

from __future__ import annotations

import argparse
import os
import platform
import time
from pathlib import Path

from film_models import MODELS  # the film models of the cost benchmark, one list

import ringlube
import ringlube.convergence

ROOT = Path(__file__).resolve().parents[2]
# the reference numerics of `ringlube convergence` (one place), with a tight periodicity test
# and the second-order time scheme
REFERENCE = {**ringlube.convergence.REFERENCE, "cycle_tol": 1e-6, "time_scheme": "bdf2"}
PRESETS = ("fast", "default", "accurate")


def cpu_run(case: ringlube.Case) -> tuple[ringlube.CycleResult, float]:
    """The run and the CPU time in s of its kernel call (process time of the f2py `rl_run`:
    the round-bore kernel is one thread; unlike the kernel's `run_time`, wall time, it does not
    grow with the other processes on a loaded machine, and it leaves out ringlube.run's
    Python side, about 1.4 ms a run, a third of a 'default' Swift-Stieber run)."""
    kernel = ringlube._kernel
    call = kernel.rl_run
    spent = []

    def timed(*args):
        t = time.process_time()
        try:
            return call(*args)
        finally:
            spent.append(time.process_time() - t)

    kernel.rl_run = timed
    try:
        r = ringlube.run(case)
    finally:
        kernel.rl_run = call
    return r, sum(spent)


def reading(case: ringlube.Case, unit: str | None) -> ringlube.Case:
    """The deck with its tension read in `unit` (None: as shipped); N/m with its own
    calibration (docs/model.md, "The N/m reading stays available")."""
    if unit == "N/m":
        return case.with_ring(tension_unit="N/m").with_("calibration", file="calibration_n_per_m.nml")
    if unit:
        return case.with_ring(tension_unit=unit)
    return case


def convergence(ring_pack: str) -> None:
    """Each JFO model under refinement in nodes (0.25 deg) and in the crank step (201 nodes)."""
    tight = {k: REFERENCE[k] for k in ("pressure_tol", "load_tol", "cycle_tol")}
    grid = [
        (51, 0.25),
        (101, 0.25),
        (201, 0.25),
        (401, 0.25),
        (201, 2.0),
        (201, 1.0),
        (201, 0.5),
        (201, 0.125),
    ]
    print(
        f"{'deck':5s} {'film model':27s} {'nodes':>5s} {'dpsi':>6s} {'energy J':>9s} "
        f"{'mixed %':>8s} {'oil mm3':>8s}"
    )
    for stem in ("cold", "hot"):
        base = ringlube.Case.from_namelist(ROOT / "inputs" / f"crf450r_4000rpm_full_{stem}.nml")
        base = base.with_physics(ring_pack=ring_pack)
        for label, physics in MODELS.items():
            if not physics or "starved" in label and "trailing" in label:
                continue
            for nodes, dpsi in grid:
                r = ringlube.run(
                    base.with_physics(**physics).with_numerics(nodes=nodes, dpsi_deg=dpsi, **tight)
                )
                oil = f"{r.oil_to_chamber:8.3f}" if "starved" in label else f"{'-':>8s}"
                print(
                    f"{stem:5s} {label:27s} {nodes:5d} {dpsi:6.3f} {r.energy_loss:9.5f} "
                    f"{r.mixed_share:8.3f} {oil}",
                    flush=True,
                )


def time_order(decks: list[str], unit: str | None) -> None:
    """Errors against 0.0625 deg at 51 nodes, and slopes, for both time schemes."""
    import math

    steps = (2.0, 1.0, 0.5, 0.25, 0.125, 0.0625)
    tight = {"nodes": 51, "pressure_tol": 1e-8, "load_tol": 1e-6, "cycle_tol": 1e-6, "max_cycles": 40}
    models = [("starved", {"cavitation": "jfo", "inlet": "starved"}, f) for f in (1e-6, 2e-6, 5e-6)]
    models.append(("flooded", {"cavitation": "jfo"}, None))
    print(
        f"{'deck':5s} {'film':12s} {'scheme':6s} {'energy error % at 2..0.125 deg':44s} "
        f"{'slope':>5s}  {'oil error % at 2..0.125 deg':44s} {'slope':>5s}"
    )
    for stem in decks:
        base = ringlube.Case.from_namelist(ROOT / "inputs" / f"crf450r_4000rpm_full_{stem}.nml")
        base = reading(base, unit)
        for label, physics, film in models:
            case = base.with_physics(**physics)
            if film:
                case = case.with_("lubricant", supply_film=film)
                label = f"{label} {film * 1e6:.0f} um"
            for scheme in ("bdf2", "euler"):
                num = {"film_time_scheme": scheme, **tight}
                runs = [ringlube.run(case.with_numerics(dpsi_deg=d, **num)) for d in steps]
                cols = []
                for name in ("energy_loss", "oil_to_chamber"):
                    if name == "oil_to_chamber" and not film:
                        cols.append(f"{'-':44s} {'':>5s}")
                        continue
                    ref = getattr(runs[-1], name)
                    err = [abs(getattr(r, name) / ref - 1) if ref else float("nan") for r in runs[:-1]]
                    slope = math.log2(err[-2] / err[-1]) if err[-1] > 0 and err[-2] > 0 else float("nan")
                    cols.append(" ".join(f"{100 * e:8.3f}" for e in err) + f" {slope:5.2f}")
                print(f"{stem:5s} {label:12s} {scheme:6s} {cols[0]}  {cols[1]}", flush=True)


def oil_default(decks: list[str], unit: str | None, extra: tuple[str, ...] = ()) -> None:
    """The starved film (supply film 1, 2 and 5 um) at the 'default' preset with each
    `film_time_scheme` and, with 'bdf2', each `film_edge_cells` against the reference
    (REFERENCE, film_time_scheme 'bdf2', film_edge_cells 'face'; the 'edge' reference's energy
    and oil are printed above each deck's rows: the two differ by the reference grid's error):
    energy and oil to the chamber, errors in %, the cycles run and the kernel time per run
    (best of 3)."""
    print(
        f"{'deck':5s} {'film':6s} {'ref E J':>9s} {'ref oil':>9s} {'scheme':6s} {'edge':8s} "
        f"{'E err %':>8s} {'oil mm3':>9s} {'oil err %':>9s} {'cycles':>6s} {'ms/run':>7s}"
    )
    for stem in decks:
        base = ringlube.Case.from_namelist(ROOT / "inputs" / f"crf450r_4000rpm_full_{stem}.nml")
        base = reading(base, unit)
        for film in (1e-6, 2e-6, 5e-6):
            case = base.with_physics(cavitation="jfo", inlet="starved").with_("lubricant", supply_film=film)
            refs = {
                edge: ringlube.run(
                    case.with_numerics(film_time_scheme="bdf2", film_edge_cells=edge, **REFERENCE)
                )
                for edge in ("face", "edge")
            }
            print(
                f"{stem:5s} {film * 1e6:4.0f}um reference 'edge': energy {refs['edge'].energy_loss:.5f} J, "
                f"oil {refs['edge'].oil_to_chamber:.5f} mm3",
                flush=True,
            )
            ref = refs["face"]
            for scheme, edge in (("euler", "face"), ("bdf2", "face"), ("bdf2", "edge")) + tuple(
                ("bdf2", e) for e in extra
            ):
                c = case.with_numerics(preset="default", film_time_scheme=scheme, film_edge_cells=edge)
                r = min((ringlube.run(c) for _ in range(3)), key=lambda x: x.run_time)
                oil_ref = ref.oil_to_chamber
                oil_err = 100 * (r.oil_to_chamber / oil_ref - 1) if oil_ref else float("nan")
                e_err = 100 * (r.energy_loss / ref.energy_loss - 1)
                print(
                    f"{stem:5s} {film * 1e6:4.0f}um {ref.energy_loss:9.5f} {oil_ref:9.5f} {scheme:6s} "
                    f"{edge:8s} {e_err:8.3f} {r.oil_to_chamber:9.5f} {oil_err:9.2f} {r.cycles_run:6d} "
                    f"{r.run_time * 1e3:7.1f}",
                    flush=True,
                )


def front_cost(decks: list[str], unit: str | None, repeats: int) -> None:
    """The starved film (supply film 1, 2 and 5 um) at 'default' with film_time_scheme 'bdf2'
    and film_edge_cells 'edge' and 'front', run alternately: energy, oil to the chamber, flagged
    steps, oil balance error, the film's Newton iterations per run and the CPU time per run
    (process time, best of `repeats`); the errors against the reference are --oil-default's."""

    print(
        f"{'deck':5s} {'film':6s} {'edge':6s} {'energy J':>9s} {'oil mm3':>10s} {'flagged':>7s} "
        f"{'balance':>9s} {'cycles':>6s} {'newton':>8s} {'cpu ms':>7s}"
    )
    for stem in decks:
        base = ringlube.Case.from_namelist(ROOT / "inputs" / f"crf450r_4000rpm_full_{stem}.nml")
        base = reading(base, unit)
        for film in (1e-6, 2e-6, 5e-6):
            case = base.with_physics(cavitation="jfo", inlet="starved").with_("lubricant", supply_film=film)
            best: dict[str, float] = {}
            last = {}
            for _ in range(repeats):
                for edge in ("edge", "front"):
                    c = case.with_numerics(preset="default", film_time_scheme="bdf2", film_edge_cells=edge)
                    t = time.process_time()
                    last[edge] = ringlube.run(c)
                    best[edge] = min(best.get(edge, float("inf")), time.process_time() - t)
            for edge, r in last.items():
                print(
                    f"{stem:5s} {film * 1e6:4.0f}um {edge:6s} {r.energy_loss:9.5f} {r.oil_to_chamber:10.6f} "
                    f"{r.flagged_steps:7d} {r.oil_balance_error:9.2e} {r.cycles_run:6d} "
                    f"{r.reynolds_solves:8d} {best[edge] * 1e3:7.1f}",
                    flush=True,
                )


def edge_cost(decks: list[str], unit: str | None, repeats: int) -> None:
    """Kernel time per cycle of the starved film (1, 2, 5 um) at 'default' with film_time_scheme
    'euler' / film_edge_cells 'face' (the default), 'bdf2' / 'face' and 'bdf2' / 'edge': the
    runs interleaved `repeats` times (the same load for all), the median per cycle, and the
    ratios to the default's; and the film's Newton iterations per cycle (the same on any
    machine)."""
    import statistics

    combos = (("euler", "face"), ("bdf2", "face"), ("bdf2", "edge"))
    heads = " ".join(f"{s + '/' + e:>13s}" for s, e in combos)
    print(f"{'deck':5s} {'film':6s} {heads}  (ms/cycle, ratio to euler/face)")
    for stem in decks:
        base = ringlube.Case.from_namelist(ROOT / "inputs" / f"crf450r_4000rpm_full_{stem}.nml")
        base = reading(base, unit)
        for film in (1e-6, 2e-6, 5e-6):
            case = base.with_physics(cavitation="jfo", inlet="starved").with_("lubricant", supply_film=film)
            cases = [
                case.with_numerics(preset="default", film_time_scheme=s, film_edge_cells=e) for s, e in combos
            ]
            times: list[list[float]] = [[] for _ in combos]
            its = [0.0 for _ in combos]
            for _ in range(repeats):
                for k, c in enumerate(cases):
                    r = ringlube.run(c)
                    times[k].append(r.run_time / r.cycles_computed)
                    its[k] = r.reynolds_solves / r.cycles_computed
            med = [statistics.median(t) for t in times]
            print(
                f"{stem:5s} {film * 1e6:4.0f}um "
                + " ".join(f"{1e3 * m:8.1f} {m / med[0]:4.2f}" for m in med)
                + "   Newton iterations per cycle: "
                + " ".join(f"{i:7.0f} {i / its[0]:4.2f}" for i in its),
                flush=True,
            )


def oil_nodes(decks: list[str], unit: str | None) -> None:
    """Oil to the chamber and energy of the starved film (1 and 2 um, film_time_scheme 'bdf2',
    each film_edge_cells) as the nodes double at 0.25 deg (tight tolerances): the grid's share of
    the oil's error."""
    tight = {"pressure_tol": 1e-8, "load_tol": 1e-6, "cycle_tol": 1e-6, "max_cycles": 40}
    print(
        f"{'deck':5s} {'film':6s} {'edge':4s} {'nodes':>5s} {'energy J':>9s} {'oil mm3':>9s} {'cycles':>6s}"
    )
    for stem in decks:
        base = ringlube.Case.from_namelist(ROOT / "inputs" / f"crf450r_4000rpm_full_{stem}.nml")
        base = reading(base, unit)
        for film in (1e-6, 2e-6):
            case = base.with_physics(cavitation="jfo", inlet="starved").with_("lubricant", supply_film=film)
            for edge in ("face", "edge"):
                for nodes in (51, 101, 201, 401):
                    r = ringlube.run(
                        case.with_numerics(
                            nodes=nodes, dpsi_deg=0.25, film_time_scheme="bdf2", film_edge_cells=edge, **tight
                        )
                    )
                    print(
                        f"{stem:5s} {film * 1e6:4.0f}um {edge:4s} {nodes:5d} {r.energy_loss:9.5f} "
                        f"{r.oil_to_chamber:9.5f} {r.cycles_run:6d}",
                        flush=True,
                    )


def oil_order(decks: list[str], unit: str | None, edge: str = "edge") -> None:
    """The starved film at 1 um (film_time_scheme 'bdf2', film_edge_cells edge: 'edge' or 'front', tight
    tolerances) as the nodes double at 0.25 deg and as the crank step halves at 51 nodes:
    energy and oil to the chamber, and the observed order log2(d_k / d_k+1) of the successive
    differences d_k of each (the limit is not needed; the order of the oil says whether what is
    left is the meniscus' first-order error in space); and h0 at 160 deg (near the bottom dead
    centre) and its mean over 20-160 deg (mid-stroke), in um; the flagged steps, the oil balance
    error and the crank angles of the flagged steps."""
    import math

    import numpy as np

    tight = {"pressure_tol": 1e-8, "load_tol": 1e-6, "cycle_tol": 1e-6, "max_cycles": 40}
    num = {"film_time_scheme": "bdf2", "film_edge_cells": edge, **tight}
    series = {
        "nodes": [(n, 0.25) for n in (51, 101, 201, 401, 801)],
        "step": [(51, d) for d in (2.0, 1.0, 0.5, 0.25, 0.125)],
    }
    print(
        f"{'deck':5s} {'refine':6s} {'nodes':>5s} {'dpsi':>6s} {'energy J':>9s} {'oil mm3':>10s} "
        f"{'cycles':>6s} {'h0 160':>7s} {'h0 mid':>7s} {'flagged':>7s} {'balance':>9s} flagged at deg"
    )
    for stem in decks:
        base = ringlube.Case.from_namelist(ROOT / "inputs" / f"crf450r_4000rpm_full_{stem}.nml")
        base = reading(base, unit)
        case = base.with_physics(cavitation="jfo", inlet="starved").with_("lubricant", supply_film=1e-6)
        for label, grid in series.items():
            rows = []
            for nodes, dpsi in grid:
                r = ringlube.run(case.with_numerics(nodes=nodes, dpsi_deg=dpsi, **num))
                rows.append((r.energy_loss, r.oil_to_chamber))
                ca = np.asarray(r.crank_angle_deg)
                h0 = np.asarray(r.h0) * 1e6
                mid = h0[(ca >= 20) & (ca <= 160)].mean()
                print(
                    f"{stem:5s} {label:6s} {nodes:5d} {dpsi:6.3f} {r.energy_loss:9.5f} "
                    f"{r.oil_to_chamber:10.6f} {r.cycles_run:6d} {np.interp(160, ca, h0):7.3f} {mid:7.3f} "
                    f"{r.flagged_steps:7d} {r.oil_balance_error:9.2e} "
                    + " ".join(f"{a:.2f}" for a in ca[np.asarray(r.flags) != 0]),
                    flush=True,
                )
            for k, name in enumerate(("energy", "oil")):
                d = [rows[i][k] - rows[i + 1][k] for i in range(len(rows) - 1)]
                orders = [
                    math.log2(abs(d[i] / d[i + 1])) if d[i + 1] else float("nan") for i in range(len(d) - 1)
                ]
                print(
                    f"{stem:5s} {label:6s} orders of the {name}'s differences: "
                    + " ".join(f"{o:5.2f}" for o in orders)
                )


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--convergence", action="store_true")
    ap.add_argument("--decks", default="cold,hot", help="decks (cold, hot), comma-separated")
    ap.add_argument("--models", default=";".join(MODELS), help="film models, separated by ';'")
    ap.add_argument("--ring-pack", default="none", choices=("none", "gas"))
    ap.add_argument("--time-order", action="store_true")
    ap.add_argument("--oil-default", action="store_true")
    ap.add_argument("--oil-nodes", action="store_true")
    ap.add_argument("--oil-order", action="store_true")
    ap.add_argument("--edge-cost", action="store_true")
    ap.add_argument("--front-cost", action="store_true")
    ap.add_argument("--tension-unit", default=None, choices=("N", "N/m"))
    ap.add_argument(
        "--edge",
        default="edge",
        choices=("edge", "front"),
        help="--oil-order: its film_edge_cells; --oil-default: 'front' adds its rows",
    )
    args = ap.parse_args()
    if args.oil_order:
        oil_order(args.decks.split(","), args.tension_unit, args.edge)
        return
    if args.oil_nodes:
        oil_nodes(args.decks.split(","), args.tension_unit)
        return
    if args.edge_cost:
        edge_cost(args.decks.split(","), args.tension_unit, args.repeats)
        return
    if args.front_cost:
        front_cost(args.decks.split(","), args.tension_unit, args.repeats)
        return
    if args.oil_default:
        oil_default(args.decks.split(","), args.tension_unit, ("front",) if args.edge == "front" else ())
        return
    if args.time_order:
        time_order(args.decks.split(","), args.tension_unit)
        return
    if args.convergence:
        convergence(args.ring_pack)
        return
    print(
        f"machine: {platform.processor() or platform.machine()}, {os.cpu_count()} cores; "
        f"cost: CPU time of each run's kernel call (process time; the round-bore kernel is one "
        f"thread), best of {args.repeats}, each run alternated with Swift-Stieber's at the same "
        f"preset on the same deck (the ratio x SS is of those two bests); reference: "
        + " ".join(f"{k}={v}" for k, v in REFERENCE.items())
        + f"; ring_pack={args.ring_pack}"
    )
    print(
        f"{'deck':5s} {'film model':27s} {'preset':9s} {'cpu ms':>7s} {'cycles':>6s} {'x SS':>5s} "
        f"{'energy err':>10s} {'mixed pts':>9s} {'oil err':>8s} {'conv':>4s}"
    )
    models = args.models.split(";")
    for stem in args.decks.split(","):
        base = ringlube.Case.from_namelist(ROOT / "inputs" / f"crf450r_4000rpm_full_{stem}.nml")
        base = base.with_physics(ring_pack=args.ring_pack)
        base = reading(base, args.tension_unit)
        for label, physics in MODELS.items():
            if label not in models and label != "swift_stieber":
                continue
            case = base.with_physics(**physics) if physics else base
            ref, ref_cpu = cpu_run(case.with_numerics(**REFERENCE))
            print(
                f"{stem:5s} {label:27s} {'reference':9s} {ref_cpu * 1e3:7.0f} "
                f"{ref.cycles_computed:6.2f} {'':5s} energy {ref.energy_loss:.6f} J, mixed "
                f"{ref.mixed_share:.3f} %"
                + (f", oil {ref.oil_to_chamber:.4f} mm3" if "starved" in label else ""),
                flush=True,
            )
            for preset in PRESETS:
                c = case.with_numerics(preset=preset)
                # the model and Swift-Stieber back to back, `repeats` times: both bests under one load
                pair = [c] if not physics else [base.with_numerics(preset=preset), c]
                best = [float("inf")] * len(pair)
                for _ in range(args.repeats):
                    for k, ck in enumerate(pair):
                        r, cpu = cpu_run(ck)
                        best[k] = min(best[k], cpu)
                oil = (
                    f"{r.oil_to_chamber / ref.oil_to_chamber - 1:+8.1e}"
                    if "starved" in label and ref.oil_to_chamber
                    else f"{'-':>8s}"
                )
                print(
                    f"{stem:5s} {label:27s} {preset:9s} {best[-1] * 1e3:7.2f} "
                    f"{r.cycles_computed:6.2f} {best[-1] / best[0]:5.1f} "
                    f"{r.energy_loss / ref.energy_loss - 1:+10.1e} "
                    f"{r.mixed_share - ref.mixed_share:+9.3f} {oil} {'yes' if r.converged else 'no':>4s}",
                    flush=True,
                )


if __name__ == "__main__":
    main()
