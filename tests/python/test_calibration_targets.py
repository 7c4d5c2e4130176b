"""`ringlube calibrate` with an engine test's targets: the friction as energy per cycle,
mean friction power or FMEP, and the mixed share optional (no engine test measures it)."""

from __future__ import annotations

import math
import shutil

import pytest

import ringlube
from ringlube import Case, InputError
from ringlube.calibrate import calibrate, cold_targets
from ringlube.cli import main

from conftest import INPUTS

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


def _targets(folder, rows: str):
    path = folder / "t.csv"
    path.write_text("condition,deck,quantity,value,unit\n" + rows)
    return path


def test_the_friction_alone_fits_zeta_kappa_sigma_alone(deck, capsys):
    """Energy per cycle alone: one input fitted (zeta_kappa_sigma), pressure_scale and the
    modelling options the deck's own; the file holds zeta_kappa_sigma alone, and the deck run
    with it has the target energy (1.8e-8 apart measured)."""
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
    assert ringlube.run(case).energy_loss == pytest.approx(1.8, rel=1e-6)


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
    assert other.energy_loss == pytest.approx(1.8, rel=1e-6)


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
