"""Hostile inputs through Python: every physical input has a plausible range,
the problem size is bounded, non-ASCII names work, relative paths resolve where documented,
error locations are true, and run_many keeps the good results of a batch with a bad case.
Each case failed (crash, NaN with exit 0, wrong file or line, lost results) before the fix."""

from __future__ import annotations

import os

import numpy as np
import pytest

import ringlube
from ringlube import BatchError, Case, InputError
from ringlube.tables import FLAGS, INPUTS

from conftest import COLD, INPUTS as INPUT_DIR

pytestmark = pytest.mark.numerics

FAST = {"nodes": 31, "dpsi_deg": 4.0}


@pytest.fixture()
def base() -> Case:
    return Case(name="hostile").with_numerics(**FAST)


@pytest.mark.parametrize(
    "group, values, variable",
    [
        ("ring", {"width": 1e300}, "&ring width"),  # was SIGSEGV (NaN lambda)
        ("ring", {"width": 1e-200}, "&ring width"),
        ("surface", {"rq_liner": 1e-200, "rq_ring": 1e-200}, "&surface rq_liner"),  # was NaN, exit 0
        ("operating", {"speed_rpm": 4.9e-324}, "&operating speed_rpm"),
        ("ring", {"density": 1e308}, "&ring density"),
        ("numerics", {"dpsi_deg": 1e-5}, "&numerics dpsi_deg"),  # 7.2e7 steps: allocation died
        ("numerics", {"nodes": 10**7}, "&numerics nodes"),
        ("lubricant", {"eta0": 1e-9}, "&lubricant eta0"),
        ("operating", {"liner_temperature": 1e9}, "&operating liner_temperature"),
    ],
    ids=lambda v: str(v),
)
def test_out_of_range_is_a_named_input_error(base, group, values, variable):
    case = base.with_(group, **values)
    with pytest.raises(InputError, match=f"{variable}: must be in "):
        case.validate()
    with pytest.raises(InputError, match=f"{variable}: must be in "):
        ringlube.run(case)


def test_every_real_input_has_a_finite_plausible_range():
    for (g, n), spec in INPUTS.items():
        if spec.kind in ("real", "integer"):
            assert np.isfinite(spec.lower) and np.isfinite(spec.upper), (g, n)
            assert spec.lower <= spec.upper < 1e20, (g, n)
            assert spec.unit, f"&{g} {n} has no unit"


def test_zero_load_gives_finite_flagged_result(base):
    """No tension, no gas, crankcase at 0 Pa: the applied load is 0 and the relative load
    residual used to be NaN everywhere (exit 0). Now finite, h0 held at the ceiling and flagged."""
    r = ringlube.run(base.with_ring(tension=0.0).with_operating(crankcase_pressure=0.0))
    assert np.isfinite(r.load_residual).all() and np.isfinite(r.friction).all()
    assert np.isfinite(r.energy_loss)
    # lift-off: held at h0_ceiling and flagged (an answer, not a failure)
    assert (r.flags & FLAGS["h0_ceiling"]).any()


def test_non_ascii_paths_and_names(tmp_path):
    """A deck in a folder and file with non-ASCII names, and a non-ASCII case name, used to
    break the f2py call (TypeError)."""
    folder = tmp_path / "ringlübe-Ölfilm"
    folder.mkdir()
    deck = folder / "kolbenring-é.nml"
    Case.from_namelist(COLD).with_numerics(**FAST).to_namelist(deck)
    r = ringlube.run(deck)
    assert r.converged and r.deck_path == str(deck)
    assert ringlube.run(Case(name="Kolbenring-ü").with_numerics(**FAST)).converged
    bad = Case(name="défaut").with_numerics(**FAST).with_ring(width=-1.0)
    with pytest.raises(InputError, match="<case défaut: changed in Python>|<case défaut>"):
        ringlube.run(bad)


def test_relative_pressure_file_of_a_python_case_resolves_against_cwd(tmp_path, monkeypatch):
    """It used to resolve against the temporary deck's folder, and silently used a file
    found there. A relative path set in Python means the working directory when it is set."""
    trace = INPUT_DIR / "pressure" / "crf450r_4000rpm_full.csv"
    (tmp_path / "p.csv").write_bytes(trace.read_bytes())
    monkeypatch.chdir(tmp_path)
    case = Case(name="rel").with_numerics(**FAST).with_operating(pressure_file="p.csv")
    assert case["operating", "pressure_file"] == os.path.join(str(tmp_path), "p.csv")
    r = ringlube.run(case)
    assert r.pressure_file == os.path.join(str(tmp_path), "p.csv")
    assert r.gas_pressure.max() > 10e5
    other = tmp_path / "elsewhere"
    other.mkdir()
    monkeypatch.chdir(other)
    assert ringlube.run(case).energy_loss == r.energy_loss  # still the file set above
    late = Case(name="rel").with_numerics(**FAST).with_operating(pressure_file="p.csv")
    with pytest.raises(InputError, match=r"&operating pressure_file: .*elsewhere/p\.csv"):
        ringlube.run(late)


def test_error_locations_name_the_real_file_and_line(tmp_path):
    deck = tmp_path / "deck.nml"
    deck.write_text("! comment\n&ring width = 1e-3,\n  tension = eight /\n")
    with pytest.raises(InputError, match=r"deck\.nml:3: &ring tension: malformed number"):
        Case.from_namelist(deck)
    deck.write_text("! comment\n&ring width = 1e-3 /\n&numerics nodes = 31, dpsi_deg = 4 /\n")
    case = Case.from_namelist(deck)
    with pytest.raises(InputError, match=r"<case deck: changed in Python>:\d+: &ring crown_offset"):
        ringlube.run(case.with_ring(crown_offset=1.0))
    # the unchanged deck's relation errors name the deck file itself, and the line
    deck.write_text("&ring width = 1e-3, crown_offset = 0.9e-3 /\n")
    with pytest.raises(InputError, match=rf"{deck}:1: &ring crown_offset: must lie inside"):
        Case.from_namelist(deck)


def test_run_many_keeps_good_results_and_names_the_bad_case(base):
    cases = [base, base.with_ring(width=-1.0), base.with_ring(crown_offset=10e-6)]
    with pytest.raises(BatchError, match=r"1 of 3 cases failed \(first: case 1:") as info:
        ringlube.run_many(cases, workers=2, progress=False)
    results, errors = info.value.results, info.value.errors
    assert list(errors) == [1] and isinstance(errors[1], InputError)
    assert results[1] is None and results[0].converged and results[2].converged
    out = ringlube.run_many(cases, workers=1, progress=False, on_error="return")
    assert isinstance(out[1], InputError) and out[0].energy_loss == results[0].energy_loss
    with pytest.raises(ValueError, match="workers must be at least 1"):
        ringlube.run_many(cases, workers=-2)


def test_batch_of_designs_equals_single_runs(base):
    x = np.array([[0.8e-3, 8e-6], [1.2e-3, 12e-6], [-1.0, 9e-6]])
    values, converged, errors = ringlube.run_designs(
        base, ["width", "crown_height"], x, ["energy_loss", "mixed_share"]
    )
    for i in (0, 1):
        r = ringlube.run(base.with_ring(width=x[i, 0], crown_height=x[i, 1]))
        assert values[i].tolist() == [r.energy_loss, r.mixed_share]
        assert converged[i] and errors[i] is None
    assert np.isnan(values[2]).all() and "&ring width: must be in" in errors[2]


def test_tension_unit_is_visible_in_the_shipped_decks():
    """The decks say what their tension means (it used to come silently from the
    calibration file), and the calibration file holds fitted inputs only."""
    for deck in sorted(INPUT_DIR.glob("crf450r_*.nml")):
        case = Case.from_namelist(deck)
        assert case.get("ring", "tension_unit") in ("N", "N/m"), deck.name
    calibration = Case.from_namelist(INPUT_DIR / "calibration.nml").to_dict()
    assert set(calibration) <= {"surface", "operating"}


def test_trace_passed_as_arrays_equals_the_file(base):
    """The pressure trace can reach the kernel as arrays (no file), checked like a file."""
    case = Case.from_namelist(COLD).with_numerics(**FAST)
    psi, p = ringlube.gas.read_csv(INPUT_DIR / "pressure" / "crf450r_4000rpm_full.csv")
    a, b = ringlube.run(case), ringlube.run(case, trace=(psi, p))
    np.testing.assert_array_equal(a.h0, b.h0)
    assert b.pressure_file == "<array>"
    with pytest.raises(InputError, match=r"pressure trace: .*must span at least 700"):
        ringlube.run(case, trace=(psi[:50], p[:50]))
