"""``ringlube convergence`` shows progress before its first run and after every run (a
starved reference run alone can take minutes), and checks its outputs before the work."""

from __future__ import annotations

import pytest

import ringlube
import ringlube.convergence as conv
from ringlube.cli import main

from conftest import COLD

pytestmark = pytest.mark.numerics


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


def test_convergence_compares_the_ring_pack_quantities(monkeypatch, tmp_path):
    """With the ring pack's gas the ladder reports blowby, ring lift share and flutter events
    against the reference (lift and flutter were left out): in the rows, the Markdown table
    and the CSV. Each run here is the reference's result with its blowby 10 % higher, its
    lift 2 points lower and one flutter event more at 51 nodes (and the reference's crank
    step), so only that row shows errors, and they are computed independently."""
    import csv

    from conftest import INPUTS

    deck = INPUTS / "crf450r_4000rpm_full_hot_gas.nml"
    ref = ringlube.run(ringlube.Case.from_namelist(deck).with_numerics(preset="fast"))
    assert ref.blowby > 0
    off = ringlube.run(ringlube.Case.from_namelist(deck).with_numerics(preset="fast"))
    off.scalars["blowby"] = 1.1 * ref.blowby
    off.scalars["ring_lift_share"] = ref.ring_lift_share - 2.0
    off.scalars["flutter_events"] = ref.flutter_events + 1.0

    def run(case):
        at_51 = case.get("numerics", "nodes") == 51 and case.get("numerics", "dpsi_deg") == 0.125
        return off if at_51 else ref

    monkeypatch.setattr(conv, "run", run)
    reference, rows = conv.convergence_study(deck, quick=True, repeats=1, progress=False)
    assert reference["extra"]["ring_lift_share"] == ref.ring_lift_share
    assert reference["extra"]["flutter_events"] == ref.flutter_events
    row = next(r for r in rows if r.setting.label == "nodes = 51")
    assert row.extra["blowby"] == (1.1 * ref.blowby, pytest.approx(0.1))
    assert row.extra["ring_lift_share"][1] == pytest.approx(2.0) and row.extra["flutter_events"][1] == 1.0
    others = [r for r in rows if r is not row]
    assert all(e == 0 for r in others for _, e in r.extra.values())

    md, csv_path, _ = conv.write_report(str(deck), reference, rows, tmp_path, "ringlube convergence")
    text = md.read_text()
    assert "| err ring_lift_share (pts) |" in text and "| err flutter_events (difference) |" in text
    line = next(x for x in text.splitlines() if "| nodes = 51 |" in x)
    assert "| 1.00e-01 |" in line and "| 2.000 |" in line and "| 1 |" in line
    with open(csv_path) as fh:
        got = {r["setting"]: r for r in csv.DictReader(fh)}
    assert float(got["nodes = 51"]["err_ring_lift_share_pts"]) == pytest.approx(2.0)
    assert float(got["nodes = 51"]["err_flutter_events"]) == 1.0


def test_convergence_without_the_ring_pack_has_no_ring_pack_columns(fake_runs, tmp_path):
    reference, rows = conv.convergence_study(COLD, quick=True, repeats=1, progress=False)
    assert reference["extra"] == {} and all(r.extra == {} for r in rows)
    md, csv_path, _ = conv.write_report(str(COLD), reference, rows, tmp_path, "ringlube convergence")
    text = md.read_text() + csv_path.read_text()
    assert "blowby" not in text and "ring_lift" not in text and "flutter" not in text
