"""The ``ringlube`` command under user mistakes: one line, exit 2 (input) or 1 (runtime),
never a traceback."""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import h5py
import pytest

import ringlube
from ringlube.cli import main

from conftest import COLD, INPUTS

pytestmark = pytest.mark.cli


@pytest.fixture(scope="module")
def result_file(tmp_path_factory):
    """A small result file (coarse numerics)."""
    d = tmp_path_factory.mktemp("res")
    deck = d / "q.nml"
    ringlube.Case.from_namelist(COLD).with_numerics(nodes=41, dpsi_deg=2.0).to_namelist(deck)
    out = d / "q.h5"
    assert main(["run", str(deck), "-o", str(out), "-q"]) == 0
    return deck, out


def study_deck(tmp_path, **extra) -> str:
    values = dict(
        name="'c'",
        cases=f"'{COLD}'",
        labels="'cold'",
        samples="24",
        population="8",
        generations="2",
        repeats="1",
    )
    values.update(extra)
    path = tmp_path / f"c{len(list(tmp_path.glob('c*.nml')))}.nml"
    path.write_text("&study\n" + "".join(f"  {k} = {v}\n" for k, v in values.items()) + "/\n")
    return str(path)


def _cases(tmp_path, result_file):
    deck, res = result_file
    folder = tmp_path / "folder"
    folder.mkdir()
    afile = tmp_path / "afile.txt"
    afile.write_text("x")
    truncated = tmp_path / "truncated.h5"
    truncated.write_bytes(res.read_bytes()[:2000])
    no_cycle = tmp_path / "other.h5"
    with h5py.File(no_cycle, "w") as f:
        f["x"] = 1.0
    corrupt = tmp_path / "corrupt"
    corrupt.mkdir()
    (corrupt / "c.h5").write_bytes(b"\x89HDF\r\n\x1a\n" + b"\0" * 100)
    sd = lambda **kw: study_deck(tmp_path, **kw)  # noqa: E731
    return {
        # (argv, exit code, a piece of the message)
        "run -o into a missing folder": (
            ["run", str(deck), "-o", str(tmp_path / "missing/x.h5")],
            2,
            "folder",
        ),
        "run -o onto a folder": (["run", str(deck), "-o", str(folder)], 2, "is a folder"),
        "run -o onto the deck": (["run", str(deck), "-o", str(deck)], 2, "is an input"),
        "run -o onto a device": (["run", str(deck), "-o", os.devnull], 2, "not a regular file"),
        "plot a missing file": (["plot", str(tmp_path / "nope.h5")], 2, "file not found"),
        "plot a text file": (["plot", str(afile)], 2, "not an HDF5 result"),
        "plot a deck": (["plot", str(deck)], 2, "not an HDF5 result"),
        "plot a truncated file": (["plot", str(truncated)], 2, "truncated.h5"),
        "plot an HDF5 file that is no result": (["plot", str(no_cycle)], 2, "other.h5"),
        "plot -o onto a file": (["plot", str(res), "-o", str(afile)], 2, "not a folder"),
        "plot --labels with a slash": (
            ["plot", str(res), "--labels", "a/b", "-o", str(tmp_path / "p")],
            2,
            "--labels",
        ),
        "optimise --out onto a file": (
            ["optimise", sd(), "--out", str(afile), "--serial"],
            2,
            "not a folder",
        ),
        "optimise a corrupt study file": (["optimise", sd(), "--out", str(corrupt), "--serial"], 2, "c.h5"),
        "samples = 'many'": (
            ["optimise", sd(samples="'many'"), "--serial"],
            2,
            "&study samples: must be a whole number, got 'many'",
        ),
        "samples = 64.5": (
            ["optimise", sd(samples="64.5"), "--serial"],
            2,
            "&study samples: must be a whole number, got 64.5",
        ),
        "samples = 1e8": (["optimise", sd(samples="1e8"), "--serial"], 2, "&study samples"),
        "samples = 100000000": (
            ["optimise", sd(samples="100000000"), "--serial"],
            2,
            "&study samples: must be at most 1,000,000",
        ),
        "folds = 0": (["optimise", sd(folds="0"), "--serial"], 2, "&study folds: must be at least 2"),
        "seed = -1": (["optimise", sd(seed="-1"), "--serial"], 2, "&study seed: must be at least 0"),
        "upper = nan": (
            ["optimise", sd(variables="'width'", lower="1e-3", upper="nan"), "--serial"],
            2,
            "&study upper: must be finite",
        ),
        "label with a slash": (
            ["optimise", sd(labels="'a/b'"), "--serial"],
            2,
            "&study labels: 'a/b' must be a plain name",
        ),
        "name with a slash": (
            ["optimise", sd(name="'x/y'"), "--serial"],
            2,
            "&study name: 'x/y' must be a plain name",
        ),
        "a missing study deck": (["optimise", str(tmp_path / "none.nml"), "--serial"], 2, "file not found"),
        "--workers -2": (["optimise", sd(), "--workers", "-2"], 2, "--workers"),
        "--workers 0": (["optimise", sd(), "--workers", "0"], 2, "--workers"),
        "--repeats x": (["convergence", str(deck), "--repeats", "x"], 2, "--repeats"),
        "convergence --out onto a file": (["convergence", str(deck), "--out", str(afile)], 2, "not a folder"),
    }


CASES = [
    "run -o into a missing folder",
    "run -o onto a folder",
    "run -o onto the deck",
    "run -o onto a device",
    "plot a missing file",
    "plot a text file",
    "plot a deck",
    "plot a truncated file",
    "plot an HDF5 file that is no result",
    "plot -o onto a file",
    "plot --labels with a slash",
    "optimise --out onto a file",
    "optimise a corrupt study file",
    "samples = 'many'",
    "samples = 64.5",
    "samples = 1e8",
    "samples = 100000000",
    "folds = 0",
    "seed = -1",
    "upper = nan",
    "label with a slash",
    "name with a slash",
    "a missing study deck",
    "--workers -2",
    "--workers 0",
    "--repeats x",
    "convergence --out onto a file",
]


@pytest.mark.parametrize("name", CASES)
def test_one_line_error(name, tmp_path, result_file, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)  # default outputs (out/NAME) land here
    argv, code, piece = _cases(tmp_path, result_file)[name]
    try:
        status = main(argv)
    except SystemExit as exc:  # argparse's own errors
        status = exc.code
    err = capsys.readouterr().err
    assert status == code, err
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert lines[0].startswith("ringlube") and "error" in lines[0]
    assert piece in lines[0]
    assert "Traceback" not in err


def test_device_is_untouched(tmp_path, result_file):
    deck, _ = result_file
    assert main(["run", str(deck), "-o", os.devnull]) == 2
    assert not os.path.isfile(os.devnull)


@pytest.mark.slow
def test_real_process_prints_one_line(tmp_path):
    """The installed command in a real process: stderr is one line, exit 2."""
    p = subprocess.run(
        [sys.executable, "-m", "ringlube.cli", "plot", str(COLD)], capture_output=True, text=True, timeout=120
    )
    assert p.returncode == 2
    assert p.stderr.count("\n") == 1 and "Traceback" not in p.stderr


# --- item 22 ---------------------------------------------------------------------------


def test_version(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["--version"])
    assert exc.value.code == 0
    expected = f"ringlube {ringlube.__version__} (kernel {ringlube.kernel_id()})"
    assert capsys.readouterr().out.strip() == expected


def test_run_quiet(tmp_path, result_file, capsys):
    deck, _ = result_file
    capsys.readouterr()
    assert main(["run", str(deck), "-o", str(tmp_path / "r.h5"), "-q"]) == 0
    assert capsys.readouterr().out == ""
    assert (tmp_path / "r.h5").is_file()


@pytest.mark.parametrize(
    "command", ["run", "plot", "gas", "convergence", "calibrate", "validate", "optimise"]
)
def test_help_shows_every_default(command, capsys):
    with pytest.raises(SystemExit):
        main([command, "--help"])
    text = " ".join(capsys.readouterr().out.split())
    from ringlube.cli_parser import _parser

    sub = next(a for a in _parser()._actions if a.dest == "command").choices[command]
    for action in sub._actions:
        if action.dest == "help":
            continue
        assert action.help, f"{command} {action.dest}: no help"
        if action.default not in (None, False, [], "==SUPPRESS=="):
            assert f"(default: {action.default})" in text, (command, action.dest)


def test_convergence_default_folder_is_the_documented_one():
    from ringlube.cli_parser import _parser

    sub = next(a for a in _parser()._actions if a.dest == "command").choices["convergence"]
    out = next(a for a in sub._actions if a.dest == "out")
    readme = (INPUTS.parent / "README.md").read_text()
    assert out.default == "docs/convergence"
    assert "docs/convergence/" in readme


@pytest.mark.slow
def test_dask_study_is_quiet_and_interrupts_in_one_line(tmp_path):
    """A LocalCluster study: nothing on stderr with -q; SIGTERM, or Ctrl-C to the process group,
    mid-run gives one line, exit 130, finished runs kept (no CancelledError, no dashboard or port
    notes, no worker's KeyboardInterrupt traceback)."""
    import signal
    import time

    deck = study_deck(tmp_path, samples="40")
    cmd = [sys.executable, "-m", "ringlube.cli", "optimise", deck, "--workers", "1", "-q"]
    p = subprocess.run([*cmd, "--out", str(tmp_path / "a")], capture_output=True, text=True, timeout=300)
    assert p.returncode == 0 and p.stderr == "", p.stderr
    big = study_deck(tmp_path, samples="2048")
    # a batch system's SIGTERM to the command; a terminal's Ctrl-C, SIGINT to the whole process
    # group, workers included (each worker printed a KeyboardInterrupt traceback)
    for how in ("SIGTERM", "Ctrl-C"):
        out = tmp_path / how
        proc = subprocess.Popen(
            [*cmd[:4], big, "--workers", "1", "-q", "--out", str(out)],
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
            start_new_session=True,  # its own process group, as a terminal's foreground job
            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
        )
        try:
            t0 = time.time()
            while time.time() - t0 < 240:
                if (out / "c.h5").exists():
                    with h5py.File(out / "c.h5") as f:
                        if "cases/cold/runs" in f and f["cases/cold/runs/done"][()].any():
                            break
                time.sleep(0.3)
            if how == "SIGTERM":
                proc.send_signal(signal.SIGTERM)
            else:
                os.killpg(proc.pid, signal.SIGINT)
            _, err = proc.communicate(timeout=120)
        finally:
            if proc.poll() is None:
                os.killpg(proc.pid, signal.SIGKILL)
        assert proc.returncode == 130, (how, err)
        assert err.strip().splitlines() == [
            "ringlube: interrupted; finished work is saved (run the same command to resume)"
        ], how
        with h5py.File(out / "c.h5") as f:
            assert 0 < f["cases/cold/runs/done"][()].sum() < 2048


def test_output_piped_into_head_ends_quietly():
    """`ringlube show DECK --set | head -1` printed 'ringlube: error: Broken pipe' when the
    reader left before the output was written (forced here: the reader exits at once, the
    command waits until the pipe reports that its reader is gone, then writes unbuffered)."""
    import subprocess
    import sys

    from conftest import COLD

    code = (
        "import select, sys; p = select.poll(); p.register(1, select.POLLERR); p.poll(); "
        "from ringlube.cli import main; sys.exit(main(['show', sys.argv[1]]))"
    )
    p = subprocess.run(
        f"'{sys.executable}' -u -c \"{code}\" '{COLD}' | true; echo ${{PIPESTATUS[0]}}",
        shell=True,
        executable="/bin/bash",
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert p.stdout.strip() == "141", (p.stdout, p.stderr)
    assert p.stderr == "", p.stderr


def test_ctrl_c_stops_a_run_within_a_step_and_writes_nothing(tmp_path):
    """Ctrl-C (SIGINT) during `ringlube.run(..., output=...)` and `ringlube run -o` stops the
    kernel within a crank step: KeyboardInterrupt / exit 130, and no result file nor a
    temporary one. Before, Python's handler acted only once the kernel returned, so a run was
    finished (and its file written) before the interrupt took effect (a review, 2026-11-26).
    The run here would take minutes (starved, 'accurate', up to 1000 cycles to 1e-14); it is
    interrupted once it is under way."""
    import signal

    deck = tmp_path / "long.nml"
    text = COLD.read_text().replace("'pressure/", f"'{INPUTS}/pressure/")
    text = text.replace("calibration.nml", str(INPUTS / "calibration.nml"))
    text = text.replace("&physics ", "&physics cavitation = 'jfo', inlet = 'starved', ")
    text = re.sub(r"max_cycles = \d+", "max_cycles = 1000", text)
    text = re.sub(r"cycle_tol = [0-9.e-]+", "cycle_tol = 1e-14", text)
    text = text.replace("preset = 'default'", "preset = 'accurate'")
    deck.write_text(text)
    api = (
        "import sys, ringlube\n"
        "case = ringlube.Case.from_namelist(sys.argv[1])\n"
        "print('started', flush=True)\n"
        "try:\n"
        "    ringlube.run(case, output=sys.argv[2])\n"
        "except KeyboardInterrupt:\n"
        "    sys.exit(130)\n"
    )
    for name, cmd in (
        ("api.h5", [sys.executable, "-c", api, str(deck)]),
        ("cli.h5", [sys.executable, "-m", "ringlube.cli", "run", str(deck), "-q", "-o"]),
    ):
        out = tmp_path / "out" / name
        out.parent.mkdir(exist_ok=True)
        # (SIGINT as an interactive shell leaves it: a test runner started in the background
        # may have it ignored, which the child would inherit and keep)
        proc = subprocess.Popen(
            [*cmd, str(out)],
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
        )
        try:
            if name == "api.h5":
                assert proc.stdout.readline().strip() == "started"
            _wait_until_computing(proc)  # the kernel is running: a signal from the process
            assert proc.poll() is None, proc.communicate()
            proc.send_signal(signal.SIGINT)
            _, err = proc.communicate(timeout=60)
        finally:
            if proc.poll() is None:
                proc.kill()
        assert proc.returncode == 130, (name, err)
        assert list(out.parent.iterdir()) == [], (name, list(out.parent.iterdir()))
        assert "Traceback" not in err, err


def _cpu_seconds(pid: int) -> float:
    """CPU time (user + system) a process has used, from /proc."""
    fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def _wait_until_computing(proc, cpu: float = 0.5, timeout: float = 300.0) -> None:
    """Wait for the process to have loaded the kernel's extension and then computed for
    ``cpu`` seconds of its own CPU time (the deck is read in milliseconds: it is in the run),
    however loaded the machine is; fails if it ends first."""
    import time

    maps, t0 = Path(f"/proc/{proc.pid}/maps"), time.monotonic()
    start = None
    while time.monotonic() - t0 < timeout:
        assert proc.poll() is None, proc.communicate()
        if start is None and "_kernel." in maps.read_text():
            start = _cpu_seconds(proc.pid)
        if start is not None and _cpu_seconds(proc.pid) - start >= cpu:
            return
        time.sleep(0.02)  # polling a condition, not a delay standing in for one
    raise AssertionError("the process did not start computing")


def test_ctrl_c_while_the_command_starts_ends_in_one_line(tmp_path):
    """Ctrl-C while `ringlube` imports its modules (seconds on a loaded machine): exit 130 and
    one line, as during its work (it was a KeyboardInterrupt traceback and exit -2). The
    signal goes as soon as numpy is loaded: ringlube's own imports have begun."""
    import signal
    import time

    deck = tmp_path / "d.nml"
    deck.write_text("&numerics preset = 'accurate', max_cycles = 1000, cycle_tol = 1e-14 /\n")
    proc = subprocess.Popen(
        [sys.executable, "-m", "ringlube.cli", "run", str(deck), "-q", "-o", str(tmp_path / "r.h5")],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
    )
    try:
        maps = Path(f"/proc/{proc.pid}/maps")
        while "_multiarray_umath" not in maps.read_text():
            assert proc.poll() is None, proc.communicate()
            time.sleep(0.005)  # polling a condition, not a delay standing in for one
        proc.send_signal(signal.SIGINT)
        out, err = proc.communicate(timeout=120)
    finally:
        if proc.poll() is None:
            proc.kill()
    assert proc.returncode == 130 and err == "ringlube: interrupted\n" and out == "", (proc.returncode, err)
    assert list(tmp_path.iterdir()) == [deck]


def test_ctrl_c_inside_an_extension_s_import_ends_in_one_line(tmp_path):
    """A Ctrl-C while the command imports a C extension: numpy turned the KeyboardInterrupt
    raised inside its import into an ImportError ('PyCapsule_Import could not import module
    "datetime"', a numpy traceback and exit 1, seen on a loaded machine). The command's SIGINT
    handler while it starts ends it at the signal: one line, exit 130. Here a script named
    `ringlube` (as the console script) imports the package, then sends itself SIGINT where
    such an import would swallow it; and once the command has built its parser (its imports), Python's own
    handler is back (a Ctrl-C during the work stops the kernel and cleans up)."""
    import signal
    import textwrap

    script = tmp_path / "ringlube"
    script.write_text(
        textwrap.dedent(
            """
            import os, signal, sys
            import ringlube  # the command's start, as its console script

            if sys.argv[1] == "started":
                import ringlube.cli as cli

                seen, build = {}, cli._parser

                def parser():  # the command's parser, its command replaced by a probe
                    seen["building"] = signal.getsignal(signal.SIGINT) is ringlube._interrupted_at_start
                    p = build()
                    parse = p.parse_args

                    def parse_args(argv):
                        args = parse(argv)

                        def probe(a):
                            seen["command"] = signal.getsignal(signal.SIGINT) is signal.default_int_handler
                            return 0

                        args.func = probe
                        return args

                    p.parse_args = parse_args
                    return p

                cli._parser = parser
                code = cli.main(["show", "any.nml"])
                print(seen["building"], seen["command"], code)
                sys.exit(0)
            try:  # an extension's import that turns an interrupt into another error
                os.kill(os.getpid(), signal.SIGINT)
                sum(range(1000))
            except KeyboardInterrupt as exc:
                raise ImportError('PyCapsule_Import could not import module "datetime"') from exc
            print("not interrupted")
            """
        )
    )

    def run(what):
        return subprocess.run(
            [sys.executable, str(script), what],
            capture_output=True,
            text=True,
            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
        )

    p = run("importing")
    assert (p.returncode, p.stderr, p.stdout) == (130, "ringlube: interrupted\n", "")
    # the start-up handler while the parser is built (its imports: scipy among them, where a
    # KeyboardInterrupt came out as scipy's 'ImportError: initialization failed' or a death by
    # SIGINT at exit), Python's own once the command runs
    p = run("started")
    assert p.returncode == 0 and p.stdout.splitlines()[-1] == "True True 0", (p.stdout, p.stderr)
    # not in a process that only inherits the command's sys.argv (a study's spawned worker),
    # and not where SIGINT is ignored (started in the background, or a Dask worker)
    code = "import sys; sys.argv[0] = {!r}; import ringlube, signal; print(signal.getsignal(signal.SIGINT))"
    p = subprocess.run([sys.executable, "-c", code.format(str(script))], capture_output=True, text=True)
    assert p.stdout == f"{signal.default_int_handler}\n", (p.stdout, p.stderr)
    p = subprocess.run(
        [sys.executable, str(script), "ignored"],
        capture_output=True,
        text=True,
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_IGN),
    )
    assert (p.returncode, p.stdout, p.stderr) == (0, "not interrupted\n", "")
