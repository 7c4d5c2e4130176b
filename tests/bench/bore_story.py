"""The ring engineer's story of the distorted bore, at more length than the validation page
(not a test; `ringlube validate` writes the page's section "Bore distortion and
conformability" from its own runs): the conformability limits per order, when and where the
film opens over the cycle (per stroke: the spread of the sectors' films, where it is
largest, the pressure behind the ring there, the steps pushed off the liner, the gas through
the faces), the radial collapse at 12,000 r/min against the crank step, narrow and wide rings
at 8 and 26 N, the tension swept, and the own 86 x 86 mm engine.

Every run: the ring pack's gas (`ring_pack = 'gas'`), the starved mass-conserving film
(`cavitation = 'jfo'`, `inlet = 'starved'`), the tension read in N (tangential force), preset
'default' and 24 sectors. The distorted bore is the shipped one: orders 2, 3 and 4 of 6.5 um
each (`inputs/crf450r_4000rpm_full_hot_distorted.nml`, which says where the amplitudes come
from); the round bore is the same deck with `bore = 'round'` (no `&bore` group). The CRF450R
decks take the shipped calibration file (fitted on a round bore without the ring pack: taken over, not
fitted, here); the own engine is uncalibrated (docs/own_engine.md). Run from the project
folder (`--part` runs one table, `--times` prints each run's wall time):

    .venv/bin/python tests/bench/bore_story.py [--part limits|cycle|step|rings|tension|own]
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import ringlube

ROOT = Path(__file__).resolve().parents[2]
INPUTS = ROOT / "inputs"
TIMES = False  # --times: each run's wall time after its row
#: the own engine's rings: its 1.2 mm, 15 N ring, 8 and 26 N, a 0.8 and a 1.5 mm ring
OWN_RINGS = [(1.2e-3, 15.0), (1.2e-3, 8.0), (1.2e-3, 26.0), (0.8e-3, 15.0), (1.5e-3, 15.0)]

COLUMNS = (
    "| engine | speed r/min | bore | ring | conformability | energy J/cycle | friction W | blowby L/min "
    "| face leakage mg/cycle | oil to chamber mm^3/cycle | light gaps % | sector jumps | off the liner % "
    "| flutter | converged |"
)


def crf450r(speed: int, bore: str) -> ringlube.Case:
    """The CRF450R hot full-load deck at ``speed`` with the ring pack and the starved film,
    the tension in N, on the shipped distorted bore or on a round one."""
    if bore == "distorted":
        return ringlube.Case.from_namelist(INPUTS / f"crf450r_{speed}rpm_full_hot_distorted.nml")
    return (
        ringlube.Case.from_namelist(INPUTS / f"crf450r_{speed}rpm_full_hot_gas.nml")
        .with_physics(cavitation="jfo", inlet="starved")
        .with_ring(tension_unit="N")
    )


def own(bore: str) -> ringlube.Case:
    """The own 86 x 86 mm engine of docs/own_engine.md at 3000 r/min full load (the shipped
    deck is distorted; round: the same with ``bore = 'round'`` and no ``&bore``)."""
    case = ringlube.Case.from_namelist(INPUTS / "own86_3000rpm_full_distorted.nml")
    if bore == "distorted":
        return case
    groups = case.to_dict()
    groups.pop("bore")
    groups["physics"]["bore"] = "round"
    return ringlube.Case(groups, name="own86_round")


def row(engine: str, speed: int, bore: str, ring: str, case: ringlube.Case) -> str:
    t0 = time.perf_counter()
    r = ringlube.run(case)
    s = r.scalars
    distorted = bore == "distorted"

    def d(name: str, fmt: str) -> str:
        return format(s[name], fmt) if distorted else "-"

    # (a step held at the ceiling is flagged but no failure: a run without a period says so)
    why = f"{r.flagged_steps:.0f} flagged" if r.scalars["periodic"] else "no period"
    conv = "yes" if r.converged else f"no ({why})"
    return (
        f"| {engine} | {speed} | {bore} | {ring} | {d('conformability', '.2f')} | {r.energy_loss:.3f} "
        f"| {r.friction_power:.1f} | {s['blowby']:.2f} | {d('face_leakage', '.3g')} "
        f"| {s['oil_to_chamber']:.3g} | {d('light_gap_share', '.1f')} | {d('sector_jumps', '.0f')} "
        f"| {s['liner_lift_share']:.2f} | {s['flutter_events']:.0f} | {conv} |"
    ) + (f"  ({time.perf_counter() - t0:.0f} s)" if TIMES else "")


def header():
    print(COLUMNS)
    print("|---" * (COLUMNS.count("|") - 1) + "|")


def limits_table():
    """The classical conformability limit of each ring per order (closed form of docs/bore.md,
    the kernel's `conformability` is A_k over it: tests/python/test_bore_study.py checks that)."""
    print(
        "| engine | ring | p_e kPa | limit k=2 um | limit k=3 um | limit k=4 um | shipped A_k um "
        "| A_4 / limit |"
    )
    print("|---|---|---|---|---|---|---|---|")
    crf, own86 = crf450r(4000, "distorted"), own("distorted")
    rings = [("CRF450R", crf, w, t) for w in (0.54e-3, 1.004e-3, 1.34e-3) for t in (8.0, 26.0)]
    rings += [("86 x 86", own86, w, t) for w, t in OWN_RINGS]
    for engine, case, w, t in rings:
        r0, e = case.value("engine", "bore_radius"), case.value("surface", "e_ring")
        d = case.value("ring", "radial_depth")
        q = t / r0  # tension in N: p_e = F_T / (b r0), q = p_e b
        lim = {k: q * r0**4 / (e * w * d**3 / 12 * (k * k - 1) ** 2) for k in (2, 3, 4)}
        amps = dict(zip(case.value("bore", "order"), case.value("bore", "amplitude")))
        print(
            f"| {engine} | {w * 1e3:.3g} mm, {t:.0f} N | {q / w / 1e3:.0f} | {lim[2] * 1e6:.0f} "
            f"| {lim[3] * 1e6:.1f} | {lim[4] * 1e6:.2f} "
            f"| {', '.join(f'{a * 1e6:g}' for a in amps.values())} | {amps[4] / lim[4]:.2f} |"
        )


def cycle_table():
    """When and where the film opens over the cycle: per stroke the smallest and the largest
    spread of the sectors' films (max h0_j / min h0_j), where it is largest (crank angle, sector
    angle of the thickest film), the pressure behind the ring there, the steps the ring is
    pushed off the liner (radial collapse: every sector at back_clearance, a spread of 1), and
    the gas through the faces (towards the crankcase positive, back to the chamber negative)."""
    import tempfile

    import h5py
    import numpy as np

    print(
        "| speed r/min | ring | stroke | smallest h0 max/min | largest h0 max/min | at crank deg "
        "| thickest sector deg | groove bar there | pushed off the liner, crank deg | face leakage mg |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|")
    strokes = ("intake", "compression", "expansion", "exhaust")
    with tempfile.TemporaryDirectory() as tmp:
        for speed, w, t in [(4000, 1.004e-3, 8.0), (4000, 1.34e-3, 8.0), (12000, 1.004e-3, 8.0)]:
            case = crf450r(speed, "distorted").with_ring(width=w, tension=t)
            r = ringlube.run(case, output=Path(tmp) / "r.h5")
            with h5py.File(r.path) as f:
                c = f["cycle"]
                ca, h = c["crank_angle_deg"][:], c["sector_h0_m"][:]
                groove, flow = c["groove_pressure_Pa"][:], c["face_flow_kg_s"][:]
                off = (c["flags"][:] & 2) != 0  # bit 2: h0 at its ceiling (back_clearance)
            m = h.shape[1]
            spread = h.max(axis=1) / h.min(axis=1)
            dt = np.deg2rad(np.gradient(ca)) / (2 * np.pi * speed / 60)  # s per step
            leak = flow * dt * 1e6  # mg per step (towards the crankcase +; all sectors)
            for i, name in enumerate(strokes):
                k = np.nonzero((ca >= 180 * i) & (ca < 180 * (i + 1)))[0]
                j = k[np.argmax(spread[k])]
                pushed = ca[k[off[k]]]
                pushed = f"{pushed.min():.0f}-{pushed.max():.0f}" if len(pushed) else "-"
                print(
                    f"| {speed} | {w * 1e3:.3g} mm, {t:.0f} N | {name} | {spread[k].min():.2f} "
                    f"| {spread[j]:.2f} | {ca[j]:.0f} "
                    f"| {360 / m * np.argmax(h[j]):.0f} | {groove[j] / 1e5:.1f} | {pushed} "
                    f"| {leak[k].sum():.3g} |",
                    flush=True,
                )


def step_table():
    """The distorted decks against the crank step (the radial collapse and the sectors'
    lift-off are resolved one step at a time): the shipped ring at two tensions on each shipped
    distorted deck at 2, 1 and 0.5 deg."""
    header()
    decks = [
        ("CRF450R", 12000, crf450r(12000, "distorted"), (8.0, 14.0)),
        ("CRF450R", 4000, crf450r(4000, "distorted"), (8.0, 26.0)),
        ("86 x 86", 3000, own("distorted"), (8.0, 26.0)),
    ]
    for engine, speed, base, tensions in decks:
        w = base.value("ring", "width")
        for t in tensions:
            for dpsi in (2.0, 1.0, 0.5):
                case = base.with_ring(width=w, tension=t).with_numerics(dpsi_deg=dpsi)
                name = f"{w * 1e3:.3g} mm, {t:.0f} N, {dpsi:g} deg"
                print(row(engine, speed, "distorted", name, case), flush=True)


def rings_table():
    """Narrow and wide, 8 and 26 N, round and distorted: CRF450R at 4000 and 12,000 r/min."""
    header()
    rings = [(w, t) for w in (0.54e-3, 1.34e-3) for t in (8.0, 26.0)]
    for speed in (4000, 12000):
        for bore in ("round", "distorted"):
            base = crf450r(speed, bore)
            for w, t in [(1.004e-3, 8.0)] + rings:
                name = f"{w * 1e3:.3g} mm, {t:.0f} N"
                print(row("CRF450R", speed, bore, name, base.with_ring(width=w, tension=t)), flush=True)


def tension_table():
    """The tension swept on the distorted bore at the study's optimum width (1.004 mm)."""
    header()
    for speed in (4000, 12000):
        base = crf450r(speed, "distorted")
        for t in (8.0, 11.0, 14.0, 18.0, 22.0, 26.0):
            ring = f"1 mm, {t:.0f} N"
            print(row("CRF450R", speed, "distorted", ring, base.with_ring(tension=t)), flush=True)


def own_table():
    """The own engine: its 1.2 mm, 15 N ring, 8 and 26 N, a 0.8 and a 1.5 mm ring."""
    header()
    for bore in ("round", "distorted"):
        base = own(bore)
        for w, t in OWN_RINGS:
            name = f"{w * 1e3:.3g} mm, {t:.0f} N"
            print(row("86 x 86", 3000, bore, name, base.with_ring(width=w, tension=t)), flush=True)


#: the tables, by the name --part takes
TABLES = {
    "limits": limits_table,
    "cycle": cycle_table,
    "step": step_table,
    "rings": rings_table,
    "tension": tension_table,
    "own": own_table,
}

if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--part", choices=tuple(TABLES), action="append", help="one table (repeatable)")
    parser.add_argument("--times", action="store_true", help="each run's wall time after its row")
    args = parser.parse_args()
    TIMES = args.times
    for part in args.part or TABLES:
        TABLES[part]()
        print()
