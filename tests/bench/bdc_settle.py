"""Benchmark (not a test): why the starved film at a thin supply film settles slowly with
`film_time_scheme = 'bdf2'` (docs/film_model.md, "Time integration in the cycle", "Settling at
1 um cold"). The ring gathers, at the end of each downstroke, the film it laid leaving the
bottom dead centre before; what it leaves there depends on whether its gap reaches BDC full
(the surplus turned back as a bank, which the lower rings take down) or starved (what it
gathered it leaves again). This prints, cycle by cycle (the run stopped after k cycles is the
full run's first k cycles), what the periodicity test judges (h0 at psi = 0, the energy, the
liner film, docs/model.md "Cycle and periodic state") and the state at BDC:

* ``h0 160``: h0 at 160 deg (um), the branch the ring rides on before BDC (about 2.5 um: the
  wetted branch of the 2 deg step; about 1.2 um: the branch of the converged reference);
* ``fill 178``: the leading edge's inlet fill one step before BDC (psi = 180 - dpsi; 1: the
  gap full, a bank turned back; near 0: the liner ahead dry);
* ``strip um``: the liner film's mean over the strip from 1 mm above the lower edge's BDC
  position down to it (the film laid leaving BDC, gathered again before the next), and
  ``dry``: its cells with no oil;
* ``ratio``: the liner film's change over the cycle projected on its change over the cycle
  before (its contraction per cycle where one mode settles; about 1: a mode that neither
  grows nor decays, near -1: a period of two).

With --steps the same case at 2, 1, 0.5 and 0.25 deg (max_cycles 40) for euler/'face' and
bdf2/'edge': cycles, energy, h0 at 160 deg, the strip's film at the periodic state. With --rows
every starved deck at 'default' (cold and hot, 1, 2 and 5 um; tension in N without and with
`ring_pack = 'gas'`, in N/m without) with euler/'face' and bdf2/'edge': cycles, periodic (P),
energy, oil to the chamber, flagged steps, the film's Newton iterations; and the shipped
distorted bore deck (crf450r_4000rpm_full_hot_distorted.nml) as it is. Run from the project
folder:

    .venv/bin/python tests/bench/bdc_settle.py [--deck cold] [--film 1e-6] [--unit N|N/m]
        [--ring-pack none|gas] [--scheme bdf2] [--edge edge] [--dpsi 2] [--no-bdc-start]
        [--cycles 10] [--steps | --rows]
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

import ringlube

ROOT = Path(__file__).resolve().parents[2]
INPUTS = ROOT / "inputs"


def base_case(args: argparse.Namespace) -> ringlube.Case:
    case = ringlube.Case.from_namelist(INPUTS / f"crf450r_4000rpm_full_{args.deck}.nml")
    if args.unit == "N/m":
        case = case.with_ring(tension_unit="N/m")
        case = case.with_("calibration", file=str(INPUTS / "calibration_n_per_m.nml"))
    if args.ring_pack != "none":
        case = case.with_physics(ring_pack=args.ring_pack)
    case = case.with_physics(cavitation="jfo", inlet="starved")
    return case.with_("lubricant", supply_film=args.film)


def bdc_state(case: ringlube.Case, r: ringlube.CycleResult) -> tuple[float, float, float, int]:
    """h0 at 160 deg, the inlet fill a step before BDC, the strip's mean film and dry cells."""
    psi = np.asarray(r.crank_angle_deg)
    h0 = np.asarray(r.h0)
    fill = np.asarray(r.inlet_fill)
    dpsi = psi[1] - psi[0]
    i160 = int(np.argmin(abs(psi - 160.0)))
    i178 = int(np.argmin(abs(psi - (180.0 - dpsi))))
    z = np.asarray(r.liner["liner_position"])
    film = np.asarray(r.liner["liner_oil_film"])
    rc = case.value("engine", "crank_radius")
    lower = 2.0 * rc + 0.5 * case.value("ring", "width")  # the lower edge at BDC (s = 2 r)
    strip = (z > lower - 1e-3) & (z <= lower)
    dry = int(np.sum(film[strip] <= 1e-9))
    return h0[i160], fill[i178], float(film[strip].mean()), dry


def trace(args: argparse.Namespace) -> None:
    case = base_case(args).with_numerics(
        preset="default",
        film_time_scheme=args.scheme,
        film_edge_cells=args.edge,
        dpsi_deg=args.dpsi,
        bdc_start=not args.no_bdc_start,
    )
    if args.no_bdc_start:
        case = case.with_numerics(liner_window=50)  # the BDC start's window, judged alike
    print(
        f"{args.deck} {args.film * 1e6:g} um, {args.unit}, ring pack {args.ring_pack}, "
        f"{args.scheme}/'{args.edge}', {args.dpsi:g} deg, bdc_start {not args.no_bdc_start}"
    )
    print(
        f"{'cycle':>5} {'energy J':>10} {'d h0':>8} {'d energy':>8} {'d liner':>8} "
        f"{'h0 160':>7} {'fill 178':>8} {'strip um':>8} {'dry':>4} {'ratio':>7} flagged"
    )
    last = None
    change = None
    for k in range(1, args.cycles + 1):
        r = ringlube.run(case.with_numerics(max_cycles=k))
        film = np.asarray(r.liner["liner_oil_film"])
        h160, fill, strip, dry = bdc_state(case, r)
        ratio = ""
        if last is not None:
            d = film - last
            if change is not None and np.dot(change, change) > 0.0:
                ratio = f"{np.dot(d, change) / np.dot(change, change):+.3f}"
            change = d
        last = film
        print(
            f"{k:>5} {r.energy_loss:>10.6f} {r.cycle_change:>8.1e} {r.energy_change:>8.1e} "
            f"{r.liner_change:>8.1e} {h160 * 1e6:>7.3f} {fill:>8.3f} {strip * 1e6:>8.3f} "
            f"{dry:>4d} {ratio:>7s} {r.flagged_steps}",
            flush=True,
        )
        if r.periodic:
            break


def steps(args: argparse.Namespace) -> None:
    base = base_case(args)
    print(
        f"{args.deck} {args.film * 1e6:g} um, {args.unit}, ring pack {args.ring_pack}, 'default' but the step"
    )
    print(
        f"{'scheme':>11} {'deg':>5} {'cycles':>6} {'periodic':>8} {'energy J':>9} "
        f"{'h0 160':>7} {'strip um':>8} {'dry':>4}"
    )
    for dpsi in (2.0, 1.0, 0.5, 0.25):
        for scheme, edge in (("euler", "face"), ("bdf2", "edge")):
            case = base.with_numerics(
                preset="default", film_time_scheme=scheme, film_edge_cells=edge, dpsi_deg=dpsi, max_cycles=40
            )
            r = ringlube.run(case)
            h160, _, strip, dry = bdc_state(case, r)
            print(
                f"{scheme + '/' + edge:>11} {dpsi:>5g} {r.cycles_run:>6d} {r.periodic!s:>8} "
                f"{r.energy_loss:>9.5f} {h160 * 1e6:>7.3f} {strip * 1e6:>8.3f} {dry:>4d}",
                flush=True,
            )


def rows(args: argparse.Namespace) -> None:
    """The starved decks at 'default' (cold, hot; 1, 2, 5 um; in N without and with the ring
    pack, in N/m without), euler/'face' against bdf2/'edge': cycles, periodic, energy, oil,
    flagged steps and the film's Newton iterations."""
    print(
        f"{'reading':8s} {'deck':5s} {'film':>5s}  euler/'face': cycles, periodic, energy J, oil mm^3, "
        "flagged, Newton | the same with bdf2/'edge'"
    )
    for unit, pack in (("N", "none"), ("N", "gas"), ("N/m", "none")):
        for deck in ("cold", "hot"):
            for film in (1e-6, 2e-6, 5e-6):
                a = argparse.Namespace(deck=deck, film=film, unit=unit, ring_pack=pack)
                base = base_case(a).with_numerics(preset="default")
                print(
                    f"{unit + ' ' + pack:8s} {deck:5s} {film * 1e6:>3.0f}um" + _both_schemes(base), flush=True
                )
    # the shipped distorted bore deck (starved, ring pack 'gas', 24 sectors) as it is
    base = ringlube.Case.from_namelist(INPUTS / "crf450r_4000rpm_full_hot_distorted.nml")
    print(f"{'distorted hot 4000 r/min deck':22s}" + _both_schemes(base), flush=True)


def _both_schemes(base: ringlube.Case) -> str:
    """The case run with euler/'face' and bdf2/'edge': cycles, periodic, energy, oil,
    flagged steps, Newton iterations of each."""
    line = ""
    for scheme, edge in (("euler", "face"), ("bdf2", "edge")):
        r = ringlube.run(base.with_numerics(film_time_scheme=scheme, film_edge_cells=edge))
        sep = "|" if scheme == "bdf2" else " "
        per = "P" if r.periodic else "-"
        line += (
            f" {sep} {r.cycles_run:>2d} {per} {r.energy_loss:.5f} {r.oil_to_chamber:9.5f} "
            f"{r.flagged_steps:>3d} {r.reynolds_solves:>6d}"
        )
    return line


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--deck", default="cold", choices=("cold", "hot"))
    ap.add_argument("--film", type=float, default=1e-6, help="&lubricant supply_film (m)")
    ap.add_argument("--unit", default="N", choices=("N", "N/m"))
    ap.add_argument("--ring-pack", default="none", choices=("none", "gas"))
    ap.add_argument("--scheme", default="bdf2", choices=("euler", "bdf2"))
    ap.add_argument("--edge", default="edge", choices=("face", "edge", "front"))
    ap.add_argument("--dpsi", type=float, default=2.0)
    ap.add_argument(
        "--no-bdc-start", action="store_true", help="start without the BDC start (liner_window 50)"
    )
    ap.add_argument("--cycles", type=int, default=10, help="at most this many cycles")
    ap.add_argument("--steps", action="store_true", help="the step sweep instead of the trace")
    ap.add_argument("--rows", action="store_true", help="the starved decks, euler/'face' against bdf2/'edge'")
    args = ap.parse_args()
    if args.rows:
        rows(args)
    elif args.steps:
        steps(args)
    else:
        trace(args)


if __name__ == "__main__":
    main()
