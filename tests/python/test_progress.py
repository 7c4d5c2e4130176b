"""Progress of a long run: `ringlube-solve` and `ringlube run` say on the terminal (standard
error) which cycle and crank angle a run of more than a few seconds is at and about how long the
cycle has left; nothing with -q, nothing into a pipe or a file, nothing from the Python API.
Each run here would take minutes (starved, 'accurate', up to 1000 cycles to 1e-14); the tests
wait for a signal from the process (its line, or its own CPU time past the 2 s after which a
line would show), then stop it with Ctrl-C."""

from __future__ import annotations

import os
import pty
import re
import select
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from conftest import COLD, INPUTS

pytestmark = pytest.mark.cli

#: the kernel's delay before its first progress line [s] (fsys.c, progress_after)
AFTER = 2.0
LINE = re.compile(r"ringlube: (warm-up|cycle \d+ \(at most 1000\)), crank angle \d+\.\d deg, .*\d+ s so far")


def _long_deck(tmp_path: Path) -> Path:
    deck = tmp_path / "long.nml"
    text = COLD.read_text().replace("'pressure/", f"'{INPUTS}/pressure/")
    text = text.replace("calibration.nml", str(INPUTS / "calibration.nml"))
    text = text.replace("&physics ", "&physics cavitation = 'jfo', inlet = 'starved', ")
    text = re.sub(r"max_cycles = \d+", "max_cycles = 1000", text)
    text = re.sub(r"cycle_tol = [0-9.e-]+", "cycle_tol = 1e-14", text)
    deck.write_text(text.replace("preset = 'default'", "preset = 'accurate'"))
    return deck


def _commands(solver: str, deck: Path, tmp_path: Path, quiet: bool) -> dict[str, list[str]]:
    q = ["-q"] if quiet else []
    cli = [sys.executable, "-m", "ringlube.cli", "run"]
    return {
        "ringlube-solve": [solver, str(deck), *q, "-o", str(tmp_path / "solve.h5")],
        "ringlube run": [*cli, str(deck), *q, "-o", str(tmp_path / "run.h5")],
    }


def _start(cmd: list[str], stderr) -> subprocess.Popen:
    # (SIGINT as an interactive shell leaves it: a runner started in the background may have
    # it ignored, which the child would inherit)
    return subprocess.Popen(
        cmd,
        stdin=subprocess.DEVNULL,
        stdout=subprocess.DEVNULL,
        stderr=stderr,
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
    )


def _cpu_seconds(pid: int) -> float:
    """CPU time (user + system) a process has used, from /proc."""
    fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def _read(fd: int, wait: float) -> bytes:
    """What the terminal `fd` received within `wait` seconds (b'' once its other end closed)."""
    ready, _, _ = select.select([fd], [], [], wait)
    if not ready:
        return b""
    try:
        return os.read(fd, 65536)
    except OSError:  # the process ended and closed the terminal
        return b""


def _stop(proc: subprocess.Popen) -> None:
    if proc.poll() is None:
        proc.send_signal(signal.SIGINT)
    try:
        proc.wait(timeout=60)
    finally:
        if proc.poll() is None:
            proc.kill()


def test_a_long_run_shows_where_it_is_on_the_terminal(solver, tmp_path):
    """Both front ends: a line naming the warm-up or the cycle (of at most max_cycles), the
    crank angle and the time so far, rewritten in place (carriage returns, no new lines), once
    the run has lasted 2 s; Ctrl-C then ends the run as before (exit 130, or the signal for
    ringlube-solve, which does not catch it), the line ended so that the prompt starts on its
    own line."""
    deck = _long_deck(tmp_path)
    for name, cmd in _commands(solver, deck, tmp_path, quiet=False).items():
        master, slave = pty.openpty()
        proc = _start(cmd, slave)
        os.close(slave)
        seen = b""
        try:
            # (a failure: the process has computed for 20 s, its line due after 2 s of its run)
            while not LINE.search(seen.decode(errors="replace")) and _cpu_seconds(proc.pid) < 20.0:
                assert proc.poll() is None, (name, seen)
                seen += _read(master, 0.2)
            assert LINE.search(seen.decode(errors="replace")), (name, seen)
        finally:
            _stop(proc)
            seen += _read(master, 1.0)
            os.close(master)
        text = seen.decode(errors="replace")
        assert text.startswith("\r"), (name, text)
        assert proc.returncode in (130, -signal.SIGINT), (name, proc.returncode, text)
        assert "Traceback" not in text, (name, text)


def test_quiet_piped_and_api_runs_show_no_progress(solver, tmp_path):
    """No line with -q (both front ends, on a terminal), none into a pipe (ringlube-solve
    without -q: a log file would fill with carriage returns), none from `ringlube.run` in a
    program (a library prints nothing of its own): each process is stopped once its run has
    lasted past the 2 s after which a line would show and it has computed crank steps since
    (its own CPU time, however loaded the machine)."""
    deck = _long_deck(tmp_path)
    api = "import sys, ringlube\nringlube.run(ringlube.Case.from_namelist(sys.argv[1]))\n"
    terminals = {}
    procs = {}
    for name, cmd in _commands(solver, deck, tmp_path, quiet=True).items():
        master, slave = pty.openpty()
        procs[f"{name} -q"] = _start(cmd, slave)
        os.close(slave)
        terminals[f"{name} -q"] = master
    master, slave = pty.openpty()
    procs["ringlube.run"] = _start([sys.executable, "-c", api, str(deck)], slave)
    os.close(slave)
    terminals["ringlube.run"] = master
    procs["ringlube-solve into a pipe"] = _start(
        _commands(solver, deck, tmp_path, quiet=False)["ringlube-solve"], subprocess.PIPE
    )
    seen = {name: b"" for name in procs}
    under_way: dict[str, tuple[float, float]] = {}  # name: (wall time, CPU time) in the run
    try:
        busy = set(procs)
        while busy:
            for name in list(busy):
                proc = procs[name]
                assert proc.poll() is None, name
                cpu = _cpu_seconds(proc.pid)
                if name not in under_way:
                    # in the run: computed 0.2 s past loading the kernel (Python's imports
                    # take CPU time too; ringlube-solve reads its deck in milliseconds)
                    python = proc.args[0] == sys.executable
                    if python and "_kernel." not in Path(f"/proc/{proc.pid}/maps").read_text():
                        continue
                    under_way[name] = (time.monotonic(), cpu + 0.2)
                wall0, cpu0 = under_way[name]
                # past the delay of a line, and computing crank steps after it
                if cpu >= cpu0 and time.monotonic() - wall0 > AFTER + 1.0 and cpu > cpu0 + 0.2:
                    busy.discard(name)
            for name, fd in terminals.items():
                seen[name] += _read(fd, 0.0)
            time.sleep(0.05)  # polling a condition, not a delay standing in for one
        for name, fd in terminals.items():
            seen[name] += _read(fd, 0.0)
    finally:
        for proc in procs.values():
            _stop(proc)
        for name, fd in terminals.items():
            seen[name] += _read(fd, 0.5)
            os.close(fd)
    seen["ringlube-solve into a pipe"] = procs["ringlube-solve into a pipe"].stderr.read()
    for name, text in seen.items():
        assert b"crank angle" not in text, (name, text)
