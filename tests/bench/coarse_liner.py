"""Benchmark (not a test): how far a starved liner film run at a coarser crank step lies from
the crank step's own, against how far the first cycle after the warm-up moves it (why the ring
pack's pilot cycle, ``&numerics pilot_cycle``, is not run with a starved inlet: a coarse
film is no better first guess than the warm-up's).

The shipped case decks without a distorted bore, starved (``cavitation = 'jfo'``, ``inlet =
'starved'``), read in N: each at its own crank step and at 2 and 4 times it, run to
``cycle_tol`` 1e-5 (``max_cycles`` 30); the L1 difference of the liner film from the crank
step's, relative to its L1 norm, and the liner change of the first cycle at the deck's own
numerics (``liner_change`` with ``max_cycles`` 1). Run from the project folder:

    .venv/bin/python tests/bench/coarse_liner.py [--decks 12000,...]
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

import ringlube

ROOT = Path(__file__).resolve().parents[2]


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--decks", default="", help="deck name parts, comma-separated (default all)")
    args = ap.parse_args()
    parts = [d for d in args.decks.split(",") if d]
    decks = [
        p
        for p in sorted((ROOT / "inputs").glob("*.nml"))
        if "&study" not in p.read_text()
        and not p.name.startswith(("calibration", "_"))
        and "distorted" not in p.name
    ]
    print(f"{'deck':34s} {'2x step':>8s} {'4x step':>8s} {'first cycle':>12s}")
    for deck in decks:
        if parts and not any(d in deck.name for d in parts):
            continue
        case = ringlube.Case.from_namelist(deck).with_physics(cavitation="jfo", inlet="starved")
        step = case.value("numerics", "dpsi_deg")
        films = {}
        for s in (1, 2, 4):
            r = ringlube.run(case.with_numerics(dpsi_deg=s * step, cycle_tol=1e-5, max_cycles=30))
            films[s] = r.liner["liner_oil_film"]
        first = ringlube.run(case.with_numerics(max_cycles=1)).scalars["liner_change"]
        d = [np.abs(films[s] - films[1]).sum() / np.abs(films[1]).sum() for s in (2, 4)]
        print(f"{deck.stem:34s} {d[0]:8.2%} {d[1]:8.2%} {first:12.2%}", flush=True)


if __name__ == "__main__":
    main()
