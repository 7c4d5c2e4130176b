"""Benchmark (not a test): what each cycle of a run changes, cycle by cycle, on its way to the
periodic state (docs/model.md, "Cycle and periodic state").

A run is deterministic, so the run stopped after k cycles (``max_cycles`` k) is the full run's
first k cycles: for k = 1 .. n this prints each cycle's energy, blowby, the distances the
periodicity test compares with ``cycle_tol`` (h0 at psi = 0, energy, liner film, ring pack;
the result's ``cycle_change``, ``energy_change``, ``liner_change``, ``ring_pack_change``), the
land and groove pressures and the ring lift at the cycle's end (its last crank step) and,
starved, the liner cell whose film changed most over the cycle with its film, until the run
is periodic. With --ref the run to ``cycle_tol`` 1e-6 (``max_cycles`` 60) is printed last,
and each cycle's energy and blowby relative to it. Run from the project folder:

    .venv/bin/python tests/bench/cycle_trace.py [--deck crf450r_12000rpm_full_hot_gas.nml]
        [--film swift_stieber|flooded|starved|starved_tg] [--unit N|N/m] [--per-length]
        [--pilot] [--cycles 10] [--ref]

--per-length reads the tension in N/m with ``calibration_n_per_m.nml`` and then applies
--unit (``--per-length --unit N``: the N/m reading's calibration with the tension read in N).
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

import ringlube

ROOT = Path(__file__).resolve().parents[2]
INPUTS = ROOT / "inputs"
FILMS = {
    "swift_stieber": {},
    "flooded": {"cavitation": "jfo"},
    "starved": {"cavitation": "jfo", "inlet": "starved"},
    "starved_tg": {"cavitation": "jfo", "inlet": "starved", "cavity_pressure": "trailing_gas"},
}


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--deck", default="crf450r_12000rpm_full_hot_gas.nml")
    ap.add_argument("--film", default="swift_stieber", choices=sorted(FILMS))
    ap.add_argument("--unit", default="", help="tension_unit (default: the deck's)")
    ap.add_argument("--per-length", action="store_true", help="calibration_n_per_m.nml, tension in N/m")
    ap.add_argument("--pilot", action="store_true", help="&numerics pilot_cycle")
    ap.add_argument("--cycles", type=int, default=10, help="at most this many cycles")
    ap.add_argument("--ref", action="store_true", help="also the run to cycle_tol 1e-6")
    args = ap.parse_args()

    case = ringlube.Case.from_namelist(INPUTS / args.deck)
    if args.per_length:
        case = case.with_ring(tension_unit="N/m")
        case = case.with_("calibration", file=str(INPUTS / "calibration_n_per_m.nml"))
    if args.unit:
        case = case.with_ring(tension_unit=args.unit)
    if FILMS[args.film]:
        case = case.with_physics(**FILMS[args.film])
    if args.pilot:
        case = case.with_numerics(pilot_cycle=True)
    ref = None
    if args.ref:
        ref = ringlube.run(case.with_numerics(cycle_tol=1e-6, max_cycles=60))

    print(
        f"{args.deck}, {args.film}{', pilot' if args.pilot else ''}, cycle_tol "
        f"{case.value('numerics', 'cycle_tol')}"
    )
    head = (
        f"{'cycle':>5} {'energy J':>10} {'blowby':>9} {'d h0':>8} {'d energy':>8} {'d liner':>8} "
        f"{'d rpack':>8} {'land bar':>9} {'groove':>8} {'lift um':>7}"
    )
    if ref is not None:
        head += f" {'E - ref':>8} {'bb - ref':>8}"
    head += "  liner cell changed most (z mm: film um)"
    print(head)
    last_film = None
    for k in range(1, args.cycles + 1):
        r = ringlube.run(case.with_numerics(max_cycles=k))
        line = (
            f"{k:>5} {r.energy_loss:>10.6f} {r.blowby:>9.5f} {r.cycle_change:>8.1e} "
            f"{r.energy_change:>8.1e} {r.scalars.get('liner_change', 0.0):>8.1e} "
            f"{r.ring_pack_change:>8.1e} {r.land_pressure[-1] / 1e5:>9.5f} "
            f"{r.groove_pressure[-1] / 1e5:>8.4f} {r.ring_lift[-1] * 1e6:>7.2f}"
        )
        if ref is not None:
            line += f" {r.energy_loss / ref.energy_loss - 1:>+8.1e} {r.blowby / ref.blowby - 1:>+8.1e}"
        if r.liner is not None and "liner_oil_film" in r.liner:
            film = np.asarray(r.liner["liner_oil_film"])
            z = np.asarray(r.liner["liner_position"])
            if last_film is not None:
                i = int(np.argmax(np.abs(film - last_film)))
                line += f"  {z[i] * 1e3:.3f}: {last_film[i] * 1e6:.4f} -> {film[i] * 1e6:.4f}"
            last_film = film
        print(line, flush=True)
        if r.periodic:
            break
    if ref is not None:
        print(f"  ref: {ref.cycles_run} cycles, {ref.energy_loss:.7f} J, blowby {ref.blowby:.6f}")


if __name__ == "__main__":
    main()
