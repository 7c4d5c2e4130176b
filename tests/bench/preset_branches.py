"""Benchmark (not a test): which branch the 'default' preset takes, against 'accurate', for the
mass-conserving film models with and without the ring pack's gas (docs/performance.md,
"Step-size bistability"), and, with ``--candidates``, the energy error of other node / crank
step settings against 'accurate' (per-model preset candidates). ``--per-length``: the decks with
the tension read in N/m and that reading's calibration (``inputs/calibration_n_per_m.nml``), the
reading whose intake stroke sits at the lift-off threshold. Run from the project folder:

    .venv/bin/python tests/bench/preset_branches.py [--candidates] [--per-length]
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import ringlube
from ringlube import Case

ROOT = Path(__file__).resolve().parents[2]
DECKS = {
    "cold": "crf450r_4000rpm_full_cold.nml",
    "hot": "crf450r_4000rpm_full_hot.nml",
    "half_cold": "crf450r_3000rpm_half_cold.nml",
    "half_hot": "crf450r_3000rpm_half_hot.nml",
}
MODELS = {
    "flooded, trailing_gas": {"cavitation": "jfo", "cavity_pressure": "trailing_gas"},
    "starved": {"cavitation": "jfo", "inlet": "starved"},
}


def deck_case(name: str) -> Case:
    """A shipped deck, read in N/m with its calibration when ``--per-length`` is given."""
    case = Case.from_namelist(ROOT / "inputs" / name)
    if "--per-length" in sys.argv[1:]:
        case = case.with_ring(tension_unit="N/m").with_("calibration", file="calibration_n_per_m.nml")
    return case


def branches() -> None:
    """'default' against 'accurate' on the 4000 r/min decks, ring pack 'none' and 'gas'."""
    for deck in ("cold", "hot"):
        for label, physics in MODELS.items():
            for ring_pack in ("none", "gas"):
                case = deck_case(DECKS[deck]).with_physics(ring_pack=ring_pack, **physics)
                d, a = (ringlube.run(case.with_numerics(preset=p)) for p in ("default", "accurate"))
                print(
                    f"{deck:4s} {label:22s} {ring_pack:4s} default {d.energy_loss:.4f} J "
                    f"accurate {a.energy_loss:.4f} J ({100 * (d.energy_loss / a.energy_loss - 1):+.1f} %), "
                    f"lifted {d.liner_lift_share:.1f} / {a.liner_lift_share:.1f} %, "
                    f"converged {d.converged} / {a.converged}",
                    flush=True,
                )


def candidates() -> None:
    """Energy error of (nodes, dpsi_deg) settings against 'accurate', ring pack 'none'."""
    for label, physics in MODELS.items():
        for deck, name in DECKS.items():
            case = deck_case(name).with_physics(**physics)
            ref = ringlube.run(case.with_numerics(preset="accurate"))
            cells = []
            for nodes, dpsi in ((51, 2.0), (51, 1.0), (51, 0.5), (101, 1.0), (101, 0.5)):
                t = time.perf_counter()
                r = ringlube.run(case.with_numerics(nodes=nodes, dpsi_deg=dpsi))
                ms = 1e3 * (time.perf_counter() - t)
                err = 100 * (r.energy_loss / ref.energy_loss - 1)
                cells.append(f"{nodes}/{dpsi:g}: {err:+.2f} % {ms:.0f} ms{'' if r.converged else ' NC'}")
            print(
                f"{label:22s} {deck:9s} accurate {ref.energy_loss:.4f} J | " + " | ".join(cells), flush=True
            )


if __name__ == "__main__":
    candidates() if "--candidates" in sys.argv[1:] else branches()
