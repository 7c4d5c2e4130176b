"""Benchmark (not a test): the flutter margin against the count of flutter events over the
ring-pack study's design space. The designs are the study's own sample (inputs/study_ring_pack.nml:
Sobol, 64 samples, seed 1, width 0.54-1.34 mm, tension 8-26 N), each run with the true model on
the three shipped 'gas' decks; the table says how many designs flutter, whether the margin's sign
agrees with the count, the margin's range within each count, and how many designs each
constraint against the reference ring (1.004 mm, 8 N) lets through.

    .venv/bin/python tests/bench/flutter_margin_study.py
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from scipy.stats import qmc

import ringlube

INPUTS = Path(__file__).resolve().parents[2] / "inputs"
LOWER, UPPER = [0.54e-3, 8.0], [1.34e-3, 26.0]
REFERENCE = {"width": 1.004e-3, "tension": 8.0}
OUT = ["flutter_events", "flutter_margin", "flutter_margin_ratio"]


def main() -> None:
    x = qmc.scale(qmc.Sobol(2, seed=1).random(64), LOWER, UPPER)
    for rpm in (4000, 8000, 12000):
        base = ringlube.Case.from_namelist(INPUTS / f"crf450r_{rpm}rpm_full_hot_gas.nml")
        v, conv, _ = ringlube.run_designs(base, ["ring:width", "ring:tension"], x, OUT)
        ev, m = v[:, 0], v[:, 1]
        ref = ringlube.run(base.with_ring(**REFERENCE))
        print(
            f"{rpm} r/min: {conv.sum()}/64 converged; {int((ev > 0).sum())} designs flutter; "
            f"margin {m.min():.1f} .. {m.max():.1f} N; its sign agrees with the count: "
            f"{bool(np.all((m < 0) == (ev > 0)))}; reference: {ref.flutter_events:g} events, "
            f"margin {ref.flutter_margin:.1f} N"
        )
        for e in sorted(set(ev.tolist())):
            s = ev == e
            print(
                f"  {int(s.sum()):3d} designs with {e:g} events: margin {m[s].min():7.1f} .. "
                f"{m[s].max():7.1f} N, widths {x[s, 0].min() * 1e3:.2f}-{x[s, 0].max() * 1e3:.2f} mm"
            )
        print(
            f"  'flutter_events <= reference' lets {int((ev <= ref.flutter_events).sum())} through, "
            f"'flutter_margin >= reference' {int((m >= ref.flutter_margin).sum())}; correlation of "
            f"the margin with width {np.corrcoef(m, x[:, 0])[0, 1]:+.3f}, with tension "
            f"{np.corrcoef(m, x[:, 1])[0, 1]:+.3f}"
        )


if __name__ == "__main__":
    main()
