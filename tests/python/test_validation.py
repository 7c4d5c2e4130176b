"""Reproduction of the study's Table 2 with the shipped calibration.

The cold case is the calibration target; the hot case is a prediction. Tolerances are
those of the issue (energy within 10 %, mixed share within 3 points); where ringlube
lands is printed (pytest -s) and written in docs/validation.md. The shipped decks read the
tension in N; the tension read in N/m, with its own calibration file, is checked beside.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import ringlube
from ringlube import Case
from ringlube.calibrate import calibrate
from ringlube.trends import trend_verdicts
from ringlube.validate.compute import PUBLISHED, trend_sweeps

from conftest import INPUTS, PER_LENGTH_CALIBRATION, per_length

pytestmark = pytest.mark.numerics

DECKS = {"cold": INPUTS / "crf450r_4000rpm_full_cold.nml", "hot": INPUTS / "crf450r_4000rpm_full_hot.nml"}
#: The calibration file of each reading of the tension (the shipped decks read it in N).
CALIBRATIONS = {"N": INPUTS / "calibration.nml", "N/m": PER_LENGTH_CALIBRATION}


@pytest.fixture(scope="module")
def results():
    return {k: ringlube.run(p, strict=True) for k, p in DECKS.items()}


@pytest.fixture(scope="module")
def results_per_length():
    return {k: ringlube.run(per_length(p), strict=True) for k, p in DECKS.items()}


def _table2(r, condition: str) -> tuple[float, float]:
    """(relative energy error, mixed-share error in points) against Table 2, printed."""
    p = PUBLISHED[condition]
    de = (r.energy_loss - p["energy_loss"]) / p["energy_loss"]
    dm = r.mixed_share - p["mixed_share"]
    print(
        f"\n{condition}: energy {r.energy_loss:.3f} J vs {p['energy_loss']} ({de:+.1%}), "
        f"mixed {r.mixed_share:.2f} % vs {p['mixed_share']} ({dm:+.2f} points), "
        f"ring mass {r.ring_mass:.2f} g (study: 24 g, see docs/validation.md)"
    )
    return de, dm


@pytest.fixture(scope="module")
def sweeps():
    return trend_sweeps(Case.from_namelist(DECKS["cold"]))


def test_table2_cold(results):
    de, dm = _table2(results["cold"], "cold")
    assert abs(de) <= 0.10
    assert abs(dm) <= 3.0


# The hot prediction with the tension read in N (the shipped decks): a strict expected failure,
# so the disagreement stays visible and the suite notices if it goes away (docs/validation.md,
# "The two readings of the tension"; docs/model.md, "Load balance").
@pytest.mark.known_limitation
@pytest.mark.xfail(
    strict=True, reason="read in N the hot mixed share is about 27 % against 12.5 % and the energy -13 %"
)
def test_table2_hot(results):
    de, dm = _table2(results["hot"], "hot")
    assert abs(de) <= 0.10
    assert abs(dm) <= 3.0


@pytest.mark.parametrize("condition", ["cold", "hot"])
def test_table2_with_the_tension_read_in_n_per_m(results_per_length, condition):
    """The tension read in N/m with its own calibration: the reading that matches Table 2's hot
    case (the prediction) best."""
    de, dm = _table2(results_per_length[condition], condition)
    assert abs(de) <= 0.10
    assert abs(dm) <= 3.0


@pytest.mark.parametrize("which", ["shipped", "per_length"])
def test_hot_loses_more_and_is_more_mixed(results, results_per_length, which):
    r = results if which == "shipped" else results_per_length
    assert r["hot"].energy_loss > r["cold"].energy_loss
    assert r["hot"].mixed_share > r["cold"].mixed_share


def test_ring_mass_against_independent_integral(results):
    case = Case.from_namelist(DECKS["cold"])
    b, c, xs = (case["ring", k] for k in ("width", "crown_height", "crown_offset"))
    r0, a, rho = case["engine", "bore_radius"], case["ring", "radial_depth"], case["ring", "density"]
    x = np.linspace(-b / 2, b / 2, 200001)
    crown_area = np.trapezoid(c * (x + xs) ** 2 / (b / 2) ** 2, x)
    grams = rho * 2 * np.pi * (r0 - a / 2) * (a * b - crown_area) * 1e3
    assert results["cold"].ring_mass == pytest.approx(grams, rel=1e-9)


@pytest.mark.slow
def test_shipped_calibration_is_the_declared_fit():
    """Re-running the declared fit on the cold case reproduces inputs/calibration.nml (the
    tension read in N, the decks' unit) and inputs/calibration_n_per_m.nml (read in N/m)."""
    chosen = {}
    for unit, path in CALIBRATIONS.items():
        fit, fits = calibrate(DECKS["cold"], progress=False, tension_unit=None if unit == "N" else unit)
        chosen[unit] = fit
        assert fit.options[("ring", "tension_unit")] == unit
        assert {f.options[("ring", "tension_unit")] for f in fits} == {"N", "N/m"}
        shipped = Case.from_namelist(path)
        assert fit.zeta_kappa_sigma == pytest.approx(shipped["surface", "zeta_kappa_sigma"], rel=1e-9)
        assert fit.pressure_scale == pytest.approx(shipped["operating", "pressure_scale"], rel=1e-9)
        assert f"tension read in '{unit}'" in path.read_text().splitlines()[0]
    # the chosen modelling options are written in every deck that uses the calibration
    fit = chosen["N"]
    for deck in sorted(INPUTS.glob("crf450r_*.nml")):
        case = Case.from_namelist(deck)
        assert Path(case["calibration", "file"]) == CALIBRATIONS["N"], deck.name
        for (group, name), value in fit.options.items():
            assert case[group, name] == value, (deck.name, group, name)


def test_energy_rises_with_tension(sweeps):
    assert trend_verdicts(sweeps)["tension"]


# The study's other trends, which ringlube does not reproduce: strict expected failures, so
# the disagreement stays visible in every test run and the suite notices if it goes away.
# The explanations are in docs/validation.md ("Published trends").
@pytest.mark.xfail(strict=True, reason="ringlube: energy rises with crown height (lumped contact)")
@pytest.mark.known_limitation
def test_energy_falls_with_crown_height(sweeps):
    assert trend_verdicts(sweeps)["crown_height"]


@pytest.mark.xfail(strict=True, reason="ringlube: a positive offset gives the lower energy")
@pytest.mark.known_limitation
def test_negative_offset_lowers_energy(sweeps):
    assert trend_verdicts(sweeps)["crown_offset"]


@pytest.mark.xfail(strict=True, reason="ringlube: energy rises monotonically with width")
@pytest.mark.known_limitation
def test_interior_optimum_in_width(sweeps):
    assert trend_verdicts(sweeps)["width"]
