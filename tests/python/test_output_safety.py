"""Every writer refuses an output that is a symbolic link, a folder or one of its inputs, and
checks its output before the work, not after."""

from __future__ import annotations

import shutil

import h5py
import matplotlib.pyplot as plt
import pytest

import ringlube
from ringlube import InputError
from ringlube.cli import main
from ringlube.executor import Executor
from ringlube.outputs import check_output, write_text
from ringlube.study import run_study
from ringlube.study.plots import save

from conftest import COLD, INPUTS

pytestmark = pytest.mark.io


@pytest.fixture()
def result_file(tmp_path, quick_case):
    path = tmp_path / "cold.h5"
    ringlube.run(quick_case, output=path)
    return path


def test_plot_refuses_symlinked_output(result_file, tmp_path, capsys):
    plots = tmp_path / "plots"
    plots.mkdir()
    (plots / "cold_friction.pdf").symlink_to("../cold.h5")
    before = result_file.read_bytes()
    assert main(["plot", str(result_file), "-o", str(plots)]) == 2
    err = capsys.readouterr().err
    assert "cold_friction.pdf: is a symbolic link" in err and len(err.strip().splitlines()) == 1
    assert result_file.read_bytes() == before and h5py.is_hdf5(result_file)
    assert sorted(p.name for p in plots.iterdir()) == ["cold_friction.pdf"]  # nothing written


def test_plot_refuses_more_labels_than_results(result_file, tmp_path, capsys):
    assert main(["plot", str(result_file), "-o", str(tmp_path), "--labels", "a,b"]) == 2
    assert "--labels: 2 labels for 1 result files" in capsys.readouterr().err


def test_study_figure_refuses_symlinked_output(tmp_path):
    victim = tmp_path / "deck.nml"
    victim.write_text("&ring /\n")
    (tmp_path / "fit_cold.png").symlink_to(victim)
    with pytest.raises(InputError, match="fit_cold.png: is a symbolic link"):
        save(plt.figure(), tmp_path, "fit_cold")
    assert victim.read_text() == "&ring /\n"


@pytest.mark.parametrize("kind", ["folder", "input", "symlink", "missing folder"])
def test_text_writer_refuses_unsafe_outputs(tmp_path, kind):
    deck = tmp_path / "deck.nml"
    deck.write_text("&ring /\n")
    target = {
        "folder": tmp_path,
        "input": deck,
        "symlink": tmp_path / "link.md",
        "missing folder": tmp_path / "nowhere" / "x.md",
    }[kind]
    if kind == "symlink":
        target.symlink_to(deck)
    with pytest.raises(InputError, match="folder|input of this run|symbolic link|does not exist"):
        write_text(target, "overwritten", [deck])
    assert deck.read_text() == "&ring /\n"
    assert list(tmp_path.glob("*.part")) == [] and list(tmp_path.glob(".*.part")) == []


def test_study_report_refuses_symlinked_output(tmp_path):
    deck = tmp_path / "s.nml"
    deck.write_text(
        f"&study\n name = 's', cases = '{COLD}', labels = 'cold', samples = 24, seed = 3\n"
        " variables = 'width', 'crown_offset', lower = 0.8e-3, -40e-6, upper = 1.2e-3, 40e-6\n"
        " population = 12, generations = 3, repeats = 2\n/\n"
    )
    out = tmp_path / "out"
    out.mkdir()
    (out / "report.md").symlink_to(deck)
    text = deck.read_text()
    with pytest.raises(InputError, match="report.md: is a symbolic link"):
        run_study(deck, out, executor=Executor(serial=True), progress=False, figures=False)
    assert deck.read_text() == text
    assert not (out / "s.h5").exists()  # refused before the runs


@pytest.mark.parametrize("out", ["deck", "folder", "missing folder", "symlink"])
def test_calibrate_checks_its_output_before_the_runs(tmp_path, monkeypatch, capsys, out):
    import ringlube.calibrate

    for name in ("crf450r_4000rpm_full_cold.nml", "calibration.nml", "targets_table2.csv"):
        shutil.copy(INPUTS / name, tmp_path)
    (tmp_path / "pressure").mkdir()
    shutil.copy(INPUTS / "pressure" / "crf450r_4000rpm_full.csv", tmp_path / "pressure")
    deck = tmp_path / "crf450r_4000rpm_full_cold.nml"
    text = deck.read_text()
    (tmp_path / "link.nml").symlink_to(deck)
    target = {
        "deck": deck,
        "folder": tmp_path,
        "missing folder": tmp_path / "no" / "cal.nml",
        "symlink": tmp_path / "link.nml",
    }[out]

    def no_runs(*args, **kwargs):
        raise AssertionError("calibrate ran before its output was checked")

    monkeypatch.setattr(ringlube.calibrate, "calibrate", no_runs)
    code = main(
        ["calibrate", str(deck), "--out", str(target), "--targets", str(tmp_path / "targets_table2.csv")]
    )
    assert code == 2
    assert capsys.readouterr().err.startswith(f"ringlube: error: --out {target}: ")
    assert deck.read_text() == text


def test_check_output_accepts_a_new_file_and_a_regular_file(tmp_path):
    (tmp_path / "old.csv").write_text("x")
    assert check_output(tmp_path / "old.csv") == tmp_path / "old.csv"
    assert check_output(tmp_path / "new.csv", [tmp_path / "old.csv"]) == tmp_path / "new.csv"


def test_written_file_is_readable_by_others(tmp_path):
    import os
    import stat

    mask = os.umask(0o022)
    try:
        path = write_text(tmp_path / "r.md", "x")
    finally:
        os.umask(mask)
    assert stat.S_IMODE(path.stat().st_mode) == 0o644


@pytest.mark.cli
def test_result_file_refuses_a_symbolic_link_in_every_front_end(tmp_path, solver, quick_case):
    """A result file named by a symbolic link is refused by `ringlube-solve`, by
    `ringlube.run(output=...)` and by `ringlube run`, and the link and its target are left as
    they were (before 2026-11-26 the kernel replaced the link, as `mv` would, while
    `ringlube run` refused it: the front ends disagreed)."""
    import subprocess

    target = tmp_path / "other.h5"
    target.write_bytes(b"someone else's result")
    link = tmp_path / "link.h5"
    link.symlink_to(target)
    p = subprocess.run([solver, str(COLD), "-q", "-o", str(link)], capture_output=True, text=True)
    assert p.returncode == 2 and "symbolic link" in p.stderr, p.stderr
    with pytest.raises(InputError, match="symbolic link"):
        ringlube.run(quick_case, output=link)
    assert main(["run", str(COLD), "-q", "-o", str(link)]) == 2
    assert link.is_symlink() and target.read_bytes() == b"someone else's result"
    assert sorted(q.name for q in tmp_path.iterdir()) == ["link.h5", "other.h5"]


@pytest.mark.cli
def test_result_file_records_where_it_was_written(tmp_path, solver, quick_case):
    """`output.file` in a result is the path it was written to (-o, output=), not the deck's
    &output file that -o overrode."""
    import subprocess

    a, b = tmp_path / "a.h5", tmp_path / "b.h5"
    p = subprocess.run([solver, str(COLD), "-q", "-o", str(a)], capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    ringlube.run(quick_case, output=b)
    for path in (a, b):
        with h5py.File(path) as f:
            assert f.attrs["output.file"] == str(path)


def test_run_command_refuses_an_empty_output_name_and_warns_when_not_converged(tmp_path, capsys):
    """`ringlube run -o ''` is an error (as `ringlube-solve -o ''`), not the deck's &output file;
    a run that does not converge says so on stderr also with -q (as ringlube-solve), exit 3."""
    assert main(["run", str(COLD), "-q", "-o", ""]) == 2
    assert "output file name is empty" in capsys.readouterr().err
    deck = tmp_path / "one.nml"
    text = COLD.read_text().replace("'pressure/", f"'{INPUTS}/pressure/")
    text = text.replace("calibration.nml", str(INPUTS / "calibration.nml"))
    deck.write_text(
        text.replace("max_cycles = 10", "max_cycles = 1").replace("cycle_tol = 1e-3", "cycle_tol = 1e-9")
    )
    assert main(["run", str(deck), "-q", "-o", str(tmp_path / "one.h5")]) == 3
    captured = capsys.readouterr()
    assert captured.out == "" and "did not converge" in captured.err
