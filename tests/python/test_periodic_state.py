"""The periodic state of a run of cycles (docs/model.md, "Cycle and periodic state"): each
carried quantity is judged by its distance from the periodic state, its change over the last
cycle divided by 1 - its contraction per cycle (the ring pack: its distance from the periodic
state of the gas network under the cycle's friction), so a slowly settling state is not taken
for a periodic one; and a slowly settling liner film is extrapolated toward its periodic
state (`&numerics accelerate`), which changes no converged answer beyond cycle_tol."""

from __future__ import annotations

import numpy as np
import pytest

import ringlube
from ringlube import Case

from conftest import COLD, INPUTS, per_length

pytestmark = pytest.mark.numerics


def _tight(case: Case) -> ringlube.CycleResult:
    """The same case run to cycle_tol 1e-6."""
    return ringlube.run(case.with_numerics(cycle_tol=1e-6, max_cycles=60))


def _assert_same_periodic_state(r, others, tol: float) -> None:
    """Energy, oil to the chamber, mixed share and liner film of ``r`` equal those of each of
    ``others`` within ``tol`` (cycle_tol; the mixed share in percent)."""
    for other in others:
        assert abs(r.energy_loss / other.energy_loss - 1) <= tol
        assert abs(r.oil_to_chamber - other.oil_to_chamber) <= tol * max(other.oil_to_chamber, 1e-12)
        assert abs(r.mixed_share - other.mixed_share) <= 100 * tol
        h, h0 = r.liner["liner_oil_film"], other.liner["liner_oil_film"]
        assert np.abs(h - h0).sum() <= tol * np.abs(h0).sum()


def test_the_energy_is_judged_at_the_rate_it_settles():
    """The 12,000 r/min 'gas' deck read in N with the N/m reading's calibration: after the ring pack's
    restart h0 at psi = 0 and the ring pack change by 2e-4 a cycle while the energy still moves by
    3.5e-3, then 6.8e-3, 2.2e-3 and 4.6e-4 (a mode contracting by 0.23 a cycle, which h0 at psi = 0
    barely shows). Judged on h0 alone the run was periodic after 2 cycles at 2.2591 J, 0.94 % above
    its periodic 2.2380 J; now the energy counts too, at that mode's rate, and the answer lies
    within cycle_tol of a run to cycle_tol 1e-6."""
    case = per_length(INPUTS / "crf450r_12000rpm_full_hot_gas.nml").with_ring(tension_unit="N")
    r, tight = ringlube.run(case), _tight(case)
    tol = case.value("numerics", "cycle_tol")
    assert r.converged and tight.converged
    assert abs(r.energy_loss / tight.energy_loss - 1) <= tol, (r.energy_loss, tight.energy_loss)
    assert abs(r.blowby / tight.blowby - 1) <= tol
    assert max(r.cycle_change, r.energy_change, r.ring_pack_change) <= tol


def test_a_slow_land_is_judged_against_its_periodic_state():
    """A 1.8 L land behind a 2.3e-9 m^2 second gap (both in range) on the cold deck with the ring pack
    read in N/m, a 0.81 mm ring at 4.76 N/m: the land sits at 5.6 bar and moves a few pascal a
    cycle, so the first cycle changed the ring pack by 1e-4 and was taken as periodic; the land's
    periodic state under the film's friction lies 5.4 kPa (1.2 % of its gauge pressure) lower, and
    the answer was 1.4e-3 low in energy and 0.96 % in blowby. Now the land is judged by its distance
    from the periodic state of the gas network under the cycle's friction (relative to its gauge
    pressure), the ring pack restarts there, and energy and blowby lie within cycle_tol of a run to
    cycle_tol 1e-6."""
    case = per_length(COLD).with_physics(ring_pack="gas")
    case = case.with_ring(width=0.807e-3, tension=4.756)
    case = case.with_ring_pack(land_volume=1.83e-3, second_gap_area=2.26e-9)
    r, tight = ringlube.run(case), _tight(case)
    tol = case.value("numerics", "cycle_tol")
    assert r.converged and r.cycles_run >= 2, r.cycles_run
    assert abs(r.energy_loss / tight.energy_loss - 1) <= tol, (r.energy_loss, tight.energy_loss)
    assert abs(r.blowby / tight.blowby - 1) <= tol, (r.blowby, tight.blowby)


@pytest.mark.parametrize("deck", ["crf450r_4000rpm_full_cold.nml", "crf450r_3000rpm_half_cold.nml"])
def test_acceleration_changes_no_answer_beyond_cycle_tol(deck):
    """Starved 'trailing_gas' read in N/m: the liner film settles geometrically (by about 0.7 a
    cycle), 6 to 9 cycles. Extrapolated along its last change once two cycles show one mode
    (`accelerate`, the default) the run takes fewer cycles, and its answers (energy, oil to the
    chamber, mixed share, liner film) equal those of a run without it and those of a run to
    cycle_tol 1e-6 within cycle_tol."""
    case = per_length(INPUTS / deck)
    case = case.with_physics(cavitation="jfo", inlet="starved", cavity_pressure="trailing_gas")
    fast, plain = ringlube.run(case), ringlube.run(case.with_numerics(accelerate=False))
    tight = _tight(case.with_numerics(accelerate=False))
    tol = case.value("numerics", "cycle_tol")
    assert fast.converged and plain.converged and tight.converged
    assert fast.cycles_run < plain.cycles_run, (fast.cycles_run, plain.cycles_run)
    _assert_same_periodic_state(fast, (plain, tight), tol)


def test_a_single_excursion_is_not_a_period_of_two():
    """The distorted bore of identical.py's variant (order 4, 10 um, 8 sectors; starved, read in N,
    with the N/m reading's calibration): with an earlier kernel, after its liner film's
    extrapolation cycle 5 ran one cycle in another state, 1.865 J between cycles of 1.597 J, and
    cycle 6 equalled cycle 4, so a period of two was taken with the mean of cycles 5 and 6,
    1.7310 J, 8 % high (a period of two checked only its last cycle's energy against two cycles
    before). Both cycles of a period of two repeat now (`ctest -R periodicity/one_odd_cycle`): the
    run is periodic, with a period of one, and the energy of a run without the extrapolation,
    within cycle_tol. Its liner film settles slowly (its change over a cycle 1e-3 at cycle 10,
    1.7e-5 from cycle 20 on): 15 cycles at 2.1589 J, 14 without the extrapolation at 2.1591 J
    (neither periodic in 10 cycles before the rate was judged either)."""
    case = per_length(COLD).with_physics(cavitation="jfo", inlet="starved", bore="distorted")
    case = case.with_("bore", order=[4], amplitude=[10e-6], sectors=8).with_ring(tension_unit="N")
    case = case.with_numerics(max_cycles=20)
    r, plain = ringlube.run(case), ringlube.run(case.with_numerics(accelerate=False))
    assert r.converged and plain.converged and r.period == 1, (r.cycles_run, r.period)
    assert abs(r.energy_loss / plain.energy_loss - 1) <= case.value("numerics", "cycle_tol")


GAS_12000 = INPUTS / "crf450r_12000rpm_full_hot_gas.nml"


@pytest.mark.parametrize("physics", [{}, {"cavitation": "jfo"}], ids=["swift_stieber", "jfo_flooded"])
def test_pilot_cycle_changes_no_answer_beyond_cycle_tol(physics):
    """The 12,000 r/min 'gas' deck as shipped (read in N): the film's friction moves the land's
    periodic state, so a ring pack started without it restarts after the first cycle and needs
    two cycles more (3 cycles run). Started from the gas network's periodic state under the
    friction of a pilot cycle at 8 times the crank step (`pilot_cycle`) the second cycle, which
    continued the first, is periodic; energy and blowby equal those of a run without the pilot
    and of one to cycle_tol 1e-6 within cycle_tol."""
    case = Case.from_namelist(GAS_12000).with_physics(**physics)
    fast, plain = ringlube.run(case.with_numerics(pilot_cycle=True)), ringlube.run(case)
    tight = _tight(case)
    tol = case.value("numerics", "cycle_tol")
    assert fast.converged and plain.converged and tight.converged
    assert (fast.cycles_run, plain.cycles_run) == (2, 3)
    for other in (plain, tight):
        assert abs(fast.energy_loss / other.energy_loss - 1) <= tol, (fast.energy_loss, other.energy_loss)
        assert abs(fast.blowby / other.blowby - 1) <= tol, (fast.blowby, other.blowby)


def test_after_a_pilot_the_first_cycle_is_not_judged_on_its_energy():
    """The 12,000 r/min 'gas' deck with the N/m reading's calibration (test above): started under
    the pilot cycle's friction its first cycle moved h0 at psi = 0 and the ring pack by less than
    cycle_tol, and judged like a first cycle after the warm-up (the energy by the ring's state) it
    was taken at 2.2748 J, 1.6 % above its periodic 2.2380 J with the pilot at 4 times the crank
    step (at 8 times, now: 2.2639 J, 1.2 % above, h0 at psi = 0 and the ring pack 3.6e-4 and
    3.2e-4 from their periodic states; `tests/bench/cycle_trace.py --pilot --per-length --unit N
    --ref`): the energy still moves with the coupled state (its groove pressure carries most of
    the load). Its energy is judged now only
    by a cycle that continued it: the answer lies within cycle_tol of a run to cycle_tol 1e-6."""
    case = per_length(GAS_12000).with_ring(tension_unit="N")
    r, tight = ringlube.run(case.with_numerics(pilot_cycle=True)), _tight(case)
    tol = case.value("numerics", "cycle_tol")
    assert r.converged and tight.converged and r.cycles_run >= 2
    assert abs(r.energy_loss / tight.energy_loss - 1) <= tol, (r.energy_loss, tight.energy_loss)
    assert abs(r.blowby / tight.blowby - 1) <= tol


@pytest.mark.parametrize("dpsi, steps", [(2.0, 360), (4.0, 180)])
def test_pilot_cycle_counts_its_crank_steps(dpsi, steps):
    """cycles_computed counts the pilot's crank steps as the run's: on the 12,000 r/min 'gas' deck
    (Swift-Stieber) the pilot runs at 8 times the crank step where the cycle's steps divide by 8
    (2 deg: 360 steps), else at 4 times (4 deg: 180 steps), so at 16 deg either way: its 270 deg
    of warm-up (the ring pack's) and its cycle are 17 + 45 steps (270 deg at 16 deg: 16.875, run
    as 17 whole steps) of the run's 360 or 180 per cycle; the run's own warm-up is the film's 90
    deg (the ring pack's 270 deg only without a pilot) and each cycle adds its closing step at
    720 deg."""
    r = ringlube.run(Case.from_namelist(GAS_12000).with_numerics(pilot_cycle=True, dpsi_deg=dpsi))
    n = r.cycles_run
    expected = n + (90 + dpsi * n) / 720 + (17 + 45) / steps
    assert r.scalars["cycles_computed"] == pytest.approx(expected, rel=1e-12)


def test_a_starved_ring_pack_starts_under_the_pilot_s_friction():
    """The 12,000 r/min 'gas' deck starved (read in N): without the pilot the ring pack starts
    without the film's friction, restarts after the first cycle, the cycle after that restart
    cannot be judged on its energy, and the run takes 4 cycles. With `pilot_cycle` the pilot
    (starved, at 4 times the crank step, with its own BDC start) gives only the ring pack its
    start; the film starts at BDC as without it (its liner film is not taken from the pilot,
    which lies 4 % from the crank step's: tests/bench/coarse_liner.py). Periodic after 3 cycles,
    its energy and blowby within cycle_tol of the run without it and of one to cycle_tol 1e-6;
    cycles_computed counts the pilot's crank steps, its BDC start's second pass included: 34 of
    warm-up, 11 of that pass (500 to 580 deg at 8 deg) and 90 of its cycle, of 360 per cycle."""
    case = Case.from_namelist(GAS_12000).with_physics(cavitation="jfo", inlet="starved")
    r, plain = ringlube.run(case.with_numerics(pilot_cycle=True)), ringlube.run(case)
    tight = _tight(case)
    tol = case.value("numerics", "cycle_tol")
    assert r.converged and plain.converged and tight.converged
    assert (r.cycles_run, plain.cycles_run) == (3, 4)
    for other in (plain, tight):
        assert abs(r.energy_loss / other.energy_loss - 1) <= tol, (r.energy_loss, other.energy_loss)
        assert abs(r.blowby / other.blowby - 1) <= tol, (r.blowby, other.blowby)
    # the run's own warm-up (270 deg), its BDC start's second pass (500 to 580 deg at 2 deg: 41
    # steps), each cycle's closing step, and the pilot
    n = r.cycles_run
    expected = n + (270 + 82 + 2 * n) / 720 + (34 + 11 + 90) / 360
    assert r.scalars["cycles_computed"] == pytest.approx(expected, rel=1e-12)


def test_a_ring_pack_at_its_periodic_state_is_not_restarted_after_the_first_cycle():
    """The 4000 r/min 'gas' deck starved, read in N/m: the first cycle is not periodic (its liner
    film changes by 4.8e-2 over 50 cells) while its ring pack lies 1.0e-5 from the periodic state
    of the gas network under that cycle's friction. Restarted there anyway (`first_restart =
    'always'`, the rule before) the second cycle cannot be judged on its energy and the run takes
    3 cycles; with the default 'away' the second cycle continues the first and is periodic. Both
    answers lie within cycle_tol of each other and of a run to cycle_tol 1e-6."""
    case = Case.from_namelist(INPUTS / "crf450r_4000rpm_full_hot_gas.nml").with_ring(tension_unit="N/m")
    case = case.with_physics(cavitation="jfo", inlet="starved")
    away, always = ringlube.run(case), ringlube.run(case.with_numerics(first_restart="always"))
    tight = _tight(case)
    tol = case.value("numerics", "cycle_tol")
    assert away.converged and always.converged and tight.converged
    assert (away.cycles_run, always.cycles_run) == (2, 3)
    # (2 cycles, the 270 deg warm-up, the BDC start's second pass and no re-warm)
    assert away.scalars["cycles_computed"] == pytest.approx(2 + (270 + 82 + 2 * 2) / 720, rel=1e-12)
    for other in (always, tight):
        assert abs(away.energy_loss / other.energy_loss - 1) <= tol, (away.energy_loss, other.energy_loss)
        assert abs(away.blowby / other.blowby - 1) <= tol, (away.blowby, other.blowby)
    assert max(away.energy_change, away.liner_change, away.ring_pack_change) <= tol


@pytest.mark.parametrize(
    "deck",
    [
        "crf450r_4000rpm_full_cold.nml",
        "crf450r_8000rpm_full_hot_gas.nml",
        "crf450r_12000rpm_full_hot_gas.nml",
    ],
)
def test_bdc_start_reaches_the_same_periodic_state_in_fewer_cycles(deck):
    """Starved, read in N as shipped. The liner film a starved ring meets is the lower rings'
    but within about 5 mm of BDC, where it gathers the film it laid leaving the last BDC. From
    the supply film the warm-up brings the ring to BDC with too little oil, and the first cycle
    changes the liner film there by 1.6 % (4000 r/min cold; 3 cycles run); at 8000 and 12,000
    r/min the ring's lower edge is dry at BDC and the oil fills that strip by about a crank
    step's travel a cycle (5 and 6 cycles; `bdc_start = .false.`). With the BDC start (the
    default, `bdc_start`: the strip under the face at BDC flooded, the warm-up's BDC passed
    twice with the film laid leaving it the first time) the runs take fewer cycles, and their
    answers (energy, oil to the chamber, mixed share, liner film) equal those of a run without
    it and those of a run without it to cycle_tol 1e-6 within cycle_tol."""
    case = Case.from_namelist(INPUTS / deck).with_ring(tension_unit="N")
    case = case.with_physics(cavitation="jfo", inlet="starved")
    plain_case = case.with_numerics(bdc_start=False)
    r, plain = ringlube.run(case), ringlube.run(plain_case)
    tight = _tight(plain_case)
    tol = case.value("numerics", "cycle_tol")
    assert r.converged and plain.converged and tight.converged
    assert r.cycles_run < plain.cycles_run, (r.cycles_run, plain.cycles_run)
    _assert_same_periodic_state(r, (plain, tight), tol)


def test_bdc_start_first_cycle_h0_equals_the_periodic_state():
    """On the cold deck starved, read in N, the first cycle after the BDC start changed the
    liner film by 4.1e-4 (L1 over the whole film, which the film away from BDC dominates) and
    passed, with h0 before BDC (psi = 160 deg) 3.4e-3 (relative to the largest h0) from its
    periodic value and the energy within 1.6e-5. With `bdc_start` (the default) the liner film's
    change is also measured over every 50 cells (`liner_window` 0 taken as 50): the film near
    BDC, still settling, takes a second cycle, and the accepted run's h0 equals that of the
    plain start's long warm-up and many cycles at a tolerance 1e6 times tighter, to the cycle
    tolerance at every step."""
    case = Case.from_namelist(COLD).with_physics(cavitation="jfo", inlet="starved")
    r = ringlube.run(case)
    ref = ringlube.run(case.with_numerics(bdc_start=False, warmup_deg=720, cycle_tol=1e-9, max_cycles=30))
    tol = case.value("numerics", "cycle_tol")
    assert r.converged and ref.periodic
    assert np.abs(r.h0 - ref.h0).max() <= tol * np.abs(ref.h0).max()


def test_the_accurate_preset_starts_plainly_unless_told():
    """'accurate' (0.25 deg) starts a starved 'vapour' run plainly: there the strip near BDC
    that the BDC start's window judges fills by a crank step's travel a cycle (the cold deck
    read in N took 25 cycles against the plain start's 13). Its first cycles are the explicit
    plain start's to the bit, and an explicit `bdc_start` still overrides the preset."""
    case = Case.from_namelist(COLD).with_physics(cavitation="jfo", inlet="starved")
    acc = case.with_numerics(preset="accurate", max_cycles=1)
    preset, plain, bdc = (
        ringlube.run(c) for c in (acc, acc.with_numerics(bdc_start=False), acc.with_numerics(bdc_start=True))
    )
    assert preset.energy_loss == plain.energy_loss and np.array_equal(preset.h0, plain.h0)
    assert bdc.cycles_computed > plain.cycles_computed  # the BDC start's second pass counts
    assert bdc.energy_loss != plain.energy_loss


@pytest.mark.parametrize("ring_pack", ["none", "gas"])
@pytest.mark.parametrize("deck, unit", [("cold", "N/m"), ("hot", "N/m"), ("cold", "N"), ("hot", "N")])
def test_bdc_start_accepted_run_equals_its_periodic_state(deck, unit, ring_pack):
    """`test_accepted_starved_run_equals_its_periodic_state` (test_oil_supply.py) with the BDC
    start (the default): the accepted run's energy, oil to the chamber, mixed and lifted shares
    and h0 at every step equal, to cycle_tol, those of the run continued from the same start to
    cycle_tol 1e-9 (30 cycles at most) and those of the plain start's (`bdc_start = .false.`)
    720 deg warm-up and 30 cycles at 1e-9. Not against the BDC start after a 720 deg warm-up:
    the hot deck read in N/m without the ring pack has two periodic states, and that start
    takes the other one (mixed share 26.0 % against 27.5 %, energy 1.05e-4 higher), while both
    references above take the one the default run takes."""
    case = Case.from_namelist(COLD.with_name(f"crf450r_4000rpm_full_{deck}.nml"))
    case = per_length(case) if unit == "N/m" else case
    case = case.with_physics(cavitation="jfo", inlet="starved", ring_pack=ring_pack)
    r = ringlube.run(case)
    same = ringlube.run(case.with_numerics(cycle_tol=1e-9, max_cycles=30))
    plain = ringlube.run(case.with_numerics(bdc_start=False, warmup_deg=720, cycle_tol=1e-9, max_cycles=30))
    tol = case.value("numerics", "cycle_tol")
    assert r.periodic and r.converged and same.periodic and plain.periodic
    for ref in (same, plain):
        assert r.energy_loss == pytest.approx(ref.energy_loss, rel=tol)
        assert r.oil_to_chamber == pytest.approx(ref.oil_to_chamber, rel=tol, abs=1e-12)
        assert r.mixed_share == pytest.approx(ref.mixed_share, rel=tol)
        assert r.liner_lift_share == pytest.approx(ref.liner_lift_share, rel=tol, abs=1e-12)
        assert np.abs(r.h0 - ref.h0).max() <= tol * np.abs(ref.h0).max()


def _lift_off_alternating_trailing_gas() -> Case:
    """The cold deck starved 'trailing_gas' with the tension read in N/m (without that reading's
    calibration), max_cycles 30: the ring lifts off on alternate cycles (1.837 and 1.276 J) up to
    cycle 6 while the liner film near BDC settles, and from cycle 7 on every cycle is 1.276 J."""
    case = Case.from_namelist(COLD).with_ring(tension_unit="N/m")
    case = case.with_physics(cavitation="jfo", inlet="starved", cavity_pressure="trailing_gas")
    return case.with_numerics(max_cycles=30)


def test_a_film_still_settling_near_bdc_is_no_period_of_two():
    """On `_lift_off_alternating_trailing_gas`, judged on the whole film's L1 change alone,
    cycles 6 and 7 repeat cycles 4 and 5 within cycle_tol and the run was reported converged
    with a period of two at their mean, 1.5568 J, 22 % above the periodic state
    (`test_a_period_of_two_repeats_near_bdc_too`). With `liner_window` 50 (the change over any
    50 cells judged in the test of a period of one too) the film near BDC, still changing over
    50 cells, is seen: the accepted run has a period of one and equals a run to cycle_tol
    1e-6."""
    case = _lift_off_alternating_trailing_gas().with_numerics(liner_window=50)
    r, tight = ringlube.run(case), _tight(case)
    tol = case.value("numerics", "cycle_tol")
    assert r.converged and tight.converged and tight.period == 1
    assert r.period == 1, (r.period, r.cycles_run)
    _assert_same_periodic_state(r, (tight,), tol)


def test_a_period_of_two_repeats_near_bdc_too():
    """Judged on the whole film's L1 change alone `_lift_off_alternating_trailing_gas` was
    accepted after 7 cycles with a period of two at 1.5568 J, 22 % above its periodic state:
    cycles 6 and 7 repeated cycles 4 and 5 within cycle_tol while the film near BDC still
    settled. With a 'trailing_gas' cavity a period of several cycles is compared over any 50
    liner cells as well (an orbit repeats everywhere; a period of one is still judged on the
    whole film, `liner_window` 0): the run is periodic after 8 cycles with a period of one and
    equals a run to cycle_tol 1e-6 (docs/model.md, "Judged at the rate it settles")."""
    case = _lift_off_alternating_trailing_gas()
    r, tight = ringlube.run(case), _tight(case)
    tol = case.value("numerics", "cycle_tol")
    assert r.converged and tight.converged and tight.period == 1
    assert r.period == 1, (r.period, r.cycles_run)
    _assert_same_periodic_state(r, (tight,), tol)
