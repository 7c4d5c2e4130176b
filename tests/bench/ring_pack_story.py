"""The ring pack's story for a ring engineer (not a test; docs/ring_pack.md quotes its table):
the study's optimum ring against the narrowest and widest rings and the lowest and highest
tension of the study's ranges, at 4000 r/min and at the CRF450R's rev limit (12,000 r/min), on
the shipped cold deck with `ring_pack = 'gas'` (Swift-Stieber film, the shipped calibration;
the 4000 r/min full-load trace at both speeds: the synthetic trace is in crank angle and has
no heat transfer, so it does not change with speed). Run from the project folder:

    .venv/bin/python tests/bench/ring_pack_story.py
"""

from pathlib import Path

import ringlube

ROOT = Path(__file__).resolve().parents[2]
base = ringlube.Case.from_namelist(ROOT / "inputs" / "crf450r_4000rpm_full_cold.nml").with_physics(
    ring_pack="gas"
)
rings = {
    "study optimum (1.004 mm, 8 N)": {},
    "narrowest (0.54 mm)": {"width": 0.54e-3},
    "widest (1.34 mm)": {"width": 1.34e-3},
    "26 N tension": {"tension": 26.0},
}
print(
    "| speed | ring | energy [J/cycle] | friction power [W] | blowby [L/min] "
    "| ring lift [% of cycle] | flutter events | converged |"
)
print("|---|---|---|---|---|---|---|---|")
for speed in (4000, 12000):
    for name, ring in rings.items():
        r = ringlube.run(base.with_operating(speed_rpm=speed).with_ring(**ring))
        print(
            f"| {speed} | {name} | {r.energy_loss:.3f} | {r.friction_power:.1f} | {r.blowby:.2f} | "
            f"{r.ring_lift_share:.1f} | {r.flutter_events:.0f} | {'yes' if r.converged else 'no'} |"
        )
