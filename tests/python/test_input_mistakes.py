"""User mistakes in designs, targets files and study decks: each refused with one line, never
last-one-wins, never a traceback, never an invented number."""

from __future__ import annotations

import shutil

import numpy as np
import pytest

import ringlube
from ringlube import InputError
from ringlube.calibrate import cold_targets
from ringlube.cli import main
from ringlube.solve import run_designs
from ringlube.study.deck import read_study
from ringlube.targets import read_targets

from conftest import COLD, INPUTS

pytestmark = pytest.mark.unit

HEADER = "condition,deck,quantity,value,unit\n"


@pytest.fixture()
def fast_case():
    return ringlube.Case.from_namelist(COLD).with_numerics(preset="fast")


# --- run_designs ----------------------------------------------------------------------


def test_run_designs_refuses_a_result_the_film_model_does_not_produce(fast_case):
    with pytest.raises(InputError, match="oil_to_chamber needs &physics inlet = 'starved'"):
        run_designs(fast_case, ["width"], np.array([[1e-3]]), ["oil_to_chamber"])


@pytest.mark.parametrize("variables", [["width", "width"], ["width", "ring:width"]])
def test_run_designs_refuses_a_variable_given_twice(fast_case, variables):
    with pytest.raises(InputError, match="give it once"):
        run_designs(fast_case, variables, np.array([[1e-3, 1.1e-3]]), ["energy_loss"])


def test_run_designs_takes_a_deck_path():
    case = ringlube.Case.from_namelist(COLD).with_numerics(preset="fast")
    v_case, ok_case, _ = run_designs(case, ["width"], np.array([[1e-3]]), ["ring_mass"])
    v_path, ok_path, _ = run_designs(str(COLD), ["width"], np.array([[1e-3]]), ["ring_mass"])
    assert ok_case[0] and ok_path[0] and v_path[0, 0] == v_case[0, 0]
    with pytest.raises(TypeError, match="expected a Case or a deck path"):
        run_designs(42, ["width"], np.array([[1e-3]]), ["ring_mass"])


# --- targets files --------------------------------------------------------------------


def targets(tmp_path, rows: str, prefix: bytes = b"") -> str:
    path = tmp_path / "t.csv"
    path.write_bytes(prefix + (HEADER + rows).encode())
    return str(path)


def test_targets_refuse_a_duplicate_row(tmp_path):
    path = targets(tmp_path, "cold,c.nml,energy_loss,1.9,J\ncold,c.nml,energy_loss,2.1,J\n")
    with pytest.raises(InputError, match=r"t.csv:3: condition 'cold' gives energy_loss twice"):
        read_targets(path)


def test_targets_refuse_a_negative_energy(tmp_path):
    with pytest.raises(InputError, match=r"t.csv:2: energy_loss = -1.9: must not be negative"):
        read_targets(targets(tmp_path, "cold,c.nml,energy_loss,-1.9,J\n"))


def test_targets_accept_a_byte_order_mark(tmp_path):
    path = targets(tmp_path, "cold,c.nml,energy_loss,1.9,J\n", prefix=b"\xef\xbb\xbf")
    assert read_targets(path)["cold"].values == {"energy_loss": 1.9}


def test_targets_that_are_not_utf8_are_one_line(tmp_path):
    path = tmp_path / "t.csv"
    path.write_bytes((HEADER + "cold,c.nml,energy_loss,1.9,J\n").encode() + b"hot,\xff,x,1,J\n")
    with pytest.raises(InputError, match=r"t.csv:3: not UTF-8 text \(byte 0xff\)"):
        read_targets(path)


def test_calibration_refuses_a_zero_target(tmp_path, capsys):
    path = targets(tmp_path, f"cold,{COLD},energy_loss,1.9,J\ncold,{COLD},mixed_share,0,%\n")
    with pytest.raises(InputError, match="mixed_share = 0: must be positive"):
        cold_targets(path)
    assert main(["calibrate", str(COLD), "--targets", path, "--out", str(tmp_path / "c.nml")]) == 2
    assert "must be positive" in capsys.readouterr().err


# --- study decks ----------------------------------------------------------------------


def study(tmp_path, body: str) -> str:
    path = tmp_path / "s.nml"
    path.write_text(f"&study\n cases = '{COLD}'\n{body}/\n")
    return str(path)


def test_study_refuses_a_variable_given_twice(tmp_path):
    with pytest.raises(InputError, match=r"s\.nml:3: &study samples: given twice \(also on line 3\)"):
        read_study(study(tmp_path, " samples = 16, samples = 32\n"))


def test_study_refuses_two_study_groups(tmp_path):
    path = study(tmp_path, "")
    with open(path, "a") as fh:
        fh.write("&study samples = 3 /\n")
    with pytest.raises(InputError, match=r"s\.nml: 2 &study groups \(lines 1, 4\)"):
        read_study(path)


def test_study_with_an_unterminated_string_is_one_line(tmp_path, capsys):
    path = tmp_path / "s.nml"
    path.write_text("&study\n cases = 'a.nml\n samples = 3\n/\n")
    with pytest.raises(InputError, match=r"s\.nml:2: &study cases: unterminated string"):
        read_study(path)
    assert capsys.readouterr().out == ""  # nothing printed by the parser either


def test_study_refuses_a_whole_number_variable(tmp_path):
    path = study(tmp_path, " variables = 'numerics:nodes'\n lower = 11\n upper = 41\n")
    with pytest.raises(InputError, match="'numerics:nodes' is a whole number"):
        read_study(path)


def test_empty_scheduler_option_is_refused(tmp_path, capsys):
    path = study(tmp_path, " samples = 24\n")
    assert main(["optimise", path, "--scheduler", "", "--out", str(tmp_path / "o"), "-q"]) == 2
    assert "--scheduler '': empty address" in capsys.readouterr().err


# --- validate -------------------------------------------------------------------------


def test_validate_without_a_calibration_file_is_one_line(tmp_path, capsys):
    (tmp_path / "inputs").mkdir()
    for name in ("crf450r_4000rpm_full_cold.nml", "crf450r_4000rpm_full_hot.nml"):
        text = (INPUTS / name).read_text()
        (tmp_path / "inputs" / name).write_text(
            "\n".join(line for line in text.splitlines() if "&calibration" not in line) + "\n"
        )
    shutil.copytree(INPUTS / "pressure", tmp_path / "inputs" / "pressure")
    assert main(["validate", "--root", str(tmp_path), "--out", str(tmp_path / "docs")]) == 2
    err = capsys.readouterr().err
    assert "&calibration file: not given" in err and len(err.strip().splitlines()) == 1


@pytest.mark.cli
def test_ring_pack_inputs_with_the_ring_pack_off_are_said(tmp_path, solver):
    """`&ring_pack` inputs with `ring_pack = 'none'` are not used: ringlube-solve warns on
    stderr (file, line, variable) and Python warns (UnusedInputWarning); with the ring pack on,
    or without such inputs, nothing is said. (A review found them silently ignored.)"""
    import subprocess
    import warnings

    deck = tmp_path / "d.nml"
    deck.write_text(
        COLD.read_text()
        .replace("'pressure/", f"'{INPUTS}/pressure/")
        .replace("calibration.nml", str(INPUTS / "calibration.nml"))
        + "&ring_pack top_gap_area = 0.2e-6 /\n"
    )
    p = subprocess.run(
        [solver, str(deck), "-q", "-o", str(tmp_path / "d.h5")], capture_output=True, text=True
    )
    line = len(deck.read_text().splitlines())
    assert p.returncode == 0 and f"warning: {deck}:{line}: &ring_pack top_gap_area is set" in p.stderr, (
        p.stderr
    )
    case = ringlube.Case.from_namelist(deck).with_numerics(preset="fast")
    with pytest.warns(ringlube.UnusedInputWarning, match="ring pack is off"):
        ringlube.run(case)
    with warnings.catch_warnings():
        warnings.simplefilter("error", ringlube.UnusedInputWarning)
        ringlube.run(case.with_physics(ring_pack="gas"))
        ringlube.run(ringlube.Case.from_namelist(COLD).with_numerics(preset="fast"))
