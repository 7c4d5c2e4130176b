"""Benchmark (make bench; not a test): the numerics presets re-measured for every film model
(issue 9). For the cold and hot 4000 r/min decks and each film model: kernel time per run
(best of N), cycles computed, and the error of energy loss, mixed share and (starved) oil to
the chamber against a converged reference of the same model (801 nodes, 0.125 deg, tight
tolerances, the numerics of tests/bench/front.py).

    python3 tests/bench/film_presets.py [--repeats N] [--ring-pack gas]
    python3 tests/bench/film_presets.py --convergence [--ring-pack gas]

`--ring-pack gas` runs every model with the gas around the ring (SPEC 14) instead of the
decks' 'none'. `--convergence` prints instead, for the JFO models, the results as the nodes double at
0.25 deg and as the crank step halves at 201 nodes (tight tolerances): whether each model
converges at all, and at what order.
"""

from __future__ import annotations

import argparse
import os
import platform
from pathlib import Path

from film_models import MODELS  # the film models of the cost benchmark, one list

import ringlube
import ringlube.convergence

ROOT = Path(__file__).resolve().parents[2]
# the reference numerics of `ringlube convergence` (one place), with a tight periodicity test
# and the second-order time scheme
REFERENCE = {**ringlube.convergence.REFERENCE, "cycle_tol": 1e-6, "time_scheme": "bdf2"}
PRESETS = ("fast", "default", "accurate")


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


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--convergence", action="store_true")
    ap.add_argument("--decks", default="cold,hot", help="decks (cold, hot), comma-separated")
    ap.add_argument("--models", default=";".join(MODELS), help="film models, separated by ';'")
    ap.add_argument("--ring-pack", default="none", choices=("none", "gas"))
    args = ap.parse_args()
    if args.convergence:
        convergence(args.ring_pack)
        return
    print(
        f"machine: {platform.processor() or platform.machine()}, {os.cpu_count()} cores; "
        f"kernel time best of {args.repeats}; reference: "
        + " ".join(f"{k}={v}" for k, v in REFERENCE.items())
        + f"; ring_pack={args.ring_pack}"
    )
    print(
        f"{'deck':5s} {'film model':27s} {'preset':9s} {'ms/run':>7s} {'cycles':>6s} {'x SS':>5s} "
        f"{'energy err':>10s} {'mixed pts':>9s} {'oil err':>8s} {'conv':>4s}"
    )
    models = args.models.split(";")
    for stem in args.decks.split(","):
        base = ringlube.Case.from_namelist(ROOT / "inputs" / f"crf450r_4000rpm_full_{stem}.nml")
        base = base.with_physics(ring_pack=args.ring_pack)
        ss = {}
        for label, physics in MODELS.items():
            if label not in models and label != "swift_stieber":
                continue
            case = base.with_physics(**physics) if physics else base
            ref = ringlube.run(case.with_numerics(**REFERENCE))
            print(
                f"{stem:5s} {label:27s} {'reference':9s} {ref.run_time * 1e3:7.0f} "
                f"{ref.cycles_computed:6.2f} {'':5s} energy {ref.energy_loss:.6f} J, mixed "
                f"{ref.mixed_share:.3f} %"
                + (f", oil {ref.oil_to_chamber:.4f} mm3" if "starved" in label else ""),
                flush=True,
            )
            for preset in PRESETS:
                c = case.with_numerics(preset=preset)
                r = min((ringlube.run(c) for _ in range(args.repeats)), key=lambda x: x.run_time)
                ss.setdefault(preset, r.run_time)
                oil = (
                    f"{r.oil_to_chamber / ref.oil_to_chamber - 1:+8.1e}"
                    if "starved" in label and ref.oil_to_chamber
                    else f"{'-':>8s}"
                )
                print(
                    f"{stem:5s} {label:27s} {preset:9s} {r.run_time * 1e3:7.2f} "
                    f"{r.cycles_computed:6.2f} {r.run_time / ss[preset]:5.1f} "
                    f"{r.energy_loss / ref.energy_loss - 1:+10.1e} "
                    f"{r.mixed_share - ref.mixed_share:+9.3f} {oil} {'yes' if r.converged else 'no':>4s}",
                    flush=True,
                )


if __name__ == "__main__":
    main()
