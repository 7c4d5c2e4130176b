"""`ringlube calibrate` with an engine test's targets: the friction as energy per cycle,
mean friction power or FMEP, and the mixed share optional (no engine test measures it)."""

from __future__ import annotations

import math
import shutil

import pytest

import ringlube
from ringlube import Case, InputError
from ringlube.calibrate import Fit, calibrate, choose, cold_targets
from ringlube.cli import main

from conftest import INPUTS

pytestmark = [pytest.mark.unit, pytest.mark.cli]

#: swept volume of the CRF450R [m^3] (bore 96 mm, stroke 63 mm), worked out here
SWEPT = math.pi / 4 * 0.096**2 * 0.063


@pytest.fixture()
def deck(tmp_path):
    """The cold deck at the 'fast' preset beside copies of its calibration file and trace."""
    (tmp_path / "pressure").mkdir()
    shutil.copy(INPUTS / "pressure" / "crf450r_4000rpm_full.csv", tmp_path / "pressure")
    shutil.copy(INPUTS / "calibration.nml", tmp_path)
    text = (INPUTS / "crf450r_4000rpm_full_cold.nml").read_text()
    assert "preset = 'default'" in text
    path = tmp_path / "cold.nml"
    path.write_text(text.replace("preset = 'default'", "preset = 'fast'"))
    return path


def _within_brent(case: Case, energy: float, target: float) -> bool:
    """Whether a fitted run's energy is within what the fit's Brent tolerance on
    zeta_kappa_sigma (xtol 1e-5 + rtol 1e-6 of it) allows: that tolerance times the energy's
    slope in zeta_kappa_sigma, measured here by a central difference."""
    z = case.value("surface", "zeta_kappa_sigma")
    lo, hi = (ringlube.run(case.with_("surface", zeta_kappa_sigma=z + d)).energy_loss for d in (-1e-3, 1e-3))
    return abs(energy - target) <= abs(hi - lo) / 2e-3 * (1e-5 + 1e-6 * z)


def _targets(folder, rows: str):
    path = folder / "t.csv"
    path.write_text("condition,deck,quantity,value,unit\n" + rows)
    return path


def test_the_friction_alone_fits_zeta_kappa_sigma_alone(deck, capsys):
    """Energy per cycle alone: one input fitted (zeta_kappa_sigma), pressure_scale and the
    modelling options the deck's own; the file holds zeta_kappa_sigma alone, and the deck run
    with it has the target energy within the fit's tolerance (1.2e-5 relative measured)."""
    targets = _targets(deck.parent, "cold,cold.nml,energy_loss,1.8,J\ncold,cold.nml,ring_mass,24,g\n")
    out = deck.parent / "mine.nml"
    assert main(["calibrate", str(deck), "--targets", str(targets), "--out", str(out)]) == 0
    said = capsys.readouterr().out
    assert "chosen: {'zeta_kappa_sigma': " in said and "(target 1.8 J), one fitted input" in said
    text = out.read_text()
    assert "&surface   zeta_kappa_sigma = " in text and "pressure_scale =" not in text
    assert "One target fits one input: pressure_scale (1) and the modelling options" in text
    fitted = Case.from_namelist(out)["surface", "zeta_kappa_sigma"]
    assert 0.02 < fitted < 0.1
    case = Case.from_namelist(deck).with_("calibration", file=str(out))
    assert case.value("operating", "pressure_scale") == 1.0
    assert _within_brent(case, ringlube.run(case).energy_loss, 1.8)


@pytest.mark.parametrize(
    "row",
    [
        f"cold,cold.nml,fmep,{1.8 / SWEPT / 1e3!r},kPa",  # FMEP = E / Vd
        f"cold,cold.nml,friction_power,{1.8 * 4000 / 120!r},W",  # P = E n / 120 (four-stroke)
    ],
)
def test_fmep_or_friction_power_is_the_same_target(deck, row):
    """The same friction given as FMEP or as friction power (converted here from 1.8 J per
    cycle) fits the same zeta_kappa_sigma: the residuals are proportional, so Brent's method
    takes the same steps (3e-16 apart measured)."""
    energy = _targets(deck.parent, "cold,cold.nml,energy_loss,1.8,J\n")
    by_energy, fits = calibrate(deck, progress=False, targets=energy)
    assert len(fits) == 1 and by_energy.fitted == ("zeta_kappa_sigma",)
    other, _ = calibrate(deck, progress=False, targets=_targets(deck.parent, row + "\n"))
    assert other.zeta_kappa_sigma == pytest.approx(by_energy.zeta_kappa_sigma, rel=1e-9)
    case = Case.from_namelist(deck).with_("calibration", file="")
    case = case.with_("surface", zeta_kappa_sigma=other.zeta_kappa_sigma)
    assert _within_brent(case, other.energy_loss, 1.8)


def test_the_mixed_share_keeps_the_two_input_fit(deck):
    """With the mixed share the targets are two and both inputs are fitted, as before."""
    targets = _targets(deck.parent, "cold,cold.nml,fmep,4.2,kPa\ncold,cold.nml,mixed_share,8.47,%\n")
    assert cold_targets(targets)[1] == {"fmep": 4.2, "mixed_share": 8.47}


@pytest.mark.parametrize(
    "rows, message",
    [
        ("cold,cold.nml,mixed_share,8.47,%\n", "lacks its friction: energy_loss (J per cycle), friction"),
        (
            "cold,cold.nml,energy_loss,1.8,J\ncold,cold.nml,fmep,4,kPa\n",
            "gives the friction twice (energy_loss, fmep); keep one row",
        ),
        ("cold,cold.nml,friction_power,-3,W\n", "friction_power = -3: must not be negative"),
    ],
)
def test_targets_that_cannot_be_fitted_are_refused(deck, rows, message, capsys):
    targets = _targets(deck.parent, rows)
    with pytest.raises(InputError, match=message.replace("(", r"\(").replace(")", r"\)")):
        cold_targets(targets)
    out = deck.parent / "c.nml"
    assert main(["calibrate", str(deck), "--targets", str(targets), "--out", str(out)]) == 2
    assert message in capsys.readouterr().err and not out.exists()


# --- the tension unit: the deck's, not fitted -------------------------------------------------


def test_the_tension_unit_is_the_decks_and_the_other_units_fits_are_listed(deck, capsys):
    """The fit keeps the deck's tension unit ('N', the shipped decks') or --tension-unit's, and
    chooses the contact area and the outlet among that unit's fits; every unit's fits are made
    and written, that unit's first; the file names its command."""
    fit, fits = calibrate(deck, progress=False)
    assert Case.from_namelist(deck).value("ring", "tension_unit") == "N"
    assert fit.options[("ring", "tension_unit")] == "N" and len(fits) == 8
    assert fit is min((f for f in fits if f.options[("ring", "tension_unit")] == "N"), key=lambda f: f.score)
    out = deck.parent / "per_length.nml"
    assert main(["calibrate", str(deck), "--tension-unit", "N/m", "--out", str(out)]) == 0
    assert "'ring.tension_unit': 'N/m'" in capsys.readouterr().out
    lines = out.read_text().splitlines()
    assert lines[0].endswith("tension read in 'N/m'.")
    assert lines[1] == f"! Regenerate: ringlube calibrate {deck} --tension-unit N/m --out {out}"
    listed = [line for line in lines if line.startswith("!   tension_unit=")]
    assert len(listed) == 8 and all("N/m" in line for line in listed[:4])
    assert not any("tension_unit=N/m" in line for line in listed[4:])
    with pytest.raises(SystemExit) as stop:
        main(["calibrate", str(deck), "--tension-unit", "kN", "--out", str(out)])
    assert stop.value.code == 2 and "invalid choice: 'kN'" in capsys.readouterr().err


def test_the_choice_is_scored_in_units_of_the_goal():
    """Energy 5 % or mixed share 1.5 points off weigh the same: of a fit with the energy exact
    and the mixed share 1.49 points off (relative residual 0.176) and one with the mixed share
    exact and the energy 11 % off (0.112), the first is chosen (score 0.99 against 2.2)."""
    t = {"energy_loss": 1.92, "mixed_share": 8.47}
    unit = {("ring", "tension_unit"): "N"}
    a = Fit(dict(unit), 0.0956, 0.8, 1.92, 8.47 + 1.49, 1, False, t)
    b = Fit(dict(unit), 0.1, 0.85, 1.92 * 0.888, 8.47, 1, False, t)
    assert b.residual < a.residual and a.score == pytest.approx(1.49 / 1.5)
    assert b.score == pytest.approx(0.112 / 0.05)
    assert choose([b, a], "N") is a
    c = Fit({("ring", "tension_unit"): "N/m"}, 0.1, 0.93, 1.92, 8.47, 1, True, t)
    assert choose([a, b, c], "N") is a and choose([a, b, c], "N/m") is c
