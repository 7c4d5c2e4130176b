"""Each speed lever of the kernel measured alone (benchmark, not a test; part of `make bench`).

Builds ``bench_kernel`` from this checkout (git HEAD, exported to a temporary folder) with
one lever taken out at a time, and from the commit before those levers (c27aa15), then times
the cold deck (CPU time, best of --repeats) at fixed numerics, so that the implementation
levers are compared at equal work; then the numerics levers (time scheme, crank step,
warm-up) on the current build.

    python3 tests/bench/levers.py [--repeats 20] [--rounds 3] [--base c27aa15]
"""

from __future__ import annotations

import argparse
import os
import re
import subprocess
import tempfile
from pathlib import Path

from front import bench  # the bench_kernel call and its parsing, one copy

ROOT = Path(__file__).resolve().parents[2]
DECK = ROOT / "inputs" / "crf450r_4000rpm_full_cold.nml"
OLD_NUMERICS = "nodes=51 dpsi_deg=1.0 pressure_tol=1e-5 load_tol=1e-3 warmup_deg=360"

# (name, file, old text, new text): one lever taken out of the current code
ABLATIONS = {
    "viscosity loop stopped by pressure_tol only (no load criterion)": [
        ("fortran/src/film.f90", "      if (dvisc * abs(f%wh) <= 0.1_dp * w_tol) exit\n", "")
    ],
    "linear h0 predictor (as before) instead of quadratic": [
        (
            "fortran/src/load_balance.f90",
            "    case (3)\n      extrapolate = 3.0_dp * v(1) - 3.0_dp * v(2) + v(3)\n",
            "    case (3)\n      extrapolate = 2.0_dp * v(1) - v(2)\n",
        )
    ],
    "slope from the last two trials of any step, secant 50 % past the root (as before)": [
        (
            "fortran/src/load_balance.f90",
            "if (mem%trials >= 2 .and. mem%y_hist(1) /= mem%y_hist(2)) then",
            "if (mem%y_hist(1) /= mem%y_hist(2)) then",
        ),
        (
            "fortran/src/load_balance.f90",
            "        dy = sign(1.02_dp * abs(gb * (yb - ya) / (gb - ga)), dy)\n",
            "        dy = sign(max(1.5_dp * abs(gb * (yb - ya) / (gb - ga)), 2.0_dp * abs(yb - ya)), dy)\n",
        ),
    ],
    "Reynolds scratch allocated at every solve (as the automatic arrays before)": [
        (
            "fortran/src/film.f90",
            "        f%active, iters, info, f%work)\n",
            "        f%active, iters, info)\n",
        )
    ],
    "Roelands at every node (also where the pressure did not change)": [
        ("fortran/src/film.f90", "        if (f%p(i) /= f%pold(i)) then\n", "        if (.true.) then\n")
    ],
    "-O2 instead of -O3": [],
}


def build(src: Path, flags: str | None = None) -> Path:
    b = src / "build"
    cmd = ["cmake", "-S", str(src), "-B", str(b), "-G", "Ninja", "-DCMAKE_BUILD_TYPE=Release"]
    if flags:
        cmd.append(f"-DRINGLUBE_RELEASE_FLAGS={flags}")
    subprocess.run(cmd, check=True, capture_output=True)
    subprocess.run(["cmake", "--build", str(b), "--target", "bench_kernel"], check=True, capture_output=True)
    return b / "bench_kernel"


def export(commit: str, dest: Path) -> Path:
    dest.mkdir(parents=True)
    archive = subprocess.run(
        ["git", "-C", str(ROOT), "archive", commit], check=True, capture_output=True
    ).stdout
    subprocess.run(["tar", "-x", "-C", str(dest)], input=archive, check=True)
    return dest


def time_run(exe: Path, numerics: str, repeats: int) -> dict:
    return bench(DECK, numerics, repeats, exe)


def line(name: str, r: dict) -> str:
    return (
        f"{name:82s} {r['ms_per_run']:7.2f} ms/run {r['ms_per_cycle']:6.2f} ms/cycle "
        f"{int(r['film_solves']):6d} film {int(r['reynolds_solves']):6d} Reynolds  "
        f"E {r['energy']:.5f} J"
    )


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeats", type=int, default=20)
    ap.add_argument("--rounds", type=int, default=3, help="interleaved rounds (best is kept)")
    ap.add_argument("--base", default="c27aa15", help="commit before the levers")
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        exes = {}
        base = export(args.base, tmp / "base")
        bench_src = (ROOT / "tests/bench/bench_kernel.f90").read_text()
        # the base kernel's film_evaluate had no load tolerance argument
        (base / "tests/bench").mkdir(exist_ok=True)
        base_src, n = re.subn(
            r"2e5_dp,\s*&\s*c%load_tol \* \(elastic_pressure\(c\) \+ 2e5_dp\) \* c%width \* f%circ\)",
            "2e5_dp)",
            bench_src,
        )
        if n != 1:
            raise SystemExit("levers.py: the film_evaluate call of bench_kernel.f90 has changed")
        (base / "tests/bench/bench_kernel.f90").write_text(base_src)
        with open(base / "tests/fortran/tests.cmake", "a") as f:
            f.write(
                "\nadd_executable(bench_kernel ${CMAKE_CURRENT_LIST_DIR}/../bench/bench_kernel.f90)\n"
                "target_link_libraries(bench_kernel PRIVATE ringlube_kernel)\n"
            )
        exes["before the levers (" + args.base + ", -O2)"] = build(base)
        head = export("HEAD", tmp / "head")
        exes["now (HEAD)"] = build(head)
        for i, (name, edits) in enumerate(ABLATIONS.items()):
            src = export("HEAD", tmp / f"abl{i}")
            for file, old, new in edits:
                text = (src / file).read_text()
                assert old in text, (name, old)
                (src / file).write_text(text.replace(old, new))
            exes["now without: " + name] = build(src, "-O2" if name.startswith("-O2") else None)

        print(
            f"cold deck, fixed numerics ({OLD_NUMERICS}, backward Euler where the build has "
            f"time_scheme), CPU time best of {args.repeats} runs, best of {args.rounds} "
            f"interleaved rounds; load average {os.getloadavg()[0]:.1f}"
        )
        best: dict[str, dict] = {}
        for _ in range(args.rounds):
            for name, exe in exes.items():
                num = OLD_NUMERICS + ("" if name.startswith("before") else " time_scheme='euler'")
                r = time_run(exe, num, args.repeats)
                if name not in best or r["ms_per_run"] < best[name]["ms_per_run"]:
                    best[name] = r
        for name, r in best.items():
            print(line(name, r))

        now = exes["now (HEAD)"]
        print("\nnumerics levers on the current build (cold deck)")
        best = {}
        numerics = [
            ("backward Euler, 1 deg, warm-up 360 deg", OLD_NUMERICS + " time_scheme='euler'"),
            ("BDF2, 1 deg, warm-up 360 deg", OLD_NUMERICS + " time_scheme='bdf2'"),
            (
                "BDF2, 2 deg, warm-up 360 deg",
                OLD_NUMERICS.replace("dpsi_deg=1.0", "dpsi_deg=2.0") + " time_scheme='bdf2'",
            ),
            ("BDF2, 2 deg, warm-up 90 deg (preset 'default' now)", "preset='default'"),
        ]
        for _ in range(args.rounds):
            for name, num in numerics:
                r = time_run(now, num, args.repeats)
                if name not in best or r["ms_per_run"] < best[name]["ms_per_run"]:
                    best[name] = r
        for name, r in best.items():
            print(line(name, r))


if __name__ == "__main__":
    main()
