"""What a Ctrl-C does to the ``ringlube`` command at each moment of its start.

Sends SIGINT to ``ringlube run DECK`` after each delay and tallies how it ended: ``one line``
(``ringlube: interrupted``, exit 130: ringlube's handler, set by the package's first lines),
``killed`` (no output: the interpreter had not yet installed its handler), ``site`` (Python's
``Fatal Python error`` while its ``site`` module runs the environment's ``.pth`` files),
``script start``, ``import re`` or ``finding ringlube`` (a KeyboardInterrupt traceback from
pip's script, before its first line, in its ``import re``, or while it finds the package:
before any code of ringlube runs), ``other`` (anything else: printed in full, a defect). The
delays are wall time on a machine that may be loaded: the moments move with its load, which
is why this is a script and not a test.

Usage::

    .venv/bin/python tests/bench/ctrl_c_at_start.py [--repeats 3] [--command .venv/bin/ringlube]
"""

from __future__ import annotations

import argparse
import collections
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
DELAYS = (0.005, 0.01, 0.02, 0.03, 0.04, 0.05, 0.06, 0.08, 0.1, 0.15, 0.2, 0.3, 0.5)


def outcome(code: int, err: str) -> str:
    """How one interrupted start ended (see the module's description)."""
    if code == 130 and err == "ringlube: interrupted\n":
        return "one line"
    if code == -signal.SIGINT and not err:
        return "killed"
    if "Fatal Python error" in err:
        return "site"
    if "Traceback" in err and "line 0, in <module>" in err:
        return "script start"
    if "Traceback" in err and "import re" in err:
        return "import re"
    if "Traceback" in err and "from ringlube.cli import main" in err and err.count('File "') <= 4:
        return "finding ringlube"
    return "other"


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--command", default=str(ROOT / ".venv" / "bin" / "ringlube"))
    args = ap.parse_args()
    deck = ROOT / "inputs" / "crf450r_4000rpm_full_cold.nml"
    tally = collections.Counter()
    with tempfile.TemporaryDirectory() as tmp:
        for d in DELAYS:
            for _ in range(args.repeats):
                p = subprocess.Popen(
                    [args.command, "run", str(deck), "-q", "-o", str(Path(tmp) / "r.h5")],
                    stdout=subprocess.PIPE,
                    stderr=subprocess.PIPE,
                    text=True,
                    preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
                )
                time.sleep(d)  # (a benchmark's delay: the moment probed)
                p.send_signal(signal.SIGINT)
                _, err = p.communicate()
                how = outcome(p.returncode, err)
                tally[d, how] += 1
                if how == "other":
                    print(f"--- {d} s, exit {p.returncode}:\n{err}", file=sys.stderr)
    print(f"{'delay s':>8}  outcome            runs")
    for (d, how), n in sorted(tally.items()):
        print(f"{d:8.3f}  {how:17s}  {n}")
    return 1 if any(how == "other" for _, how in tally) else 0


if __name__ == "__main__":
    sys.exit(main())
