"""Reproduction of the study's Table 2 with the shipped calibration (issue 4).

The cold case is the calibration target; the hot case is a prediction. Tolerances are
those of the issue (energy within 10 %, mixed share within 3 points); where ringlube
lands is printed (pytest -s) and written in docs/validation.md.
"""

from __future__ import annotations

import numpy as np
import pytest

import ringlube
from ringlube import Case
from ringlube.calibrate import calibrate
from ringlube.trends import trend_verdicts
from ringlube.validate_compute import PUBLISHED, trend_sweeps

from conftest import INPUTS

DECKS = {"cold": INPUTS / "crf450r_4000rpm_full_cold.nml", "hot": INPUTS / "crf450r_4000rpm_full_hot.nml"}


@pytest.fixture(scope="module")
def results():
    return {k: ringlube.run(p, strict=True) for k, p in DECKS.items()}


@pytest.fixture(scope="module")
def sweeps():
    return trend_sweeps(Case.from_namelist(DECKS["cold"]))


@pytest.mark.parametrize("condition", ["cold", "hot"])
def test_table2(results, condition):
    r, p = results[condition], PUBLISHED[condition]
    de = (r.energy_loss - p["energy_loss"]) / p["energy_loss"]
    dm = r.mixed_share - p["mixed_share"]
    print(
        f"\n{condition}: energy {r.energy_loss:.3f} J vs {p['energy_loss']} ({de:+.1%}), "
        f"mixed {r.mixed_share:.2f} % vs {p['mixed_share']} ({dm:+.2f} points), "
        f"ring mass {r.ring_mass:.2f} g (study: 24 g, see docs/validation.md)"
    )
    assert abs(de) <= 0.10
    assert abs(dm) <= 3.0


def test_hot_loses_more_and_is_more_mixed(results):
    assert results["hot"].energy_loss > results["cold"].energy_loss
    assert results["hot"].mixed_share > results["cold"].mixed_share


def test_ring_mass_against_independent_integral(results):
    case = Case.from_namelist(DECKS["cold"])
    b, c, xs = (case["ring", k] for k in ("width", "crown_height", "crown_offset"))
    r0, a, rho = case["engine", "bore_radius"], case["ring", "radial_depth"], case["ring", "density"]
    x = np.linspace(-b / 2, b / 2, 200001)
    crown_area = np.trapezoid(c * (x + xs) ** 2 / (b / 2) ** 2, x)
    grams = rho * 2 * np.pi * (r0 - a / 2) * (a * b - crown_area) * 1e3
    assert results["cold"].ring_mass == pytest.approx(grams, rel=1e-9)


def test_shipped_calibration_is_the_declared_fit():
    """Re-running the declared fit on the cold case reproduces inputs/calibration.nml."""
    fit, _ = calibrate(DECKS["cold"], progress=False)
    shipped = Case.from_namelist(INPUTS / "calibration.nml")
    assert fit.zeta_kappa_sigma == pytest.approx(shipped["surface", "zeta_kappa_sigma"], rel=1e-9)
    assert fit.pressure_scale == pytest.approx(shipped["operating", "pressure_scale"], rel=1e-9)
    # the chosen modelling options are written in every deck that uses the calibration
    for deck in DECKS.values():
        case = Case.from_namelist(deck)
        for (group, name), value in fit.options.items():
            assert case[group, name] == value, (deck.name, group, name)


def test_energy_rises_with_tension(sweeps):
    assert trend_verdicts(sweeps)["tension"]


# The study's other trends, which ringlube does not reproduce: strict expected failures, so
# the disagreement stays visible in every test run and the suite notices if it goes away.
# The explanations are in docs/validation.md ("Published trends").
@pytest.mark.xfail(strict=True, reason="ringlube: energy rises with crown height (lumped contact)")
def test_energy_falls_with_crown_height(sweeps):
    assert trend_verdicts(sweeps)["crown_height"]


@pytest.mark.xfail(strict=True, reason="ringlube: a positive offset gives the lower energy")
def test_negative_offset_lowers_energy(sweeps):
    assert trend_verdicts(sweeps)["crown_offset"]


@pytest.mark.xfail(strict=True, reason="ringlube: energy rises monotonically with width")
def test_interior_optimum_in_width(sweeps):
    assert trend_verdicts(sweeps)["width"]
