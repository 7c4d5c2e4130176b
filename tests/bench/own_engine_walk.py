"""docs/own_engine.md as written, timed (not a test; the page's timings, study numbers and overrun
check come from here). Run from the project folder:

    .venv/bin/python tests/bench/own_engine_walk.py [--keep DIR]

In an empty folder (a temporary one, or ``--keep DIR``, which must not exist) every fenced
block of the page is taken in order: a deck (first line ``! myengine/NAME: ...``) or a file
(```` ```csv ```` with first line ``# myengine/NAME: ...``) is written to its path, each line of
a ```` ```sh ```` block runs as its own process (``ringlube`` from this virtual environment, as
a user types it), a ```` ```python ```` block runs as ``python -c``. Nothing is shrunk: full
sizes, the study on a local Dask cluster (the command's default: one worker per core). Prints
the wall time of every step and the load average, then every step's output, the study report's
constraints, chosen designs and "How sure" section, the flutter margin of the page's ring on
its overrun deck against the width (0.8-1.5 mm), and whether every line of each
```` ```output ```` block of the page is in the output of the command block before it.
"""

from __future__ import annotations

import argparse
import os
import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
DOC = ROOT / "docs" / "own_engine.md"
BIN = Path(sys.executable).parent


def blocks() -> list[tuple[str, str]]:
    """(info string, text) of every fenced block of the page."""
    return re.findall(r"^```(\w*)\n(.*?)^```", DOC.read_text(encoding="utf-8"), flags=re.S | re.M)


def walk(folder: Path) -> None:
    env = {**os.environ, "PATH": f"{BIN}{os.pathsep}{os.environ.get('PATH', '')}"}
    steps, outputs, checks = [], [], []
    last = None  # output of the last command block
    load0 = os.getloadavg()
    t_all = time.perf_counter()
    for info, text in blocks():
        first = text.splitlines()[0] if text.strip() else ""
        m = re.match(r"[!#] (myengine/\S+): ", first)
        if m and info in ("", "csv"):
            path = folder / m.group(1)
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_text(text)
        elif info == "sh":
            last = ""
            for line in filter(None, map(str.strip, text.splitlines())):
                t0 = time.perf_counter()
                p = subprocess.run(line, shell=True, cwd=folder, env=env, capture_output=True, text=True)
                steps.append((line, time.perf_counter() - t0))
                if p.returncode:
                    raise SystemExit(f"{line}: exit {p.returncode}\n{p.stderr}")
                last += p.stdout
                outputs.append((line, p.stdout))
        elif info == "python":
            t0 = time.perf_counter()
            p = subprocess.run(
                [sys.executable, "-c", text], cwd=folder, env=env, capture_output=True, text=True
            )
            head = next(x for x in text.splitlines() if x.startswith(("case =", "overrun =")))
            steps.append((f"python: {head} ...", time.perf_counter() - t0))
            if p.returncode:
                raise SystemExit(f"python block: exit {p.returncode}\n{p.stderr}")
            last = p.stdout
            outputs.append(("python", p.stdout))
        elif info == "output":
            missing = [x for x in text.splitlines() if x.strip() and x.rstrip() not in (last or "")]
            checks.append((text.splitlines()[0], missing))
    total = time.perf_counter() - t_all
    load1 = os.getloadavg()

    print("| step | wall time s |\n|---|---|")
    for line, s in steps:
        print(f"| `{line}` | {s:.1f} |")
    print(f"| the whole walk | {total:.0f} |")
    print(
        f"\nload average (1 min) at the start {load0[0]:.1f}, at the end {load1[0]:.1f}; "
        f"{os.cpu_count()} cores"
    )
    for line, out in outputs:
        print(f"\n$ {line}\n{out}", end="")
    report = (folder / "myengine" / "study" / "report.md").read_text()
    for title in ("## Constraints", "## Chosen designs", "## How sure is this answer"):
        part = report[report.index(title) :]
        nxt = part.find("\n## ", 3)
        print("\n" + (part if nxt < 0 else part[:nxt]))
    overrun_sweep(folder)
    print("\noutput blocks of the page against the commands' output:")
    for first, missing in checks:
        print(f"  {first[:60]!r}: " + ("all lines found" if not missing else f"NOT FOUND: {missing}"))


def overrun_sweep(folder: Path) -> None:
    """The flutter margin of the page's ring on its overrun deck against the width (the
    drawing's barrel kept), with the number of lift events per cycle and the ring's mass."""
    import numpy as np

    import ringlube

    case = ringlube.Case.from_namelist(folder / "myengine" / "overrun.nml")
    widths = np.round(np.arange(0.8e-3, 1.5e-3 + 1e-9, 0.05e-3), 6)
    rs = ringlube.run_many([case.with_ring(width=float(w)) for w in widths], progress=False)
    print(
        "\noverrun deck, width swept:\n\n"
        "| width mm | flutter margin N | x peak inertia | flutter events | ring g |"
    )
    print("|---|---|---|---|---|")
    for w, r in zip(widths, rs):
        print(
            f"| {w * 1e3:.2f} | {r.flutter_margin:.1f} | {r.flutter_margin_ratio:+.2f} | "
            f"{r.flutter_events:g} | {r.ring_mass:.2f} |"
        )


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--keep", type=Path, help="walk in this new folder and keep it (default: a temporary one)")
    a = p.parse_args()
    if a.keep:
        a.keep.mkdir(parents=True)
        walk(a.keep.resolve())
    else:
        with tempfile.TemporaryDirectory() as tmp:
            walk(Path(tmp))


if __name__ == "__main__":
    main()
