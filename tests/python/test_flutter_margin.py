"""Flutter and lift as margins: the least net force holding the top ring on its lower flank
while the chamber pressure exceeds the land's (``flutter_margin``, N, and over the peak inertia
force, ``flutter_margin_ratio``), and the peak groove and land pressures with their angles."""

from __future__ import annotations

import h5py
import numpy as np
import pytest

import ringlube

from conftest import INPUTS, per_length

pytestmark = pytest.mark.numerics

DECK = INPUTS / "crf450r_12000rpm_full_hot_gas.nml"
OUT = ["flutter_events", "flutter_margin", "flutter_margin_ratio", "energy_loss"]


@pytest.fixture(scope="module")
def base():
    return ringlube.Case.from_namelist(DECK)


def test_the_margin_is_continuous_and_changes_sign_at_the_first_flutter_event(base):
    # A fine sweep of the ring's density (its inertia) across the first flutter event at
    # 12,000 r/min: flutter_events jumps 0, 1, 2, 3, 4 (it flips on a few hundredths of a
    # newton), the margin falls by the same step each time (the ring's weight times the
    # acceleration at the critical instant: linear in the density) and is positive exactly
    # where no flutter event is, negative exactly where one is.
    # (the deck read in N/m, the reading this sweep was set on: read in N the onset lies elsewhere)
    x = np.arange(5300.0, 5541.0, 10.0)
    v, conv, errors = ringlube.run_designs(per_length(base), ["ring:density"], x[:, None], OUT)
    assert conv.all() and not any(errors)
    events, margin, ratio = v[:, 0], v[:, 1], v[:, 2]
    assert events[0] == 0 and events[-1] >= 3 and len(set(events)) >= 4
    np.testing.assert_array_equal(margin > 0, events == 0)
    np.testing.assert_array_equal(ratio > 0, events == 0)
    # no jump: every step of the sweep moves the margin by about the median step (0.24-0.27 N
    # per 10 kg/m^3; the least force is taken over adaptive sub-steps, whose sampling of the
    # critical instant wiggles it by some 0.05 N, and the instant moves, a kink near 5380);
    # a jump is many steps (the coupled solution's own jump, between 5540 and 5560 where the
    # ring pack's periodic state taken at the end of a cycle is another one, with one flutter
    # event and a margin of -27.7 N, is 100 of them)
    step = np.diff(margin)
    assert np.all(step < 0)
    assert 0.5 < np.min(step / np.median(step)) and np.max(step / np.median(step)) < 1.5, step
    # and the zero, interpolated, falls between the last run without and the first with
    k = int(np.argmax(events > 0))
    zero = x[k - 1] - margin[k - 1] * (x[k] - x[k - 1]) / (margin[k] - margin[k - 1])
    assert x[k - 1] < zero < x[k]


def test_margins_and_peaks_in_the_file_and_the_summary(base, tmp_path):
    r = ringlube.run(base, output=tmp_path / "g.h5")
    # the shipped 12,000 r/min deck flutters once: a negative margin
    assert r.flutter_events == 1 and r.flutter_margin < 0 and r.flutter_margin_ratio < 0
    # the ratio: over the largest inertia force m_r |a_p| of the cycle's steps (the piston's
    # acceleration at each step's middle, where the ring pack takes it)
    rc, lc = base.value("engine", "crank_radius"), base.value("engine", "conrod_length")
    omega = base.value("operating", "speed_rpm") * np.pi / 30
    dpsi = base.value("numerics", "dpsi_deg")
    psi = np.radians(r.crank_angle_deg - dpsi / 2)

    def x(p):  # the slider-crank position
        return rc * (1 - np.cos(p)) + lc - np.sqrt(lc**2 - (rc * np.sin(p)) ** 2)

    h = 1e-4  # its acceleration by a central difference (error ~h^2: 1e-8)
    accel = omega**2 * (x(psi + h) - 2 * x(psi) + x(psi - h)) / h**2
    mass = r.ring_mass * 1e-3
    assert r.flutter_margin / r.flutter_margin_ratio == pytest.approx(mass * np.max(np.abs(accel)), rel=1e-6)
    # the peaks against the series
    k = int(np.argmax(r.groove_pressure))
    assert (r.peak_groove_pressure, r.peak_groove_angle) == (r.groove_pressure[k], r.crank_angle_deg[k])
    k = int(np.argmax(r.land_pressure))
    assert (r.peak_land_pressure, r.peak_land_angle) == (r.land_pressure[k], r.crank_angle_deg[k])
    with h5py.File(tmp_path / "g.h5") as f:
        assert f.attrs["flutter_margin_N"] == r.flutter_margin
        assert f.attrs["peak_land_pressure_Pa"] == r.peak_land_pressure
        assert f.attrs["peak_groove_angle_deg"] == r.peak_groove_angle
    text = r.summary()
    assert "flutter margin" in text and "peak groove pressure" in text and "land " in text
    # the ring pack's results only with the ring pack
    plain = ringlube.run(ringlube.Case.from_namelist(INPUTS / "crf450r_4000rpm_full_cold.nml"))
    assert not hasattr(plain, "flutter_margin") or "flutter margin" not in plain.summary()


def test_no_gas_above_the_land_is_the_whole_inertia_force():
    # no trace and no crankcase pressure: the chamber never exceeds the land, nothing holds the
    # ring down or could make it flutter: the margin is the largest inertia force, ratio 1
    case = ringlube.Case().with_numerics(nodes=31, dpsi_deg=4.0).with_("physics", ring_pack="gas")
    r = ringlube.run(case.with_("operating", crankcase_pressure=0.0))
    assert r.flutter_events == 0 and r.flutter_margin_ratio == 1.0
    assert np.isfinite(r.flutter_margin) and r.flutter_margin > 0


def test_the_margin_is_a_study_constraint(tmp_path):
    from ringlube.study.deck import read_study

    deck = tmp_path / "s.nml"
    deck.write_text(
        f"&study cases = '{DECK}', variables = 'width', lower = 0.8e-3, upper = 1.2e-3,\n"
        " samples = 16, constraints = 'flutter_margin >= 0' /\n"
    )
    s = read_study(deck)
    assert "flutter_margin" in s.outputs and s.constraints == ["flutter_margin >= 0"]
