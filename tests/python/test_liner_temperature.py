"""A liner temperature that varies along the stroke: ``&operating liner_temperature_top``
and ``liner_temperature_bottom``, linear in the ring's position between TDC and BDC; the film
takes the viscosity of the liner temperature where the ring is, step by step."""

from __future__ import annotations

import numpy as np
import pytest

import ringlube
from ringlube.errors import InputError

from conftest import COLD

pytestmark = pytest.mark.numerics

SERIES = ("h0", "friction", "hydrodynamic_load", "asperity_load", "power_loss", "film_temperature")


@pytest.fixture(scope="module")
def base():
    return ringlube.Case.from_namelist(COLD).with_numerics(nodes=41, dpsi_deg=2.0)


def same(a, b, rtol):
    for name in SERIES:
        want = getattr(b, name)
        atol = rtol * np.max(np.abs(want))
        np.testing.assert_allclose(getattr(a, name), want, rtol=0, atol=atol, err_msg=name)
    assert a.energy_loss == pytest.approx(b.energy_loss, rel=rtol)


def test_a_uniform_profile_is_the_single_temperature(base):
    # both ends at the single temperature: the law at every step is the one of that temperature
    # (T_top + 0 x s/(2r) is T_top exactly), so the run is the single temperature's to the last
    # bit; both ends at another temperature T: the run at liner_temperature = T, to round-off
    # (the first step switches the law from liner_temperature's to T's and recomputes the held
    # viscosity, which is then what a run at T holds: in fact the same bits here)
    t = base.value("operating", "liner_temperature")
    single = ringlube.run(base)
    both_ends = base.with_operating(liner_temperature_top=t, liner_temperature_bottom=t)
    same(ringlube.run(both_ends), single, rtol=0)
    assert np.all(single.film_temperature == t)
    hotter = ringlube.run(base.with_operating(liner_temperature=t + 20))
    both = ringlube.run(base.with_operating(liner_temperature_top=t + 20, liner_temperature_bottom=t + 20))
    same(both, hotter, rtol=1e-12)


def test_the_film_temperature_follows_the_ring(base):
    # the series against the linear profile in the piston position (slider-crank, here)
    top, bottom = 390.0, 350.0
    r = ringlube.run(base.with_operating(liner_temperature_top=top, liner_temperature_bottom=bottom))
    rc, lc = base.value("engine", "crank_radius"), base.value("engine", "conrod_length")
    psi = np.radians(r.crank_angle_deg)
    s = rc * (1 - np.cos(psi)) + lc - np.sqrt(lc**2 - (rc * np.sin(psi)) ** 2)
    np.testing.assert_allclose(r.film_temperature, top + (bottom - top) * s / (2 * rc), rtol=1e-14)
    assert r.film_temperature[0] == top and r.film_temperature[90] == pytest.approx(bottom, rel=1e-15)


def test_each_step_runs_at_the_liner_temperature_where_the_ring_is(base):
    # Without the squeeze term a step has no memory: its h0 balances the load at that step
    # alone. So the profile's run at step k is the uniform run at the film temperature of
    # step k, at step k (the load and pressure loops converged far below the differences
    # that matter: load_tol 1e-10, pressure_tol 1e-12; agreement to 1e-7 of h0).
    quasi = base.with_physics(squeeze=False).with_numerics(load_tol=1e-10, pressure_tol=1e-12)
    top, bottom = 400.0, 340.0
    r = ringlube.run(quasi.with_operating(liner_temperature_top=top, liner_temperature_bottom=bottom))
    for k in (10, 60, 120, 200, 290, 340):
        t = r.film_temperature[k]
        u = ringlube.run(quasi.with_operating(liner_temperature=t))
        assert r.h0[k] == pytest.approx(u.h0[k], rel=1e-7), k
        assert r.friction[k] == pytest.approx(u.friction[k], rel=1e-6, abs=1e-9), k
    # (with the squeeze term) hot at the top and cool at the bottom is not a mean of the two
    # uniform runs: firing TDC's boundary friction comes from the hot end, the mid-stroke's
    # viscous friction from the cooler liner: above both; the reverse below both
    e = {tt: ringlube.run(base.with_operating(liner_temperature=tt)).energy_loss for tt in (top, bottom)}
    hot_top = ringlube.run(base.with_operating(liner_temperature_top=top, liner_temperature_bottom=bottom))
    cool_top = ringlube.run(base.with_operating(liner_temperature_top=bottom, liner_temperature_bottom=top))
    assert hot_top.energy_loss > max(e.values()) and cool_top.energy_loss < min(e.values())
    # one end given: the other is liner_temperature
    one = ringlube.run(base.with_operating(liner_temperature_top=top))
    assert one.film_temperature[0] == top
    assert one.film_temperature[90] == pytest.approx(base.value("operating", "liner_temperature"), rel=1e-15)


def test_profile_mistakes_are_named(base):
    with pytest.raises(InputError, match=r"_top: must be 0 \(liner_temperature\) or at least 200 K"):
        base.with_operating(liner_temperature_top=150.0).validate()
    with pytest.raises(InputError, match=r"&operating liner_temperature_bottom: must be in \[0"):
        base.with_operating(liner_temperature_bottom=800.0).validate()


def test_a_distorted_bore_takes_the_profile_in_every_sector(base):
    # the sectors' films take the liner temperature of the step as the ring's does: a bore
    # "distorted" by a zero amplitude is the round bore (its sectors alike), with a profile too
    profile = base.with_operating(liner_temperature_top=400.0, liner_temperature_bottom=340.0)
    zero = profile.with_physics(bore="distorted").with_("bore", order=[4], amplitude=[0.0], sectors=8)
    same(ringlube.run(zero), ringlube.run(profile), rtol=1e-12)
