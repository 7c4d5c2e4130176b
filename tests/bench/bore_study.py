"""Not a test: the answer of a finished bore study (``ringlube optimise inputs/study_bore.nml``)
in numbers, and the tension trade behind it, for docs/bore.md ("In a study").

1. From the study file: per case the samples that converged (and every sample's blowby and
   share of the cycle off the liner, by width), the candidates re-simulated with
   the true model and why those that are not good are not, the chosen designs and the
   reference with their energy, blowby, oil to the chamber and light gaps (true model).
2. The tension trade: each case's chosen knee (its width and crown) run on its base deck at
   tensions 8, 12.5, 17, 21.5 and 26 N (the study's range), with the same results, the face
   leakage, the share of the cycle pushed off the liner, whether it converged, the cycles it
   ran and the kernel's wall time (``run_time``, s: on a loaded machine more than its CPU time); and at
   12,000 r/min a 0.75 mm ring (crown 9.31 um), from the band of widths where the study's
   samples seal at high tension and are pushed off the liner at low tension.
3. When and where the gaps open over the cycle in those runs: the crank-angle windows where
   the largest sector film/gap is over 4 times the smallest (the criterion of
   `ctest -R bore/gas_assisted_conformability`), the sectors over 4 times the smallest there
   (angle around the bore), and the windows where gas passes the faces (``face_flow`` > 0).

    .venv/bin/python tests/bench/bore_study.py OUT/crf450r_bore.h5 [--workers 2]

Runs 15 true-model cycles (about 2-3 min of CPU time) besides reading the file.
"""

from __future__ import annotations

import argparse
import json
import os
import time

import h5py
import numpy as np

from ringlube.case import Case
from ringlube.solve import run_many

TENSIONS = (8.0, 12.5, 17.0, 21.5, 26.0)
OBJECTIVES = ("energy_loss", "blowby", "oil_to_chamber", "light_gap_share")
OPEN_RATIO = 4.0
#: A ring of the band of widths (about 0.63-0.86 mm) where the 12,000 r/min samples of the
#: shipped study are sealed at high tension and pushed off the liner at low tension, with the
#: reference ring's crown.
BAND_WIDTH, BAND_CROWN = 0.75e-3, 9.31e-6


def _text(v) -> str:
    return v.decode() if isinstance(v, bytes) else str(v)


def _row(name, x, f, cols, conv) -> str:
    vals = [f[0, cols.index(o)] if f.ndim == 2 else f[cols.index(o)] for o in OBJECTIVES]
    lift = f[cols.index("liner_lift_share")]
    return (
        f"| {name} | {x[0] * 1e3:.3f} | {x[1]:.1f} | {x[2] * 1e6:.2f} | {vals[0]:.3f} | {vals[1]:.2f} "
        f"| {vals[2]:.3f} | {vals[3]:.2f} | {lift:.2f} | {'yes' if conv else 'no'} |"
    )


HEAD = (
    "| design | width mm | tension N | crown um | energy J | blowby L/min | oil mm3 | light gaps % "
    "| off the liner % | converged |\n|---|---|---|---|---|---|---|---|---|---|"
)


def study_tables(path: str) -> dict[str, tuple[np.ndarray, str]]:
    """Print the study file's counts and chosen designs; return each case's knee and deck."""
    knees = {}
    with h5py.File(path, "r") as f:
        settings = json.loads(_text(f.attrs["settings"]))
        stages, kernel = _text(f.attrs["stages"]), _text(f.attrs["kernel_id"])
        print(f"study {settings['name']}: stages {stages}, kernel {kernel}")
        for label, deck in zip(settings["labels"], settings["cases"]):
            g = f["cases"][label]
            cols = [_text(c) for c in g["chosen/f_true"].attrs["columns"]]
            runs = g["runs"]
            print(f"\n## {label} ({os.path.basename(deck)})\n")
            print(
                f"samples converged: {int(runs['converged'][()].sum())} of {len(runs['converged'])}, "
                f"failed {int(runs['failed'][()].sum())}"
            )
            fit = {o: g[f"surface/{o}"].attrs for o in OBJECTIVES}
            fits = ", ".join(
                f"{o} R^2 {a['r2']:.2f} (cross-validated error {a['cv_rel']:.0%})" for o, a in fit.items()
            )
            print(f"surfaces: {fits}")
            cand = g["candidates"]
            ft, conv = cand["f_true"][()], cand["converged"][()].astype(bool)
            lifted = ft[:, cols.index("liner_lift_share")] > 0
            good = int((conv & ~lifted).sum())
            print(
                f"candidates re-simulated: {len(conv)}; converged and on the liner {good}, "
                f"not converged {int((~conv).sum())}, off the liner {int(lifted.sum())} "
                f"(both {int((~conv & lifted).sum())})"
            )
            print("\n" + HEAD)
            ch = g["chosen"]
            for n, x, fr, c in zip(ch["names"][()], ch["x"][()], ch["f_true"][()], ch["converged"][()]):
                print(_row(_text(n), x, fr, cols, c))
            ref = g["reference"]
            print(_row("reference", ref["x"][0], ref["f_true"][0], cols, ref["converged"][0]))
            x, out = f["samples/x"][()], runs["outputs"][()]
            print(
                "\nsamples by width (width mm / tension N: blowby L/min, off the liner %, '*' not converged):"
            )
            print(
                "; ".join(
                    f"{x[i, 0] * 1e3:.3f}/{x[i, 1]:.1f}: {out[i, cols.index('blowby')]:.1f}, "
                    f"{out[i, cols.index('liner_lift_share')]:.2f}{'' if runs['converged'][i] else '*'}"
                    for i in np.argsort(x[:, 0])
                )
            )
            names = [_text(n) for n in ch["names"][()]]
            knees[label] = (ch["x"][()][names.index("knee")], deck)
    return knees


def windows(mask: np.ndarray, psi: np.ndarray) -> str:
    """Crank-angle windows (consecutive steps) where ``mask`` holds, as 'a-b deg' ranges."""
    ks = np.flatnonzero(mask)
    if not len(ks):
        return "none"
    runs, start = [], ks[0]
    for a, b in zip(ks[:-1], ks[1:]):
        if b != a + 1:
            runs.append((start, a))
            start = b
    runs.append((start, ks[-1]))
    return ", ".join(f"{psi[a]:.0f}" if a == b else f"{psi[a]:.0f}-{psi[b]:.0f}" for a, b in runs) + " deg"


def sweep(knees: dict, workers: int) -> None:
    rings = [(label, x, deck) for label, (x, deck) in knees.items()]
    if "r12000" in knees:  # the band of widths where tension decides whether the ring seals
        rings.append(("r12000", np.array([BAND_WIDTH, 0.0, BAND_CROWN]), knees["r12000"][1]))
    cases, keys = [], []
    for label, x, deck in rings:
        base = Case.from_namelist(deck)
        for t in TENSIONS:
            cases.append(base.with_("ring", width=float(x[0]), tension=t, crown_height=float(x[2])))
            keys.append((label, x, t))
    t0 = time.perf_counter()
    results = run_many(cases, workers=workers, progress=False)
    wall, load = time.perf_counter() - t0, os.getloadavg()[0]
    print(f"\n(the tension sweeps: {len(cases)} runs, {wall:.0f} s wall, load average {load:.1f})")
    last = None
    for (label, x, t), r in zip(keys, results):
        if (label, x[0]) != last:
            print(f"\n## {label}: width {x[0] * 1e3:.3f} mm and crown {x[2] * 1e6:.2f} um over the tension\n")
            print(
                "| tension N | energy J | blowby L/min | oil mm3 | light gaps % | face leakage mg "
                "| off the liner % | conformability | converged | cycles | kernel wall s |"
                "\n|---|---|---|---|---|---|---|---|---|---|---|"
            )
            last = (label, x[0])
        print(
            f"| {t:.1f} | {r.energy_loss:.3f} | {r.blowby:.2f} | {r.oil_to_chamber:.3f} "
            f"| {r.light_gap_share:.2f} | {r.face_leakage:.3f} | {r.liner_lift_share:.2f} "
            f"| {r.conformability:.2f} | {'yes' if r.converged else 'no'} | {r.cycles_run:.0f} "
            f"| {r.run_time:.1f} |"
        )
    for (label, x, t), r in zip(keys, results):
        h, psi, theta = r.sector_h0, r.crank_angle_deg, r.sector_angle_deg
        ratio = h.max(axis=1) / h.min(axis=1)
        open_ = ratio > OPEN_RATIO
        where = sorted(
            {
                float(theta[j])
                for k in np.flatnonzero(open_)
                for j in np.flatnonzero(h[k] > OPEN_RATIO * h[k].min())
            }
        )
        print(
            f"\n{label} {x[0] * 1e3:.3f} mm {t:.1f} N: largest gap over {OPEN_RATIO:g} x the smallest at "
            f"{windows(open_, psi)}"
            f" (largest ratio {ratio.max():.1f} at {psi[int(np.argmax(ratio))]:.0f} deg); sectors there: "
            f"{', '.join(f'{a:.0f}' for a in where) or 'none'} deg around the bore; gas through the faces at "
            f"{windows(np.asarray(r.face_flow) > 0, psi)}"
        )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("study", help="the finished study file (OUT/crf450r_bore.h5)")
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--no-sweep", action="store_true", help="only the study file's tables")
    a = ap.parse_args()
    knees = study_tables(a.study)
    if not a.no_sweep:
        sweep(knees, a.workers)


if __name__ == "__main__":
    main()
