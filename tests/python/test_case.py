"""The Case API and the errors that reach Python."""

from __future__ import annotations

import pytest

import ringlube
from ringlube import Case, InputError, NotConvergedError

from conftest import COLD, DECKS

pytestmark = pytest.mark.unit


@pytest.mark.parametrize("deck", DECKS, ids=lambda p: p.stem)
def test_round_trip(deck, tmp_path):
    case = Case.from_namelist(deck)
    out = tmp_path / "copy.nml"
    case.to_namelist(out)
    again = Case.from_namelist(out)
    assert again == case
    assert again.validate() == case.validate() == 360  # preset default: 2 deg steps


def test_get_set_and_variants():
    case = Case.from_namelist(COLD)
    assert case["ring", "width"] == pytest.approx(1.004e-3)
    wider = case.with_ring(width=1.2e-3)
    assert wider["ring", "width"] == 1.2e-3
    assert case["ring", "width"] == pytest.approx(1.004e-3)  # original untouched
    case["operating", "speed_rpm"] = 3000
    assert case.get("operating", "speed_rpm") == 3000
    assert case.get("ring", "no_such_thing", "dflt") == "dflt"
    # the pressure file was made absolute, so the case runs from anywhere
    assert case["operating", "pressure_file"].startswith("/")


def test_value_kept_until_the_case_or_its_files_change(tmp_path):
    """Case.value() reads every input through one kernel handle and keeps the texts: a
    change to the case or to its calibration file is still seen."""
    cal = tmp_path / "cal.nml"
    cal.write_text("&surface zeta_kappa_sigma = 0.05 /\n")
    case = Case({"calibration": {"file": str(cal)}})
    assert case.value("surface", "zeta_kappa_sigma") == 0.05
    assert case.value("ring", "width") == case.value("ring", "width")
    case["ring", "width"] = 1.5e-3
    assert case.value("ring", "width") == 1.5e-3
    cal.write_text("&surface zeta_kappa_sigma = 0.07 /\n")
    assert case.value("surface", "zeta_kappa_sigma") == 0.07
    assert case.copy().value("surface", "zeta_kappa_sigma") == 0.07
    cal.unlink()
    with pytest.raises(InputError, match="cal.nml"):
        case.value("ring", "width")


def test_empty_case_runs_on_defaults():
    r = ringlube.run(Case(name="defaults").with_numerics(nodes=31, dpsi_deg=4.0))
    assert r.energy_loss > 0 and r.converged


def test_bad_deck_raises_named_error(tmp_path):
    deck = tmp_path / "bad.nml"
    deck.write_text("&ring width = 1.0.0e-3 /\n")
    with pytest.raises(InputError, match=r"bad\.nml:1: &ring width: malformed number"):
        ringlube.run(deck)


def test_bad_value_from_python_raises_named_error(quick_case):
    with pytest.raises(
        InputError, match=r"changed in Python>:\d+: &ring width: must be in \[1.0E-5, 5.0E-2\] m, got -1.0E-3"
    ):
        ringlube.run(quick_case.with_ring(width=-1e-3))
    with pytest.raises(InputError, match=r"&physics outlet"):
        quick_case.with_physics(outlet="nowhere").validate()
    with pytest.raises(InputError, match=r"&ring widht: unknown variable"):
        quick_case.with_ring(widht=1e-3).validate()
    with pytest.raises(InputError, match=r"unknown namelist group &rings"):
        quick_case.with_("rings", width=1e-3)
    # the interpreter is still alive and the kernel still works
    assert ringlube.run(quick_case).energy_loss > 0


def test_missing_pressure_file(quick_case):
    with pytest.raises(
        InputError, match=r"&operating pressure_file: .*nothere\.csv: pressure file not found"
    ):
        ringlube.run(quick_case.with_operating(pressure_file="/nonexistent/nothere.csv"))


def test_non_convergence_fatal_only_on_request(quick_case):
    case = quick_case.with_numerics(max_cycles=1, warmup_deg=0, cycle_tol=1e-12)
    r = ringlube.run(case)
    assert not r.converged
    with pytest.raises(NotConvergedError):
        ringlube.run(case, strict=True)
