"""``ringlube convergence`` shows progress before its first run and after every run (a
starved reference run alone can take minutes), and checks its outputs before the work."""

from __future__ import annotations

import pytest

import ringlube
import ringlube.convergence as conv
from ringlube.cli import main

from conftest import COLD


@pytest.fixture()
def fake_runs(monkeypatch, capsys):
    """Replace the kernel runs by one fast result; record the progress shown before each."""
    result = ringlube.run(ringlube.Case.from_namelist(COLD).with_numerics(preset="fast"))
    seen: list[str] = []

    def run(case):
        seen.append(capsys.readouterr().err)
        return result

    monkeypatch.setattr(conv, "run", run)
    return seen


def test_convergence_shows_progress_before_the_first_run(fake_runs):
    reference, rows = conv.convergence_study(COLD, quick=True, repeats=2, progress=True)
    runs = 5 + 2 * len(conv.ladder(quick=True))
    assert len(fake_runs) == runs
    assert "reference: nodes 801" in fake_runs[0]  # shown before the reference run starts
    assert f"0/{runs}" in fake_runs[0]
    assert all(f"{k}/{runs}" in fake_runs[k] for k in (1, 5, runs - 1))  # one step per run
    assert len(rows) == len(conv.ladder(quick=True))


def test_convergence_checks_its_outputs_before_the_runs(fake_runs, tmp_path, capsys):
    victim = tmp_path / "victim.nml"
    victim.write_text("&ring /\n")
    (tmp_path / f"convergence_{COLD.stem}.csv").symlink_to(victim)
    assert main(["convergence", str(COLD), "--quick", "--out", str(tmp_path)]) == 2
    assert "is a symbolic link" in capsys.readouterr().err
    assert fake_runs == [] and victim.read_text() == "&ring /\n"
