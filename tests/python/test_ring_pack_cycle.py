"""The ring pack coupled to the film: the groove pressure is the ring's
back pressure, the land pressure its lower edge, both advanced with the film at every crank
step; the results reach Python and the HDF5 file by name. The tests of a starved lift-off and
of the periods of several cycles are set on the decks read in N/m (``conftest.per_length``), the
reading whose intake stroke lifts off and whose designs below have those periods."""

from __future__ import annotations

import h5py
import numpy as np
import pytest

import ringlube
from ringlube import Case
from ringlube.tables import FLAGS

from conftest import COLD, per_length

pytestmark = pytest.mark.numerics

FAST = {"preset": "fast"}


@pytest.fixture(scope="module")
def cold() -> Case:
    return Case.from_namelist(COLD)


@pytest.mark.parametrize("deck", ["crf450r_4000rpm_full_cold.nml", "crf450r_3000rpm_half_cold.nml"])
def test_gas_keeps_the_starved_ring_on_the_liner(deck):
    """Without the ring pack the starved decks lift off the liner on the intake stroke (the
    crankcase pressure below the ring beats the chamber's behind it); with it the ring rides
    up against its upper flank, the groove sees the land pressure and no step is held at the
    h0 ceiling."""
    case = per_length(COLD.with_name(deck)).with_physics(cavitation="jfo", inlet="starved")
    alone, pack = (ringlube.run(case.with_physics(ring_pack=rp)) for rp in ("none", "gas"))
    lift = FLAGS["h0_ceiling"]
    assert alone.liner_lift_share > 10 and ((alone.flags & lift) > 0).any()
    assert pack.converged and pack.liner_lift_share == 0 and not ((pack.flags & lift) > 0).any()
    intake = (pack.crank_angle_deg > 10) & (pack.crank_angle_deg < 170)
    # on the intake stroke the groove holds more than the chamber: the ring's back pressure
    assert (pack.groove_pressure[intake] > pack.gas_pressure[intake]).mean() > 0.9


def test_ring_pack_results_balance_and_file(cold, tmp_path):
    """Blowby, lift and the gas balance of the reported cycle; the series and root attributes
    of docs/model.md "The gas around the ring" in the HDF5 file; the land pressure peaks after
    firing TDC, after the chamber's."""
    out = tmp_path / "gas.h5"
    r = ringlube.run(cold.with_physics(ring_pack="gas"), output=out)
    assert r.converged and r.periodic
    assert r.gas_balance_error <= 1e-8, r.gas_balance_error
    assert 0.1 < r.blowby < 50 and r.blowby_mass > 0 and r.blowback_mass >= 0
    assert 0 <= r.ring_lift_share <= 100 and r.flutter_events >= 0
    assert (r.ring_lift >= 0).all() and (
        r.ring_lift <= cold.value("ring_pack", "groove_clearance") + 1e-15
    ).all()
    k_chamber, k_land = np.argmax(r.gas_pressure), np.argmax(r.land_pressure)
    assert 360 <= r.crank_angle_deg[k_chamber] < r.crank_angle_deg[k_land] < 540
    # the applied load is the groove pressure behind the ring
    width, bore = cold.value("ring", "width"), cold.value("engine", "bore_radius")
    p_e = r.applied_load / (width * 2 * np.pi * bore) - r.groove_pressure
    assert np.ptp(p_e) <= 1e-9 * np.abs(p_e).max()
    with h5py.File(out) as f:
        for name in (
            "groove_pressure_Pa",
            "land_pressure_Pa",
            "ring_lift_m",
            "top_gap_flow_kg_s",
            "second_gap_flow_kg_s",
        ):
            assert f["cycle"][name].attrs["units"]
        for name in (
            "blowby_l_min",
            "blowby_mg_per_cycle",
            "blowback_mg_per_cycle",
            "ring_lift_share_pct",
            "flutter_events",
            "gas_balance_error",
        ):
            assert name in f.attrs, name
    plain = ringlube.run(cold)
    assert "blowby" not in plain.scalars and "groove_pressure" not in plain.series
    assert "blowby" in r.summary() and "blowby" not in plain.summary()
    from ringlube.plot import plot_results

    names = [p.name for p in plot_results([r], tmp_path / "plots", formats=("png",))]
    assert names[-1] == "gas_ring_pack.png" or any(n.endswith("_ring_pack.png") for n in names), names


def test_blowby_rises_with_the_top_gap(cold):
    """Monotone physics, coupled: a larger top-ring gap lets more gas past the rings."""
    case = cold.with_physics(ring_pack="gas").with_numerics(**FAST)
    blowby = [ringlube.run(case.with_("ring_pack", top_gap_area=a)).blowby for a in (0.05e-6, 0.1e-6, 0.2e-6)]
    assert blowby[0] < blowby[1] < blowby[2], blowby


def test_ring_pack_works_with_every_film_model(cold):
    """Swift-Stieber and JFO, flooded and starved, vapour and trailing gas: each converges
    with the ring pack at the 'fast' preset and closes its gas balance."""
    for physics in (
        {},
        {"cavitation": "jfo"},
        {"cavitation": "jfo", "inlet": "starved"},
        {"cavitation": "jfo", "cavity_pressure": "trailing_gas", "inlet": "starved"},
    ):
        r = ringlube.run(cold.with_physics(ring_pack="gas", **physics).with_numerics(**FAST))
        assert r.periodic and r.gas_balance_error <= 1e-8, physics


def test_open_land_limit_reproduces_no_ring_pack(cold):
    """A huge land volume and second gap with the ring held on its lower flank
    reproduce ring_pack = 'none' (p2 = p1 behind the ring, p3 = crankcase below it) in the
    coupled cycle, to solver tolerance. The ring is held down by the gas: the crankcase
    (50 kPa) lies below the lowest chamber pressure (93 kPa), so the chamber presses the
    ring on its lower flank with at least 22 N, more than the friction off firing TDC and the
    inertia of a light ring (100 kg/m^3: 0.1 g); the groove (0.1 mm^3) fills through the
    open upper channel within 0.1 us. The load balance is solved to 1e-6 (the preset's looser
    tolerance alone moves h0 by up to 1e-3 between two runs that differ in round-off);
    measured: h0 within 1.5e-5, energy 1.1e-6, p2 - p1 7e-5 of p1, p3 - p4 2.7e-4 of p4."""
    base = cold.with_operating(crankcase_pressure=5e4).with_ring(density=100.0).with_numerics(load_tol=1e-6)
    open_land = base.with_physics(ring_pack="gas").with_(
        "ring_pack", land_volume=1e-2, second_gap_area=1e-4, groove_volume=1e-10
    )
    alone, pack = ringlube.run(base), ringlube.run(open_land)
    assert alone.converged and pack.converged
    assert pack.ring_lift_share == 0 and pack.flutter_events == 0
    # the pressures of the source study: p2 = p1, p3 = crankcase
    assert np.max(np.abs(pack.groove_pressure - pack.gas_pressure) / pack.gas_pressure) <= 1e-4
    assert np.max(np.abs(pack.land_pressure - 5e4)) / 5e4 <= 1e-3
    # and the same film: h0 and friction over the cycle, energy, mixed share
    assert np.max(np.abs(pack.h0 / alone.h0 - 1)) <= 1e-4
    assert abs(pack.energy_loss / alone.energy_loss - 1) <= 1e-5
    assert abs(pack.mixed_share - alone.mixed_share) <= 1e-2


@pytest.mark.parametrize("deck", ["crf450r_4000rpm_full_cold.nml", "crf450r_4000rpm_full_hot.nml"])
def test_ring_pack_periodic_in_one_cycle(deck):
    """The ring pack must not double a Swift-Stieber run. With the ring pack
    the warm-up starts at the end of expansion (270 deg), so the land pressure at psi = 0
    carries the film's friction and the first reported cycle is already periodic (from the
    gas network's frictionless periodic state and a 90 deg warm-up it took two: h0 at psi = 0
    moved by 3e-3). The answer is the two-cycle one to within the periodicity tolerance."""
    case = Case.from_namelist(COLD.with_name(deck)).with_physics(ring_pack="gas")
    r = ringlube.run(case)
    assert r.converged and r.cycles_run == 1, (r.cycles_run, r.cycle_change)
    two = ringlube.run(case.with_numerics(cycle_tol=1e-5))
    assert two.cycles_run >= 2
    assert abs(r.energy_loss / two.energy_loss - 1) <= 1e-3
    assert abs(r.blowby / two.blowby - 1) <= 1e-3


def test_ring_pack_restarts_from_its_periodic_state_at_the_rev_limit():
    """At 12,000 r/min the land relaxes over several cycles (its time constant is fixed in
    seconds, three times as many crank degrees as at 4000 r/min) and the film's friction moves
    its periodic state by 3 %: a cycle that is not periodic restarts the ring pack from its
    periodic state under that cycle's friction, 90 deg before the cycle's end, and the film
    runs those 90 deg again from its own state there, so the next cycle starts without a jump
    in the groove and land pressures. The run needs 3 cycles (4 without a restart) and the
    answer is the same (periodicity tolerance). (The cycle after the restart is not judged on its
    energy against the first cycle's, which ran from the old land: on this deck read in N that
    passed at 0.94 % from the periodic energy; test_the_energy_is_judged_at_the_rate_it_settles.)"""
    from conftest import INPUTS

    case = Case.from_namelist(INPUTS / "crf450r_12000rpm_full_hot_gas.nml")
    r = ringlube.run(case)
    assert r.converged and r.cycles_run <= 3, (r.cycles_run, r.cycle_change)
    tight = ringlube.run(case.with_numerics(cycle_tol=1e-5, max_cycles=20))
    assert tight.periodic
    assert abs(r.energy_loss / tight.energy_loss - 1) <= 1e-3
    assert abs(r.blowby / tight.blowby - 1) <= 1e-3


@pytest.mark.parametrize("max_cycles", [1, 10])
def test_blowby_is_the_reported_cycles_own(max_cycles):
    """The blowby a run reports is the mass through the second ring's gap over the reported
    cycle, the sum of its `second_gap_flow` series. Also for a run stopped after its first
    cycle at the rev limit, which is not periodic: the restart of the ring pack that would prepare
    a second cycle must not replace the cycle's numbers (it did: the blowby reported was the
    restart's gas-only cycle's)."""
    from conftest import INPUTS

    case = Case.from_namelist(INPUTS / "crf450r_12000rpm_full_hot_gas.nml")
    r = ringlube.run(case.with_numerics(max_cycles=max_cycles))
    assert r.periodic == (max_cycles > 1)
    dt = np.deg2rad(case.value("numerics", "dpsi_deg")) / (case.value("operating", "speed_rpm") * np.pi / 30)
    assert r.blowby_mass == pytest.approx(np.sum(r.second_gap_flow) * dt * 1e6, rel=1e-9)


def test_rewarm_with_no_warm_up():
    """`warmup_deg = 0`: the re-warm after a first cycle that is not periodic still runs (one
    crank step) from a saved film state, and the run reaches the same periodic answer."""
    from conftest import INPUTS

    case = Case.from_namelist(INPUTS / "crf450r_12000rpm_full_hot_gas.nml")
    r = ringlube.run(case)
    z = ringlube.run(case.with_numerics(warmup_deg=0.0))
    assert r.converged and z.converged and np.isfinite(z.h0).all()
    assert z.energy_loss == pytest.approx(r.energy_loss, rel=2e-3)
    assert z.blowby == pytest.approx(r.blowby, rel=2e-3)


def test_large_land_is_not_reported_periodic_far_from_its_state():
    """A large land (1e-3 m^3, in range) relaxes over hundreds of cycles and changes by a
    few Pa a cycle far from its periodic state: the start must reach that state (Aitken's
    extrapolation up to ratios near 1, convergence judged by the distance |d| / (1 - rho)),
    not stop because one cycle changes little. The reported blowby lies within 10 % of
    300 coupled cycles' (2.22 against 2.13 l/min; before: 0.50 reported periodic after 2
    cycles, 0.62 against 1.12 here, the 300 cycles themselves still far from 2.13)."""
    case = Case.from_namelist(COLD.with_name("crf450r_12000rpm_full_hot_gas.nml")).with_(
        "ring_pack", land_volume=1e-3
    )
    r = ringlube.run(case)
    long = ringlube.run(case.with_numerics(max_cycles=300, cycle_tol=1e-14))
    assert r.periodic
    assert abs(r.blowby - long.blowby) <= 0.1 * long.blowby, (r.blowby, long.blowby)
    assert abs(r.energy_loss - long.energy_loss) <= 1e-2 * long.energy_loss


def test_a_slow_land_starts_where_its_coarse_cycles_settled():
    """A 0.39 L land (in range) on the 4000 r/min hot deck at 'fast', 1.516 mm at 27.02 N/m,
    large gaps and clearance (a second engineer's sweep, 2026-11-26): the land contracts by
    0.95-0.999 a cycle and its cycle map bends at the fixed point, so the start's fine gas
    cycles never settled; Aitken's extrapolation jumped past the fixed point and back, and the
    50th cycle ended at 772 kPa against a periodic 497 kPa. The coupled cycle, whose land moves
    a few kPa a cycle there, then passed cycle_tol: 2.885 J and 9.17 l/min reported converged
    against 2.770 J and 5.95 l/min. Fine cycles that do not settle now leave the start where the
    coarse cycles settled (496 kPa). Within the coupled test's reach for a slow land: energy to
    1e-3 and blowby and the land pressure at psi = 0 to 1 % of the 30th cycle of a run to
    cycle_tol 1e-6 (which it does not pass: the land's change counts as |d| / (1 - rho) with rho
    about 0.95; its 29th and 30th cycles agree to 1e-4)."""
    from conftest import INPUTS

    case = Case.from_namelist(INPUTS / "crf450r_4000rpm_full_hot.nml")
    case = case.with_ring(width=1.516e-3, tension=27.02)
    case = case.with_physics(ring_pack="gas").with_numerics(preset="fast")
    case = case.with_ring_pack(
        land_volume=3.86e-4, top_gap_area=8.71e-7, groove_clearance=8.87e-5, second_gap_area=1.85e-7
    )
    r = ringlube.run(case)
    before, tight = _stopped_after(case, (29, 30))
    for name in ("energy_loss", "blowby"):
        assert getattr(tight, name) == pytest.approx(getattr(before, name), rel=1e-4)
    assert r.converged
    assert r.energy_loss == pytest.approx(tight.energy_loss, rel=1e-3)
    assert r.blowby == pytest.approx(tight.blowby, rel=1e-2)
    assert r.land_pressure[0] == pytest.approx(tight.land_pressure[0], rel=1e-2)


def test_a_start_that_does_not_settle_does_not_vouch_for_the_first_cycle():
    """A 0.4 L land with a 0.2 mm^2 top gap on the 4000 r/min hot deck read in N/m at 'fast' (a review,
    2026-11-26): neither the gas start's coarse nor its fine cycles settle in 50, the start
    leaves the land at 526 kPa against a periodic 300 kPa, its contraction is unknown, and the
    first coupled cycle moved the land by 1 kPa and passed: 2.372 J and 6.28 l/min reported
    converged against 2.306 J and 3.59 l/min (also before the faster start). A start that did
    not settle cannot pass the first cycle: the restart follows, and the run gives the answer
    of a run to cycle_tol 1e-6 (energy to 1e-4, blowby to 1e-3)."""
    from conftest import INPUTS

    case = per_length(INPUTS / "crf450r_4000rpm_full_hot.nml")
    case = case.with_physics(ring_pack="gas").with_numerics(preset="fast")
    case = case.with_ring_pack(
        top_gap_area=2e-7, groove_clearance=8.87e-5, second_gap_area=1.85e-7, land_volume=4e-4
    )
    r = ringlube.run(case)
    tight = ringlube.run(case.with_numerics(cycle_tol=1e-6, max_cycles=300))
    assert r.converged and r.cycles_run >= 2, r.cycles_run
    assert r.energy_loss == pytest.approx(tight.energy_loss, rel=1e-4)
    assert r.blowby == pytest.approx(tight.blowby, rel=1e-3)


@pytest.mark.parametrize("deck", ["crf450r_4000rpm_full_cold.nml", "crf450r_8000rpm_full_hot_gas.nml"])
@pytest.mark.parametrize("preset", ["fast", "default", "accurate"])
def test_coarse_warm_up_gives_the_full_warm_ups_answer(deck, preset):
    """With a Swift-Stieber film of 41 nodes or more ('default', 'accurate'), the 180 deg the
    ring pack's warm-up adds before the film's own run on an 11-node film, with 25-40 nodes
    ('fast': 31) on a 7-node film (they only feed the gas network the friction through
    blowdown). A warm-up of the film's own over the whole 270 deg (`warmup_deg = 270`:
    no coarse part) must give the same one-cycle answer within the periodicity tolerance."""
    case = Case.from_namelist(COLD.with_name(deck)).with_physics(ring_pack="gas").with_numerics(preset=preset)
    coarse, full = ringlube.run(case), ringlube.run(case.with_numerics(warmup_deg=270.0))
    assert coarse.converged and full.converged
    assert coarse.cycles_run == full.cycles_run == 1
    assert coarse.cycles_computed == pytest.approx(full.cycles_computed)
    assert coarse.energy_loss == pytest.approx(full.energy_loss, rel=1e-4)
    assert coarse.blowby == pytest.approx(full.blowby, rel=1e-4)
    assert coarse.ring_lift_share == pytest.approx(full.ring_lift_share, rel=1e-3, abs=1e-3)


def _stopped_after(case, cycles):
    """The runs of ``case`` stopped after each of ``cycles`` cycles, with a cycle tolerance no
    state meets: the k-th reports the k-th cycle itself, not a mean over a period."""
    return [ringlube.run(case.with_numerics(cycle_tol=1e-14, max_cycles=k)) for k in cycles]


def _liner_change(a, b, window):
    """The liner film's change from ``b`` to ``a``: its L1 norm relative to ``a``'s, and with a
    ``window`` the largest such change over any ``window`` consecutive cells, relative to
    ``a``'s over them or to ``a``'s mean over as many cells if that is larger."""
    whole = np.abs(a - b).sum() / np.abs(a).sum()
    if not window:
        return whole
    ca = np.concatenate([[0.0], np.cumsum(np.abs(a))])
    cd = np.concatenate([[0.0], np.cumsum(np.abs(a - b))])
    floor = ca[-1] * window / a.size
    return max(whole, ((cd[window:] - cd[:-window]) / np.maximum(ca[window:] - ca[:-window], floor)).max())


def test_the_last_cycles_changes_say_why_a_run_is_not_periodic():
    """A run reports what its test of a period of one compares with cycle_tol (`liner_change`
    and `energy_change` with a starved inlet, `cycle_change` of h0 and `energy_change` without;
    `ring_pack_change` with the gas), and the summary prints them: before, a starved run that
    was not converged showed only h0's change, often below cycle_tol. Each is the quantity's
    distance from its periodic state: its change over the last cycle divided by 1 - its
    contraction per cycle, the ratio of its last two changes (the liner film's: of their L1
    norms, where the two point the same way; the energy moves at the liner film's rate; with
    the BDC start's liner window, the default on a round bore with a vapour cavity, the larger
    of the whole film's change and that over any 50 liner cells, relative to their film or to
    the film's mean over 50 cells). Checked against the runs stopped after 2, 3 and 4 cycles
    (without the liner film's extrapolation, so that each cycle continues the one before),
    with the window and judged on the whole film alone (`bdc_start = .false.`). The cold deck
    starved with the gas is periodic after 3 cycles (liner film 6.2e-4 over 50 cells; its
    liner film 4.6e-6 and h0 3.4e-4 from a run to cycle_tol 1e-9) and 4 on the whole film
    (6.7e-5); stopped a cycle earlier it is not (7.6e-3 and 1.4e-3), and says so."""
    case = per_length(COLD).with_physics(cavitation="jfo", inlet="starved", ring_pack="gas")
    case = case.with_numerics(accelerate=False)
    tol = case.value("numerics", "cycle_tol")
    for window, cycles in ((50, 3), (0, 4)):
        own = case if window else case.with_numerics(bdc_start=False)
        two, three, four = _stopped_after(own, (2, 3, 4))
        h2, h3, h4 = (r.liner["liner_oil_film"] for r in (two, three, four))
        change = [_liner_change(b, a, window) for a, b in ((h2, h3), (h3, h4))]
        assert (h4 - h3) @ (h3 - h2) > 0  # (the same sense: else the change counts as it is)
        rho = min(change[1] / change[0], 0.99)
        assert 0.0 < rho < 0.99, rho
        assert four.liner_change == pytest.approx(change[1] / (1 - rho), rel=1e-9)
        de = abs(four.energy_loss - three.energy_loss) / four.energy_loss
        assert four.energy_change == pytest.approx(de / (1 - rho), rel=1e-9, abs=1e-15)
        done = ringlube.run(own)
        assert done.converged and done.cycles_run == cycles, (window, done.cycles_run)
        assert max(done.liner_change, done.energy_change, done.ring_pack_change) <= tol
        stopped = ringlube.run(own.with_numerics(max_cycles=cycles - 1))
        assert not stopped.converged and stopped.liner_change > tol
        assert f"liner film {stopped.liner_change:.2E}" in stopped.summary()
    # without a starved inlet: h0's, the energy's and the ring pack's; the first cycle of the
    # rev-limit deck is not periodic (its land moves with the film's friction) and shows which
    # moved
    from conftest import INPUTS

    rev = per_length(INPUTS / "crf450r_12000rpm_full_hot_gas.nml")
    first = ringlube.run(rev.with_numerics(max_cycles=1))
    assert "liner_change" not in first.scalars and not first.converged
    assert max(first.cycle_change, first.ring_pack_change) > rev.value("numerics", "cycle_tol")
    changes = (first.cycle_change, first.energy_change, first.ring_pack_change)
    assert "h0 {:.2E}, energy {:.2E}, ring pack {:.2E}".format(*changes) in first.summary()


def test_a_starved_period_reports_the_changes_its_test_passed():
    """Starved, a period of two liner-film cycles is accepted when the energy and the ring pack
    repeat every cycle (history_period); the changes reported are then those (6e-6), not the
    energy's over two cycles back to the transient after the ring pack's restart (1.5e-2
    printed beside 'converged yes'; a review, 2026-11-26). 8000 r/min hot 'gas' deck, 0.79 mm
    at 13.5 N/m, starved, read in N/m: period 2 after 4 cycles, 1.92455 J (to cycle_tol 1e-7
    the film settles to a period of one after 7 cycles, 1.92454 J); the period is not refused
    on the first cycle's energy, which ran before the restart (`ctest -R
    periodicity/two_after_restart`). That is the liner film judged on the whole film
    (`bdc_start = .false.`); over any 50 cells as well (the default) the film near BDC is seen
    still settling and the run is periodic with a period of one after 5 cycles, its energy and
    blowby those of the run to cycle_tol 1e-7 within cycle_tol."""
    from conftest import INPUTS

    case = per_length(INPUTS / "crf450r_8000rpm_full_hot_gas.nml")
    case = case.with_ring(width=0.79e-3, tension=13.5).with_physics(cavitation="jfo", inlet="starved")
    r = ringlube.run(case.with_numerics(bdc_start=False))
    tol = case.value("numerics", "cycle_tol")
    assert r.converged and r.period == 2, (r.period, r.cycles_run)
    assert max(r.liner_change, r.energy_change, r.ring_pack_change) <= tol, r.summary()
    window, tight = ringlube.run(case), ringlube.run(case.with_numerics(cycle_tol=1e-7, max_cycles=40))
    assert window.converged and window.period == 1 and tight.converged, (window.period, window.cycles_run)
    assert max(window.liner_change, window.energy_change, window.ring_pack_change) <= tol, window.summary()
    for name in ("energy_loss", "blowby"):
        assert getattr(window, name) == pytest.approx(getattr(tight, name), rel=tol), name


def test_period_of_two_cycles_reports_the_means():
    """A 0.8788 mm ring at 14.18 N/m on the 8000 r/min hot 'gas' deck settles into a period of
    two cycles (land pressure at a cycle's end alternating between 1.856 and 2.033 bar, energy between
    1.8318 and 1.8368 J): it used to run to max_cycles and be reported not converged. It is
    periodic with period 2 and reports the means over both cycles: energy within 1e-4 and blowby
    within 5e-4 (measured 6e-6 and 1.4e-4 after 3 cycles) of the mean of cycles 11 and 12 of a
    run whose tolerance no state meets, each of which lies more than 1e-3 from it (energy
    1.35e-3, blowby 1.2e-2; docs/model.md, "A period of several cycles")."""
    from conftest import INPUTS

    case = per_length(INPUTS / "crf450r_8000rpm_full_hot_gas.nml")
    case = case.with_ring(width=0.8788e-3, tension=14.18)
    r = ringlube.run(case)
    assert r.converged and r.periodic and r.period == 2 and r.cycles_run <= 4, r.cycles_run
    # the summary's count of flagged steps is the last cycle's, and says so with a period of two
    flagged = next(line for line in r.summary().splitlines() if "flagged crank steps" in line)
    assert "the last cycle's" in flagged, flagged
    # the changes it reports are over its period (within cycle_tol), not over its last cycle
    assert max(r.cycle_change, r.ring_pack_change) <= case.value("numerics", "cycle_tol")
    assert "(change over the period of 2 cycles: h0 " in r.summary()
    single = _stopped_after(case, (11, 12))
    assert all(s.period == 0 and not s.converged for s in single)
    for name, rel in (("energy_loss", 1e-4), ("blowby", 5e-4)):
        values = [getattr(s, name) for s in single]
        mean = sum(values) / 2
        assert getattr(r, name) == pytest.approx(mean, rel=rel), (name, values)
        assert all(abs(v / mean - 1) > 1e-3 for v in values), (name, values)
    # a period of one cycle says so
    assert ringlube.run(per_length(INPUTS / "crf450r_8000rpm_full_hot_gas.nml")).period == 1


def test_starved_period_of_two_cycles_with_the_ring_pack():
    """The same ring starved (JFO, 1 um supply film) settles into a period of two cycles too:
    energy alternating between 1.9752 and 2.0029 J and the land pressure at psi = 0 between
    2.040 and 1.906 bar, the liner film repeating after two cycles (to 5e-4 from the eighth).
    The starved test compared the energy and the ring pack over one cycle only, so the run went
    to max_cycles and was reported not converged with the last cycle's energy, 0.7 % from the
    mean. It is periodic with period 2 and reports the means over both cycles: energy and
    blowby within 1e-4 of the mean of cycles 15 and 16 of a run whose tolerance no state meets
    (measured 4e-6 and 3e-6), each of which lies more than 1e-3 (energy, 7e-3) and 5e-3
    (blowby, 8.8e-3) from it."""
    from conftest import INPUTS

    case = per_length(INPUTS / "crf450r_8000rpm_full_hot_gas.nml")
    case = case.with_ring(width=0.8788e-3, tension=14.18).with_physics(cavitation="jfo", inlet="starved")
    r = ringlube.run(case)
    assert r.converged and r.periodic and r.period == 2, (r.cycles_run, r.energy_loss)
    single = _stopped_after(case, (15, 16))
    assert all(s.period == 0 and not s.converged for s in single)
    for name, rel, apart in (("energy_loss", 1e-4, 1e-3), ("blowby", 1e-4, 5e-3)):
        values = [getattr(s, name) for s in single]
        mean = sum(values) / 2
        assert getattr(r, name) == pytest.approx(mean, rel=rel), (name, values)
        assert all(abs(v / mean - 1) > apart for v in values), (name, values)
    assert r.oil_balance_error < 1e-6


def test_period_of_five_cycles_reports_the_means():
    """At 8000 r/min the hot 'gas' deck starved (JFO, 1 um supply film) with a 1.070 mm ring at
    5.2 N/m settles into a period of five cycles: four at 2.293 J, then one at 2.026 J, the oil
    left near BDC building up and being picked up again. With a period of two at most it ran
    to max_cycles (30) and reported the last cycle's 2.2936 J, 2.4 % from the mean (or 2.026 J,
    -9.5 %, had it stopped three cycles later). It is periodic with period 5 and reports the means of
    its last five cycles, which are the runs stopped after each of them (to round-off); five
    later cycles give the same means (the orbit repeats), and their energies spread by more
    than 5 % about it (docs/model.md, "A period of several cycles"). Judged on the whole liner
    film (`bdc_start = .false.`), where the orbit is found after 18 cycles; with the film over
    any 50 cells as well (the default) after 59, its means the same to 2e-8."""
    from conftest import INPUTS

    case = per_length(INPUTS / "crf450r_8000rpm_full_hot_gas.nml")
    case = case.with_ring(width=1.070e-3, tension=5.2).with_physics(cavitation="jfo", inlet="starved")
    case = case.with_numerics(bdc_start=False)
    r = ringlube.run(case.with_numerics(max_cycles=30))
    assert r.converged and r.periodic and r.period == 5, (r.period, r.cycles_run)
    n = r.cycles_run
    short = ringlube.run(case)  # max_cycles 10: the orbit starts too late, and the summary says what to try
    assert short.period == 0 and "a period p needs 2p + 1 cycles; try a larger max_cycles" in short.summary()
    assert "(a period of 5 cycles: energy, shares, blowby are means)" in r.summary()
    for last in (n, n + 5):
        cycles = range(last - 4, last + 1)
        single = _stopped_after(case, cycles)
        assert all(s.period == 0 and not s.converged for s in single)
        for name in ("energy_loss", "blowby", "mixed_share", "ring_lift_share"):
            mean = np.mean([getattr(s, name) for s in single])
            assert getattr(r, name) == pytest.approx(mean, rel=1e-12 if last == n else 1e-3), name
        energies = [s.energy_loss for s in single]
        assert min(energies) < 0.95 * r.energy_loss < max(energies), energies


def test_a_starved_two_cycle_is_not_taken_against_the_first_cycle():
    """The 4000 r/min hot 'gas' deck starved with 'trailing_gas', a 1.0848 mm ring at 10.64 N/m:
    cycles 1-5 ran 1.19861, 1.04879, 1.19859, 1.19855, 1.19855 J. Cycle 3's energy equalled cycle
    1's, which ran before the ring pack's restart, and the film repeated over two cycles, so a
    starved two-cycle compared with the first cycle's energy would have been reported at cycle 3
    with the mean of cycles 2 and 3, 6 % low (found by a review's sweep). A starved
    two-cycle never compares with the first cycle's energy (test_periodicity,
    starved_map_and_energy); with the restart starting the gas network from the coupled cycle's
    own state at the re-warm's first step and stepping it as the coupled cycle does, cycle 2
    no longer dips (1.19861, 1.19855, 1.19855 J). The run is periodic with period 1 at
    the energy of a run to cycle_tol 1e-9 (within 1e-4), and at 1e-9 no transient is taken for a
    period."""
    from conftest import INPUTS

    case = per_length(INPUTS / "crf450r_4000rpm_full_hot_gas.nml").with_ring(width=1.0848e-3, tension=10.64)
    case = case.with_physics(cavitation="jfo", inlet="starved", cavity_pressure="trailing_gas")
    first = [ringlube.run(case.with_numerics(cycle_tol=1e-14, max_cycles=n)).energy_loss for n in (1, 2, 3)]
    assert first[1:] == pytest.approx([first[0], first[0]], rel=1e-4), first
    r = ringlube.run(case)
    tight = ringlube.run(case.with_numerics(cycle_tol=1e-9, max_cycles=60))
    assert r.period == 1 and r.converged, (r.period, r.cycles_run)
    assert tight.period == 1, (tight.period, tight.cycles_run)
    assert r.energy_loss == pytest.approx(tight.energy_loss, rel=1e-4)


def test_flutter_events_of_a_period_of_two_cycles_are_one_number(tmp_path):
    """At 12000 r/min a 0.64 mm ring at 14 N/m with a 0.2 mm^2 top gap and a 20 um groove
    clearance has a period of two cycles with 1 and 2 flutter events: the mean, 1.5 events per
    cycle, is what the run reports everywhere. As an 'integer' result it was 1 in Python (the
    mean truncated), 2 in the HDF5 file and the summary (rounded) and 1.5 in the scalars."""
    from conftest import INPUTS

    case = per_length(INPUTS / "crf450r_12000rpm_full_hot_gas.nml")
    case = case.with_ring(width=0.64e-3, tension=14.0)
    case = case.with_ring_pack(top_gap_area=2e-7, groove_clearance=2e-5)
    r = ringlube.run(case, output=tmp_path / "p2.h5")
    assert r.period == 2 and r.converged
    n = r.cycles_run
    single = _stopped_after(case, (n - 1, n))
    assert sorted(s.flutter_events for s in single) == [1, 2]
    assert r.flutter_events == r.scalars["flutter_events"] == 1.5
    with h5py.File(tmp_path / "p2.h5") as f:
        assert f.attrs["flutter_events"] == 1.5
    assert "(1.5 flutter events" in r.summary()


def test_a_period_of_two_cycles_with_a_flagged_cycle_is_not_converged():
    """The means of a period of two cycles take both cycles, so both must be free of flags but
    lift-off for the run to be converged. The 8000 r/min 'gas' deck starved (JFO, 4 um supply
    film) with a 0.99 mm ring at 20 N/m was a starved two-cycle after 3 cycles whose second
    cycle had a step outside load_tol (flag 4 at 516 deg); it was reported converged from the
    third cycle's flags alone. No period contains the cycle after the ring pack's restart now,
    and the run (without the liner film's extrapolation) is periodic with period 1 after 7
    cycles, its liner film alternating within cycle_tol, with a flagged step:
    not converged, and the summary says why. Whichever period is found, a flag in any of its
    cycles makes the run not converged (test_periodicity, means_and_flags: history_clean over
    the period's cycles)."""
    from conftest import INPUTS

    case = per_length(INPUTS / "crf450r_8000rpm_full_hot_gas.nml")
    case = case.with_ring(width=0.99e-3, tension=20.0).with_physics(cavitation="jfo", inlet="starved")
    case = case.with_lubricant(supply_film=4e-6).with_numerics(accelerate=False)
    r = ringlube.run(case)
    assert r.periodic and r.period in (1, 2), (r.period, r.cycles_run)
    not_lift = ~np.int64(FLAGS["h0_ceiling"])
    flagged = (r.flags & not_lift).any()
    if r.period == 2:
        previous = ringlube.run(case.with_numerics(cycle_tol=1e-14, max_cycles=r.cycles_run - 1))
        flagged = flagged or (previous.flags & not_lift).any()
    assert flagged
    assert not r.converged and "(a step is flagged in the period's cycles)" in r.summary()


def test_a_transient_near_repeat_is_not_a_period():
    """At 12000 r/min the hot 'gas' deck starved (JFO, 1 um) with a 1.215 mm ring at 5.5 N/m
    passes through a transient whose cycle 14 starts and ends as cycle 6 did, with cycle 6's
    energy, while the cycles between do not repeat (2.061 J in cycle 9, 2.970 J in cycle 17);
    it then settles into a period of 9 cycles. With two states in a row and one energy
    compared it was reported periodic with period 8 after 14 cycles and converged, 2.3316 J,
    6 % below the mean of the period it settles into (2.489 J). A reported period must be an
    orbit: the cycles after it repeat those a period before (energy to a few cycle_tol;
    docs/model.md, "A period of several cycles")."""
    from conftest import INPUTS

    case = Case.from_namelist(INPUTS / "crf450r_12000rpm_full_hot_gas.nml")
    case = case.with_ring(width=1.215e-3, tension=5.5).with_physics(cavitation="jfo", inlet="starved")
    r = ringlube.run(case.with_numerics(max_cycles=30))
    if r.period >= 2:
        n, p = r.cycles_run, r.period
        cycles = range(n - p + 1, n + p + 1)
        single = _stopped_after(case, cycles)
        assert all(s.period == 0 for s in single)
        e = [s.energy_loss for s in single]
        assert all(abs(e[i + p] - e[i]) <= 5e-3 * e[i] for i in range(p)), (p, n, e)


def test_a_starved_period_of_one_must_repeat():
    """At 12000 r/min the hot 'gas' deck starved (JFO, 1 um) with a 1.205 mm ring at 4.25 N/m
    has a period of five cycles (2.9475, 2.1830, 2.2059, 2.2166, 2.2166 J; mean 2.3539 J, found
    at cycle_tol 1e-4 after 40 cycles). Judged on the whole liner film (`bdc_start = .false.`)
    at the default 1e-3 its cycles 10 and 11 passed the starved test of a period of one (energy
    within 1e-7, the liner film map's L1 change 7.0e-4), and the run was reported converged at
    2.2166 J, 6 % below the mean; cycle 12 is 2.9475 J. The film left near BDC (z = 63.6 mm)
    still grows by 1 % a cycle (8.825 -> 8.911 um) until the ring picks it up in cycle 12;
    over the 2673 liner points the L1 norm dilutes that below cycle_tol. Judged over any 50
    cells as well (the default with a vapour cavity) that growth is seen: the run finds its
    period of five (after 34 cycles), whose cycles repeat, at the mean of the run to
    cycle_tol 1e-4 within cycle_tol."""
    from conftest import INPUTS

    case = per_length(INPUTS / "crf450r_12000rpm_full_hot_gas.nml")
    case = case.with_ring(width=1.205e-3, tension=4.25).with_physics(cavitation="jfo", inlet="starved")
    r = ringlube.run(case.with_numerics(max_cycles=60))
    ref = ringlube.run(case.with_numerics(max_cycles=80, cycle_tol=1e-4))
    assert r.converged and ref.converged and r.period == ref.period == 5, (r.period, r.cycles_run)
    assert r.energy_loss == pytest.approx(ref.energy_loss, rel=case.value("numerics", "cycle_tol"))
    n, p = r.cycles_run, r.period
    single = _stopped_after(case, range(n - p + 1, n + p + 1))
    e = [s.energy_loss for s in single]
    assert all(abs(e[i + p] - e[i]) <= 5e-3 * e[i] for i in range(p)), (p, n, e)
