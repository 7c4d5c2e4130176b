"""The oil from a data sheet (``&lubricant kv40, kv100`` with ``oil_density``) or an SAE
J300 grade (``grade``): the kernel's Roelands law put through the two kinematic
viscosities, which it returns exactly; a grade's viscosities against the standard."""

from __future__ import annotations

import math

import numpy as np
import pytest

import ringlube
from ringlube import oil
from ringlube.errors import InputError

from conftest import COLD

pytestmark = [pytest.mark.unit, pytest.mark.numerics]

#: SAE J300 (2015-01): kinematic viscosity at 100 degC [mm^2/s] of the high-temperature
#: grades, min up to below max
J300 = {20: (6.9, 9.3), 30: (9.3, 12.5), 40: (12.5, 16.3), 50: (16.3, 21.9), 60: (21.9, 26.1)}
#: ASTM D2270 table 1: H [mm^2/s] at kinematic viscosities at 100 degC [mm^2/s]
D2270_H = {8.1: 60.74, 10.9: 93.92, 14.4: 141.0, 19.1: 214.4, 24.0: 301.8}


def viscosity_index(kv40: float, kv100: float) -> float:
    """ASTM D2270: procedure A below VI 100, procedure B above (H from the table)."""
    h = D2270_H[round(kv100, 1)]
    if kv40 >= h:  # VI <= 100: (L - U)/(L - H) 100, here only at U = H
        assert kv40 == pytest.approx(h, rel=1e-12)
        return 100.0
    n = (math.log10(h) - math.log10(kv40)) / math.log10(kv100)
    return (10**n - 1) / 0.00715 + 100


@pytest.mark.parametrize(
    "kv40, kv100, rho",
    [(61.0, 10.4, 850.0), (44.0, 8.4, 840.0), (150.0, 17.0, 880.0), (25.0, 5.2, 820.0), (320.0, 24.0, 900.0)],
)
def test_the_fit_returns_the_data_sheet_viscosities(kv40, kv100, rho):
    # The law at p = 0 passes through (theta0, eta0) for every s0, and s0 puts it through
    # the second point: both come back to round-off. The tolerance, 1e-14, is a few units
    # in the last place of the exp/log pairs that evaluate the law (each contributes about
    # 1e-16 relative, times ln(eta) + 9.67 ~ 5 for the second point's exponent).
    case = ringlube.Case({"lubricant": {"kv40": kv40, "kv100": kv100, "oil_density": rho}})
    nu = oil.kinematic_viscosity(case, [313.15, 373.15])
    assert nu[0] == pytest.approx(kv40, rel=1e-14)
    assert nu[1] == pytest.approx(kv100, rel=1e-14)
    assert case.value("lubricant", "theta0") == 313.15
    assert case.value("lubricant", "eta0") == pytest.approx(kv40 * 1e-6 * rho, rel=1e-15)


def deck_with_oil(tmp_path, oil_text: str):
    """The cold deck with `oil_text` in place of eta0, theta0 and beta (paths absolute)."""
    law = "eta0 = 0.05, theta0 = 313.15, beta = 0.04, alpha = 1e-8 /"
    text = COLD.read_text()
    assert law in text
    deck = tmp_path / "oil.nml"
    deck.write_text(
        text.replace(law, f"alpha = 1e-8, {oil_text} /")
        .replace("'calibration.nml'", f"'{COLD.parent}/calibration.nml'")
        .replace("pressure/", f"{COLD.parent}/pressure/")
    )
    return ringlube.Case.from_namelist(deck).with_numerics(nodes=41)


def test_a_data_sheet_of_the_default_law_gives_the_default_law_back(tmp_path):
    # the source study's eta0, beta through its own viscosities at 40 and 100 degC: the fit
    # recovers beta (eta0 is the 40 degC point itself) and the run is the default run's to
    # round-off (beta to 1e-14: through two logs of the viscosity ratio)
    default = ringlube.Case.from_namelist(COLD).with_numerics(nodes=41)
    eta = oil.viscosity(default, [313.15, 373.15])
    rho = default.value("lubricant", "oil_density")
    kv40, kv100 = (float(e) / rho * 1e6 for e in eta)
    fitted = deck_with_oil(tmp_path, f"kv40 = {kv40!r}, kv100 = {kv100!r}")
    assert fitted.value("lubricant", "beta") == pytest.approx(0.04, rel=1e-13)
    assert fitted.value("lubricant", "eta0") == pytest.approx(0.05, rel=1e-15)
    a, b = ringlube.run(default), ringlube.run(fitted)
    np.testing.assert_allclose(b.h0, a.h0, rtol=1e-9)
    assert b.energy_loss == pytest.approx(a.energy_loss, rel=1e-9)


GRADES = ["0W-20", "5W-30", "10W-30", "5W-40", "15W-40", "20W-50", "30", "40", "25W-60"]


@pytest.mark.parametrize("name", GRADES)
def test_grade_values_lie_in_their_cited_windows(name):
    # the kinematic viscosity at 100 degC in the grade's SAE J300 window (its centre), and at
    # 40 degC the viscosity index the grade assumes (160 multigrade, 100 straight grade) by
    # ASTM D2270, computed here from the kernel's law
    g = oil.grade(name)
    lo, hi = J300[int(name.split("-")[-1])]
    assert (g.kv100_min, g.kv100_max) == (lo, hi)
    case = ringlube.Case({"lubricant": {"grade": name}})
    nu40, nu100 = oil.kinematic_viscosity(case, [313.15, 373.15])
    assert lo <= nu100 < hi and nu100 == pytest.approx((lo + hi) / 2, rel=1e-14)
    assert nu40 == pytest.approx(g.kv40, rel=1e-14)
    vi = viscosity_index(nu40, round(nu100, 12))
    assert vi == pytest.approx(160.0 if "W" in name else 100.0, abs=1e-9)


def test_a_grade_changes_the_run_and_is_recorded(tmp_path):
    base = ringlube.Case.from_namelist(COLD).with_numerics(nodes=41)
    graded = deck_with_oil(tmp_path, "grade = '5W-30'")
    r = ringlube.run(graded, output=tmp_path / "graded.h5")
    # a 5W-30 at the liner temperature is thicker than the source study's oil
    assert oil.viscosity(graded, 348.0)[0] > oil.viscosity(base, 348.0)[0]
    assert r.energy_loss != ringlube.run(base).energy_loss
    import h5py

    with h5py.File(tmp_path / "graded.h5") as f:
        assert f.attrs["lubricant.grade"] in (b"5W-30", "5W-30")
        assert f.attrs["lubricant.eta0"] == pytest.approx(graded.value("lubricant", "eta0"), rel=0)
        assert f.attrs["lubricant.theta0"] == 313.15


def test_oil_mistakes_are_named(tmp_path):
    case = ringlube.Case({"lubricant": {"grade": "5W-30", "kv40": 60.0, "kv100": 10.0}})
    with pytest.raises(InputError, match=r"&lubricant grade: and the data sheet's kv40, kv100 are both"):
        case.validate()
    with pytest.raises(InputError, match=r"&lubricant kv100: must be given with kv40"):
        ringlube.Case({"lubricant": {"kv40": 60.0}}).validate()
    with pytest.raises(InputError, match=r"&lubricant kv40: must be given with kv100"):
        ringlube.Case({"lubricant": {"kv100": 10.0}}).validate()
    with pytest.raises(InputError, match=r"&lubricant kv40: must exceed kv100"):
        ringlube.Case({"lubricant": {"kv40": 10.0, "kv100": 12.0}}).validate()
    with pytest.raises(InputError, match=r"&lubricant grade: '5W-35' is not an SAE J300 engine-oil grade"):
        ringlube.Case({"lubricant": {"grade": "5W-35"}}).validate()
    with pytest.raises(InputError, match=r"&lubricant grade: '7W-30' is not"):
        oil.grade("7W-30")
    # one source of the viscosity law: eta0, theta0, beta or the oil data, named at the line
    deck = tmp_path / "both.nml"
    deck.write_text("&lubricant eta0 = 0.05,\n  kv40 = 60, kv100 = 10 /\n")
    with pytest.raises(InputError, match=r"both\.nml:1: &lubricant eta0: set together with the oil.s kv40"):
        ringlube.Case.from_namelist(deck)
    deck.write_text("&lubricant grade = '10W-40',\n  beta = 0.03 /\n")
    with pytest.raises(InputError, match=r"both\.nml:2: &lubricant beta: set together with the oil's grade"):
        ringlube.Case.from_namelist(deck)
    # a design may not vary what the oil data replace
    graded = ringlube.Case({"lubricant": {"grade": "5W-30"}}).with_numerics(nodes=31, dpsi_deg=4.0)
    values, _, errors = ringlube.run_designs(graded, ["lubricant:eta0"], [[0.06]], ["energy_loss"])
    assert np.isnan(values[0, 0])
    assert "&lubricant eta0: the case takes its viscosity from the oil's grade" in errors[0]
