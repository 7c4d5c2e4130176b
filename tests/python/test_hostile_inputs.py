"""Hostile inputs of a fourth round: one reading of every deck and trace in every front end,
named errors for values the run could not honour, messages that say what to do."""

from __future__ import annotations

import re
import shutil
import subprocess

import numpy as np
import pytest

import ringlube
from ringlube import InputError
from ringlube.cli import main
from ringlube.executor import Executor

from conftest import COLD, INPUTS

pytestmark = [pytest.mark.unit, pytest.mark.io]


def own_inputs(folder, calibration=None):
    """A copy of the cold deck with its calibration file (optionally replaced) and trace."""
    (folder / "pressure").mkdir()
    shutil.copy(INPUTS / "pressure" / "crf450r_4000rpm_full.csv", folder / "pressure")
    cal = (INPUTS / "calibration.nml").read_text()
    (folder / "calibration.nml").write_text(calibration(cal) if calibration else cal)
    shutil.copy(COLD, folder / "cold.nml")
    return folder / "cold.nml"


# --- a NUL byte: one reading (a named error) in ringlube-solve, ringlube run/show and the API --


@pytest.mark.cli
def test_a_nul_byte_in_a_deck_is_one_named_error_everywhere(tmp_path, solver, capsys):
    deck = own_inputs(tmp_path)
    text = deck.read_text()
    line = text[: text.index("&operating")].count("\n") + 1
    deck.write_text(text.replace("&operating", "! a comment \0 with a NUL\n&operating", 1))
    message = f"cold.nml:{line}: a NUL byte (binary data, not text) in the deck"
    p = subprocess.run(
        [solver, str(deck), "-q", "-o", str(tmp_path / "r.h5")], capture_output=True, text=True
    )
    assert p.returncode == 2 and message in p.stderr, p.stderr
    for command in (["run", str(deck), "-q", "-o", str(tmp_path / "r.h5")], ["show", str(deck)]):
        assert main(command) == 2
        err = capsys.readouterr().err
        assert message in err and "Traceback" not in err, err
    with pytest.raises(InputError, match=re.escape(message)):
        ringlube.Case.from_namelist(deck)
    assert not (tmp_path / "r.h5").exists()


# --- the chamber pressure has one limit: a trace's, also after pressure_scale ----------------


@pytest.mark.cli
def test_pressure_scale_is_held_to_the_limit_of_a_trace(tmp_path, solver):
    """The shipped trace peaks at 60 bar: 16 times is 960 bar and runs, 17 times is refused
    like a trace point above 1000 bar (1e8 Pa), in the deck, through the API and with a trace
    given as arrays."""
    peak = np.loadtxt(
        INPUTS / "pressure" / "crf450r_4000rpm_full.csv", delimiter=",", comments="#", skiprows=3
    )
    assert 16 * peak[:, 1].max() <= 1e8 < 17 * peak[:, 1].max()
    deck = own_inputs(tmp_path, lambda t: re.sub(r"pressure_scale = \S+ /", "pressure_scale = 17 /", t))
    cal = (tmp_path / "calibration.nml").read_text()
    assert "pressure_scale = 17 /" in cal
    line = cal[: cal.index("&operating")].count("\n") + 1
    p = subprocess.run(
        [solver, str(deck), "-q", "-o", str(tmp_path / "r.h5")], capture_output=True, text=True
    )
    assert p.returncode == 2, p.stderr
    assert (
        f"calibration.nml:{line}: &operating pressure_scale: 1.7E+1 times the trace's highest pressure"
        in p.stderr
    )
    assert "at most 1000 bar" in p.stderr and not (tmp_path / "r.h5").exists()
    case = ringlube.Case.from_namelist(COLD).with_numerics(preset="fast")
    with pytest.raises(InputError, match="pressure_scale: .* at most 1000 bar"):
        ringlube.run(case.with_("operating", pressure_scale=17.0))
    assert np.isfinite(ringlube.run(case.with_("operating", pressure_scale=16.0)).energy_loss)
    with pytest.raises(InputError, match="pressure_scale = .*above 1000 bar"):
        ringlube.run(case.with_("operating", pressure_scale=2.0), trace=(peak[:, 0], peak[:, 1] * 9))
    _, ok, errors = ringlube.run_designs(
        case, ["operating:pressure_scale"], np.array([[17.0]]), ["energy_loss"]
    )
    assert not ok[0] and "pressure_scale: 1.7E+1 times" in errors[0] and "at most 1000 bar" in errors[0]


# --- a CSV with a byte-order mark reads as without -------------------------------------------


def test_a_trace_with_a_byte_order_mark_reads_as_without(tmp_path):
    deck = own_inputs(tmp_path)
    trace = tmp_path / "pressure" / "crf450r_4000rpm_full.csv"
    case = ringlube.Case.from_namelist(deck).with_numerics(preset="fast")
    plain = ringlube.run(case).energy_loss
    for text in (trace.read_text(), "".join(trace.read_text().splitlines(True)[2:])):  # header first
        trace.write_bytes(b"\xef\xbb\xbf" + text.encode())
        assert ringlube.run(case).energy_loss == plain


# --- messages that say what changed and what to do -------------------------------------------


def _study(path, **extra):
    lines = [
        "&study",
        f"  name = 'm', cases = '{COLD}'",
        "  variables = 'width', 'crown_offset', lower = 0.8e-3, -40e-6, upper = 1.2e-3, 40e-6",
        "  population = 12, generations = 4, repeats = 2",
        *(f"  {k} = {v}" for k, v in {"samples": 24, "seed": 5, **extra}.items()),
        "/",
    ]
    path.write_text("\n".join(lines) + "\n")
    return path


def test_a_refused_resume_names_what_changed_and_restart(tmp_path):
    from ringlube.study import run_study

    deck, out = _study(tmp_path / "m.nml"), tmp_path / "out"
    with pytest.raises(KeyboardInterrupt):
        run_study(deck, out, executor=Executor(serial=True), progress=False, figures=False, stop_after=2)
    _study(deck, samples=32)
    with pytest.raises(InputError) as e:
        run_study(deck, out, executor=Executor(serial=True), progress=False, figures=False)
    assert "other samples (24, now 32)" in str(e.value) and "--restart" in str(e.value)
    assert "recorded" not in str(e.value) and "objectives" not in str(e.value)
    _study(deck, constraints="'fmep <= 100'")
    with pytest.raises(InputError) as e:
        run_study(deck, out, executor=Executor(serial=True), progress=False, figures=False)
    assert "other recorded results (a constraint on a result" in str(e.value)
    assert "samples" not in str(e.value) and "objectives" not in str(e.value)


@pytest.mark.parametrize(
    "variable, takes",
    [
        ("physics:cavitation", "one of 'swift_stieber', 'jfo'"),
        ("operating:pressure_file", "text"),
        ("physics:squeeze", ".true. or .false."),
    ],
)
def test_a_text_input_as_a_study_variable_says_it_is_not_a_number(tmp_path, variable, takes):
    from ringlube.study.deck import read_study

    deck = _study(tmp_path / "m.nml").read_text().replace("'width', 'crown_offset'", f"'{variable}', 'width'")
    (tmp_path / "m.nml").write_text(
        deck.replace("lower = 0.8e-3, -40e-6, upper = 1.2e-3, 40e-6", "lower = 0, 0.8e-3, upper = 1, 1.2e-3")
    )
    with pytest.raises(InputError, match=rf"m.nml:3: &study variables: '{variable}' is not a number") as e:
        read_study(tmp_path / "m.nml")
    assert f"takes {takes})" in str(e.value) and "quoted string" not in str(e.value)


def test_optimise_on_a_case_deck_says_it_is_a_case_deck(capsys):
    assert main(["optimise", str(COLD), "--serial"]) == 2
    err = capsys.readouterr().err
    assert "this is a case deck" in err and "ringlube run" in err and "&calibration: not a group" not in err


# --- front ends agree ------------------------------------------------------------------------


@pytest.mark.cli
def test_a_value_of_100000_digits_reads_alike_in_every_front_end(tmp_path, solver, capsys):
    """ringlube-solve read it; run and show refused it (a 4096-byte limit of the f2py layer)."""
    deck = own_inputs(tmp_path)
    text = deck.read_text().replace("preset = 'default'", "preset = 'fast'", 1)
    deck.write_text(
        text.replace("&operating speed_rpm = 4000,", "&operating speed_rpm = 4000." + "0" * 100_000 + ",")
    )
    p = subprocess.run(
        [solver, str(deck), "-q", "-o", str(tmp_path / "a.h5")], capture_output=True, text=True
    )
    assert p.returncode == 0, p.stderr
    assert main(["run", str(deck), "-q", "-o", str(tmp_path / "b.h5")]) == 0
    assert ringlube.load(tmp_path / "a.h5").energy_loss == ringlube.load(tmp_path / "b.h5").energy_loss
    assert main(["show", str(deck)]) == 0
    assert "4000.0 [r/min]" in capsys.readouterr().out
    assert ringlube.Case.from_namelist(deck)["operating", "speed_rpm"] == 4000.0


def test_serial_and_scheduler_together_are_refused_before_any_work(tmp_path, capsys):
    deck = _study(tmp_path / "m.nml")
    assert (
        main(
            [
                "optimise",
                str(deck),
                "--out",
                str(tmp_path / "o"),
                "--serial",
                "--scheduler",
                "tcp://10.0.0.1:1",
            ]
        )
        == 2
    )
    assert "--serial and --scheduler: choose one" in capsys.readouterr().err
    assert not (tmp_path / "o").exists()
    with pytest.raises(InputError, match="choose one"):
        Executor(scheduler="tcp://10.0.0.1:1", serial=True)


# --- the Python API --------------------------------------------------------------------------


def test_case_item_of_a_wrong_key_is_a_key_error_naming_the_close_match():
    case = ringlube.Case.from_namelist(COLD)
    with pytest.raises(KeyError, match=r"case\['ring_pack', name\]"):
        case["ringpack"]
    with pytest.raises(KeyError, match=r"case\['ring', 'width'\]"):
        case["width"]
    with pytest.raises(KeyError, match=r"&ring widht: not an input; did you mean case\['ring', 'width'\]"):
        case["ring", "widht"]
    assert case["ring", "width"] == 1.004e-3 and case["RING", "Width"] == 1.004e-3
    assert case["ring_pack", "gas_temperature"] is None  # an input not set: None, as before


def test_a_variable_given_twice_in_other_letter_case_is_refused():
    with pytest.raises(InputError, match=r"&ring_pack gamma: given twice \(gamma, GAMMA\)"):
        ringlube.Case().with_("ring_pack", gamma=1.3, GAMMA=1.4)
    with pytest.raises(InputError, match="given twice"):
        ringlube.Case().with_ring(width=1e-3, Width=1.1e-3)


def test_ring_pack_results_in_compare_and_a_clear_missing_result():
    base = ringlube.Case().with_numerics(nodes=31, dpsi_deg=4.0)
    plain = ringlube.run(base)
    with pytest.raises(
        AttributeError, match=r"blowby: not produced by this run \(it needs &physics ring_pack = 'gas'\)"
    ):
        getattr(plain, "blowby")  # noqa: B009
    with pytest.raises(AttributeError, match="^no_such$"):
        getattr(plain, "no_such")  # noqa: B009
    pack = ringlube.run(base.with_("physics", ring_pack="gas"))
    table = ringlube.compare([plain, pack], ["plain", "pack"])
    assert {"blowby", "ring_lift_share", "flutter_events"} <= set(table.values)
    one = ringlube.compare([plain, pack], ["plain", "pack"], names="blowby")
    assert list(one.values) == ["blowby"] and one.values["blowby"][1] == pack.blowby


def test_show_warns_of_unused_ring_pack_inputs_and_keeps_columns_apart(tmp_path, capsys):
    deck = own_inputs(tmp_path)
    deck.write_text(
        deck.read_text().replace("&operating", "&ring_pack gas_temperature = 500 /\n&operating", 1)
    )
    assert main(["show", str(deck)]) == 0
    out, err = capsys.readouterr()
    assert "&ring_pack gas_temperature is set, but &physics ring_pack = 'none'" in err
    assert "&calibration file" in out and "&calibrationfile" not in out


# --- the ring pack's edges -------------------------------------------------------------------


def test_no_gas_anywhere_is_a_defined_periodic_state():
    """No trace and no crankcase pressure: the chamber is at the crankcase's 0 Pa, the ring
    pack holds no gas and nothing in it changes (its change was 0/0 = NaN, the run 'not
    converged' after max_cycles, advising more)."""
    case = ringlube.Case().with_numerics(nodes=31, dpsi_deg=4.0).with_("physics", ring_pack="gas")
    r = ringlube.run(case.with_("operating", crankcase_pressure=0.0))
    assert r.scalars["ring_pack_change"] == 0.0 and r.converged and r.blowby == 0.0
    assert np.isfinite(list(r.scalars.values())).all()


# --- study summaries -------------------------------------------------------------------------


def test_a_surrogate_error_on_a_true_zero_is_a_difference_not_inf_or_nan():
    from ringlube.study.format import surrogate_error

    assert surrogate_error("energy_loss", 1.01, 1.0) == "+1.0%"
    assert surrogate_error("oil_to_chamber", -0.5, 0.0) == "-0.5 mm^3 (true 0)"
    assert surrogate_error("liner_lift_share", 0.0, 0.0) == "+0 % (true 0)"
    assert surrogate_error("flutter_events", 2.0, 0.0) == "+2 (true 0)"
    assert surrogate_error("energy_loss", float("nan"), 1.0) == "-"


def gas_deck(folder, extra=""):
    """The 4000 r/min hot deck with the ring pack, its trace and calibration copied to folder,
    with `extra` groups after it."""
    own_inputs(folder)
    deck = folder / "gas.nml"
    deck.write_text((INPUTS / "crf450r_4000rpm_full_hot_gas.nml").read_text() + extra)
    return deck


SEALED = "&ring_pack top_gap_area = 0, second_gap_area = 0, groove_clearance = 1e-6 /\n"


@pytest.mark.cli
def test_a_sealed_ring_pack_is_refused_by_name(tmp_path, solver, capsys):
    """No end gaps and a 1 um groove clearance: the top ring stays on its upper flank, no gas
    enters or leaves the groove and the land together, and their pressure is whatever the warm-up
    trapped (27.7 J, 28.4 J with a warm-up of 360 deg, 20.9 J at 0.25 deg; gas_balance_error
    3e287, 'converged'). Refused in every front end, naming the deck, the group and the
    inputs; nothing written."""
    deck = gas_deck(tmp_path, SEALED)
    why = r"gas\.nml: &ring_pack: a sealed ring pack: no gas reached the second land from the chamber"
    out = str(tmp_path / "r.h5")
    p = subprocess.run([solver, str(deck), "-q", "-o", out], capture_output=True, text=True)
    assert p.returncode == 2 and re.search(why, p.stderr)
    assert "top_gap_area or second_gap_area > 0" in p.stderr
    assert main(["run", str(deck), "-q", "-o", str(tmp_path / "r2.h5")]) == 2
    assert re.search(why, capsys.readouterr().err)
    with pytest.raises(InputError, match=why):
        ringlube.run(ringlube.Case.from_namelist(deck))
    assert not (tmp_path / "r.h5").exists() and not (tmp_path / "r2.h5").exists()


def test_a_land_without_end_gaps_fed_past_the_ring_is_a_result():
    """No end gaps with the default clearance: the ring leaves its upper flank and gas passes
    its flanks every cycle, so the land's pressure is a result of the cycle: it runs, and the
    warm-up does not change it."""
    case = ringlube.Case.from_namelist(INPUTS / "crf450r_4000rpm_full_hot_gas.nml").with_(
        "ring_pack", top_gap_area=0.0, second_gap_area=0.0
    )
    r = ringlube.run(case)
    assert r.converged and r.scalars["gas_exchange"] > 0 and r.gas_balance_error < 1e-12
    again = ringlube.run(case.with_numerics(warmup_deg=0.0))
    assert again.energy_loss == pytest.approx(r.energy_loss, rel=1e-3)


def test_unit_less_results_show_no_unit_1():
    """'flutter_events 1' and 'INFEASIBLE: flutter_events 1 > 0', not 'flutter_events 1 1'
    and '> 0 1'."""
    from types import SimpleNamespace as NS

    from ringlube.study.constraints import parse_constraint
    from ringlube.study.format import _feasible_text, _values, with_unit

    assert _values(["flutter_events", "energy_loss"], [1.0, 2.5]) == "flutter_events 1, energy_loss 2.5 J"
    s = NS(parsed_constraints=[parse_constraint("flutter_events <= 0")], outputs=["flutter_events"])
    study = NS(s=s, cases={"a": NS(reference=None)})
    assert _feasible_text(study, "a", np.array([1.0])) == "INFEASIBLE: flutter_events 1 > 0"
    assert with_unit("0", "1") == "0" and with_unit("3", "mg") == "3 mg"


def test_scene_weights_near_the_largest_float_do_not_overflow(tmp_path):
    """Weights of 1e308: the scene is their mean (their sum overflowed, every weight became 0
    and every scene result a 'feasible' 0, exit 0); weights beyond the float range of each
    other are refused by name."""
    from types import SimpleNamespace as NS

    from ringlube.study.deck import read_study
    from ringlube.study.runs import scene_results
    from ringlube.study.settings import StudySettings
    from ringlube.study.state import CaseState, Runs

    def runs(v):
        ones = np.ones(2, bool)
        return Runs(np.full((2, 1), v), ones, ones, ~ones, ["", ""])

    def settings(weights, **kw):
        return StudySettings(
            "s", ["a", "b"], ["a", "b"], weights, [], [], [], [], outputs=["energy_loss"], **kw
        )

    cases = {"a": CaseState(runs(1.0)), "b": CaseState(runs(3.0))}
    study = NS(s=settings([1e308, 1e308]), cases=cases)
    scene_results(study)
    np.testing.assert_array_equal(study.cases["scene"].runs.outputs, [[2.0], [2.0]])
    timed = settings([1e308, 1e308], weighting="time", cycle_rates=[1e308, 1e308])
    np.testing.assert_array_equal(timed.scene_weights(), [[0.5], [0.5]])

    deck = tmp_path / "w.nml"
    body = f"cases = '{COLD}', '{INPUTS / 'crf450r_4000rpm_full_hot.nml'}'"
    deck.write_text(f"&study {body}, weights = 1e308, 1e308 /\n")
    assert read_study(deck).weights == [1e308, 1e308]
    deck.write_text(f"&study {body}, weights = 1e308, 1e-20 /\n")
    with pytest.raises(InputError, match=r"w\.nml:\d+: &study weights: 1e-20 is 0 beside 1e\+308"):
        read_study(deck)
