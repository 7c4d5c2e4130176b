"""Benchmark (not a test): the ring pack's cost, ms per computed cycle of ringlube-solve with
&physics ring_pack = 'none' and 'gas' on the 4000 r/min decks, Swift-Stieber, flooded and starved JFO
(best of 5; the kernel's own run_time_s / cycles_computed), and ms per run. A fresh process's one
run includes the kernel's one-time set-up (about 2.7 ms: tables built on first use), so the script
also prints the steady state of many runs in one process, as a study sees it (`build/bench_kernel
DECK OVERRIDES 20`, best of 3). Run from the project folder:

    .venv/bin/python tests/bench/ring_pack_cost.py [build/ringlube-solve]
"""

import re
import subprocess
import sys
import tempfile
from pathlib import Path

import h5py

ROOT = Path(__file__).resolve().parents[2]
S = sys.argv[1] if len(sys.argv) > 1 else str(ROOT / "build" / "ringlube-solve")
BENCH = str(Path(S).parent / "bench_kernel")


def steady_ms(deck: Path, physics: str) -> float:
    """Best of 3 of bench_kernel's ms per run (20 runs in one process) with &physics overrides."""
    best = float("inf")
    for _ in range(3):
        out = subprocess.run(
            [BENCH, str(deck), f"&physics {physics} /", "20"], capture_output=True, text=True, check=True
        ).stdout
        best = min(best, float(re.search(r"ms_per_run=\s*([0-9.]+)", out).group(1)))
    return best


tmp = Path(tempfile.mkdtemp())
for deck in ("4000rpm_full_cold", "4000rpm_full_hot"):
    for model, phys in (
        ("swift_stieber", ""),
        ("jfo flooded", "cavitation='jfo',"),
        ("jfo starved", "cavitation='jfo', inlet='starved',"),
    ):
        best = {}
        for rp in ("none", "gas"):
            txt = (ROOT / "inputs" / f"crf450r_{deck}.nml").read_text()
            txt = txt.replace("&physics", f"&physics {phys} ring_pack='{rp}',")
            txt = txt.replace("'calibration.nml'", repr(str(ROOT / "inputs" / "calibration.nml")))
            txt = txt.replace("'pressure/", "'" + str(ROOT / "inputs" / "pressure") + "/")
            (tmp / "c.nml").write_text(txt)
            ts, runs = [], []
            for _ in range(5):
                subprocess.run([S, str(tmp / "c.nml"), "-o", str(tmp / "c.h5"), "-q"], check=False)
                with h5py.File(tmp / "c.h5") as f:
                    ts.append(f.attrs["run_time_s"] / f.attrs["cycles_computed"] * 1e3)
                    runs.append(f.attrs["run_time_s"] * 1e3)
                    cyc = f.attrs["cycles_computed"]
            best[rp] = (min(ts), cyc, min(runs))
        deck_path = ROOT / "inputs" / f"crf450r_{deck}.nml"
        steady = {rp: steady_ms(deck_path, f"{phys} ring_pack='{rp}'") for rp in ("none", "gas")}
        print(
            f"{deck} {model}: steady state ms per run none {steady['none']:.2f} gas {steady['gas']:.2f} "
            f"ratio {steady['gas'] / steady['none']:.2f}",
            flush=True,
        )
        print(
            f"{deck} {model}: ms per cycle none {best['none'][0]:.2f} gas {best['gas'][0]:.2f} "
            f"ratio {best['gas'][0] / best['none'][0]:.2f}; cycles computed "
            f"{best['none'][1]:.2f} / {best['gas'][1]:.2f}; ms per run {best['none'][2]:.1f} / "
            f"{best['gas'][2]:.1f}, ratio {best['gas'][2] / best['none'][2]:.2f}",
            flush=True,
        )
