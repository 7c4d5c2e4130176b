"""The mass-conserving film and the starved inlet in the cycle: the oil
balance closes, starvation never breaks a run, the optional results are written and read
back by name, and the extremes of the stability matrix hold with the new film models. Tests of
the intake-stroke lift-off and of states found on the decks read in N/m take them through
``conftest.per_length``."""

from __future__ import annotations

import itertools

import h5py
import numpy as np
import pytest

import ringlube
from ringlube import Case
from ringlube.executor import Executor
from ringlube.study.variables import DESIGN_RANGES
from ringlube.tables import FLAGS

from conftest import COLD, HOT, per_length

pytestmark = pytest.mark.numerics

FAST = {"preset": "fast"}


@pytest.fixture(scope="module")
def cold() -> Case:
    return Case.from_namelist(COLD)


@pytest.mark.parametrize("cavity", ["vapour", "trailing_gas"])
def test_oil_balance_closes_over_the_cycle(cold, cavity):
    """Oil in (supply film laid) = oil out (to the chamber, taken down) + change of the oil
    stored on the liner, in the bank and in the gap: to round-off, not to a tolerance."""
    r = ringlube.run(cold.with_physics(cavitation="jfo", inlet="starved", cavity_pressure=cavity))
    assert r.oil_balance_error <= 1e-10, r.oil_balance_error
    assert r.oil_to_chamber >= 0 and np.isfinite(r.oil_to_chamber)
    assert (r.inlet_fill >= 0).all() and (r.inlet_fill <= 1).all()
    assert (r.wetted_width >= 0).all() and (r.wetted_width <= cold["ring", "width"] + 1e-12).all()
    assert (r.oil_bank >= 0).all() and (r.oil_left >= 0).all()
    assert r.liner["liner_oil_film"].min() >= 0
    assert not (r.flags & FLAGS["inlet_overdraw"]).any(), "the inlet drew more oil than there was"
    assert r.converged and not (r.flags & FLAGS["cavitation"]).any(), "every step's connectivity loop settles"


@pytest.mark.parametrize("unit", ["N", "N/m"])
@pytest.mark.parametrize("cavity", ["vapour", "trailing_gas"])
def test_bdf2_film_oil_balance_closes_over_the_cycle(cold, cavity, unit):
    """`film_time_scheme = 'bdf2'`: the film's content by BDF2, the oil it exchanges with the
    liner and the bank filtered alike (docs/film_model.md, "Time integration in the cycle"),
    so the cycle's oil balance still closes to round-off, and no edge draws more oil than
    there is; in both readings of the tension."""
    from conftest import per_length

    case = cold if unit == "N" else per_length(cold)
    case = case.with_physics(cavitation="jfo", inlet="starved", cavity_pressure=cavity)
    r = ringlube.run(case.with_numerics(film_time_scheme="bdf2", max_cycles=20))
    assert r.converged, r.cycles_run
    assert r.oil_balance_error <= 1e-10, r.oil_balance_error
    assert r.oil_to_chamber >= 0 and np.isfinite(r.oil_to_chamber)
    assert (r.inlet_fill >= 0).all() and (r.inlet_fill <= 1).all()
    assert (r.oil_bank >= 0).all() and (r.oil_left >= 0).all()
    assert r.liner["liner_oil_film"].min() >= 0
    assert not (r.flags & FLAGS["inlet_overdraw"]).any(), "the inlet drew more oil than there was"
    euler = ringlube.run(case.with_numerics(film_time_scheme="euler", max_cycles=20))
    assert r.energy_loss != euler.energy_loss, "the option reaches the film"


@pytest.mark.parametrize("deck", ["cold", "hot"])
def test_trailing_gas_connectivity_settles(deck):
    """The cavity-pressure rule can alternate between two zone sets (a meniscus between two
    nodes); the loop must end that, not run to its cap and flag the step (it did on the cold
    deck before)."""
    case = Case.from_namelist(COLD.with_name(f"crf450r_4000rpm_full_{deck}.nml"))
    r = ringlube.run(case.with_physics(cavitation="jfo", cavity_pressure="trailing_gas"))
    assert r.converged and not (r.flags & FLAGS["cavitation"]).any()


@pytest.mark.parametrize("deck", ["cold", "hot"])
def test_starved_first_cycle_is_periodic_and_right(deck):
    """A starved run warms up over the last upstroke (and 90 deg before it), so its first cycle
    passes the periodicity test and its results equal those of a long warm-up and many cycles
    at a tolerance 1e6 times tighter, to the cycle tolerance. With a 5 um supply film, where
    the ring does not lift off on these decks: at the default 1 um the ring lifts off on the
    intake stroke, the liner film's slow mode is larger and a run takes up to 6 cycles
    (docs/model.md, "Periodicity")."""
    case = Case.from_namelist(COLD.with_name(f"crf450r_4000rpm_full_{deck}.nml"))
    case = case.with_physics(cavitation="jfo", inlet="starved").with_("lubricant", supply_film=5e-6)
    r = ringlube.run(case)
    ref = ringlube.run(case.with_numerics(warmup_deg=720, cycle_tol=1e-9, max_cycles=20))
    tol = case.value("numerics", "cycle_tol")
    assert r.periodic and r.cycles_run == 1
    # (the reference repeats to 1e-9 within its long warm-up and one or two cycles since the
    # liner film has no cell-aliasing spikes; it took 3 or more before)
    assert ref.periodic
    assert r.energy_loss == pytest.approx(ref.energy_loss, rel=tol)
    assert r.oil_to_chamber == pytest.approx(ref.oil_to_chamber, rel=tol)
    film, film_ref = r.liner["liner_oil_film"], ref.liner["liner_oil_film"]
    assert np.abs(film - film_ref).sum() <= tol * np.abs(film_ref).sum()


@pytest.mark.parametrize("ring_pack", ["none", "gas"])
@pytest.mark.parametrize(
    "deck, unit",
    [
        ("cold", "N/m"),
        ("hot", "N/m"),
        ("cold", "N"),
        ("hot", "N"),
    ],
)
def test_accepted_starved_run_equals_its_periodic_state(deck, unit, ring_pack):
    """At the shipped 1 um supply film the periodicity test looks at the liner film and the
    energy only. Every other result of the accepted run must equal that of a long warm-up and
    30 cycles at a tolerance 1e6 times tighter, to the cycle tolerance too: the oil to the
    chamber, the mixed and lifted shares and h0 at every step (a run accepted while
    those still moved would report them wrongly). Read in N/m, without the ring pack the ring
    lifts off for a quarter of the cycle and the liner film alternates between two cycles
    (docs/model.md "Periodicity"); the reference then ends unperiodic at 30 cycles and is
    compared anyway. Read in N (the shipped decks) the cold deck was accepted after 2.5 cycles
    with its mixed share 2e-3 and its h0 1.9e-3 (relative) from the periodic state, twice
    cycle_tol; judged at the rate each quantity settles it runs a third cycle and passes. The
    plain start (`bdc_start = .false.`; the BDC start, the default, in
    `test_bdc_start_accepted_run_equals_its_periodic_state`)."""
    case = Case.from_namelist(COLD.with_name(f"crf450r_4000rpm_full_{deck}.nml"))
    case = per_length(case) if unit == "N/m" else case
    case = case.with_physics(cavitation="jfo", inlet="starved", ring_pack=ring_pack)
    case = case.with_numerics(bdc_start=False)
    r = ringlube.run(case)
    ref = ringlube.run(case.with_numerics(warmup_deg=720, cycle_tol=1e-9, max_cycles=30))
    tol = case.value("numerics", "cycle_tol")
    assert r.periodic and r.converged
    assert r.energy_loss == pytest.approx(ref.energy_loss, rel=tol)
    assert r.oil_to_chamber == pytest.approx(ref.oil_to_chamber, rel=tol, abs=1e-12)
    assert r.mixed_share == pytest.approx(ref.mixed_share, rel=tol)
    assert r.liner_lift_share == pytest.approx(ref.liner_lift_share, rel=tol, abs=1e-12)
    assert np.abs(r.h0 - ref.h0).max() <= tol * np.abs(ref.h0).max()


@pytest.mark.parametrize("deck", ["cold", "hot"])
def test_flooded_jfo_first_cycle_is_periodic(deck):
    """The flooded mass-conserving film with a vapour cavity warms up over 270 deg like the
    starved one (its cavity's content remembers the initial full film longer than 90 deg:
    with the 90 deg of the deck every shipped deck took a second cycle), so its first cycle is
    periodic and equals a long warm-up and many cycles at a tolerance 1e6 times tighter."""
    case = Case.from_namelist(COLD.with_name(f"crf450r_4000rpm_full_{deck}.nml"))
    case = case.with_physics(cavitation="jfo")
    r = ringlube.run(case)
    ref = ringlube.run(case.with_numerics(warmup_deg=720, cycle_tol=1e-9, max_cycles=20))
    tol = case.value("numerics", "cycle_tol")
    assert r.periodic and r.cycles_run == 1, r.cycles_run
    assert ref.periodic
    assert r.energy_loss == pytest.approx(ref.energy_loss, rel=tol)
    assert r.mixed_share == pytest.approx(ref.mixed_share, rel=tol)


def test_supply_film_to_zero_never_breaks_the_run(cold):
    """Less oil supplied: less oil carried to the chamber, a thinner film over the upstrokes,
    and never a NaN (flags instead)."""
    starved = cold.with_physics(cavitation="jfo", inlet="starved").with_numerics(**FAST)
    cases = [starved.with_("lubricant", supply_film=f) for f in (20e-6, 5e-6, 2e-6, 0.5e-6, 0.0)]
    # with no supply the oil of the start-up film in the gap still reaches the chamber, less by
    # a factor 1e-7 every 10 cycles (4.7e-11 mm3 at the 10th: a blown face pushes it out of the
    # leading edge ahead of the ring, docs/model.md "Blown face"); 20 cycles leave 4e-18 mm3
    cases[-1] = cases[-1].with_numerics(max_cycles=20)
    results = ringlube.run_many(cases, workers=2, progress=False)
    for r in results:
        for name in ("h0", "friction", "power_loss", "inlet_fill", "oil_bank"):
            assert np.isfinite(getattr(r, name)).all(), name
        assert np.isfinite(r.energy_loss) and r.energy_loss > 0
    oil = [r.oil_to_chamber for r in results]
    assert all(a > b for a, b in zip(oil, oil[1:-1])), oil
    assert results[-1].oil_to_chamber == pytest.approx(0.0, abs=1e-12)
    up = results[0].sliding_speed < 0  # upstrokes: the supply film is what the ring meets
    fills = [r.inlet_fill[up].mean() for r in results]
    assert all(a >= b for a, b in zip(fills, fills[1:])), fills


@pytest.mark.cli
def test_optional_results_round_trip_and_layout(cold, tmp_path, solver):
    import subprocess

    case = cold.with_physics(cavitation="jfo", inlet="starved").with_numerics(**FAST)
    r = ringlube.run(case, output=tmp_path / "s.h5")
    assert {"inlet_fill", "wetted_width", "oil_left", "oil_bank"} <= set(r.series)
    assert {"oil_to_chamber", "oil_balance_error"} <= set(r.scalars)
    back = ringlube.load(r.path)
    for k in r.series:
        np.testing.assert_array_equal(getattr(back, k), getattr(r, k))
    for k in r.liner:
        np.testing.assert_array_equal(back.liner[k], r.liner[k])
    with h5py.File(tmp_path / "s.h5") as f:
        assert f.attrs["oil_to_chamber_mm3"] == r.oil_to_chamber
        assert f["liner/oil_film_m"].shape == f["liner/position_m"].shape
        assert f["liner/oil_film_m"].attrs["units"] == "m"
    # Swift-Stieber runs write none of them
    ss = ringlube.run(cold.with_numerics(**FAST))
    assert "inlet_fill" not in ss.series and not ss.liner and "oil_to_chamber" not in ss.scalars
    # the standalone program writes the same file
    deck = tmp_path / "s.nml"
    case.to_namelist(deck)
    subprocess.run([solver, "-q", str(deck), "-o", str(tmp_path / "cli.h5")], check=False)
    cli = ringlube.load(tmp_path / "cli.h5")
    np.testing.assert_array_equal(cli.oil_bank, r.oil_bank)
    assert cli.oil_to_chamber == r.oil_to_chamber


def test_starved_needs_the_mass_conserving_film(cold):
    with pytest.raises(ringlube.InputError, match=r"&physics inlet: 'starved' needs"):
        cold.with_physics(inlet="starved").validate()


CORNERS = DESIGN_RANGES  # the study's design box (one home: ringlube.study.variables)


@pytest.mark.parametrize(
    "physics",
    [
        {"cavitation": "jfo"},
        {"cavitation": "jfo", "inlet": "starved"},
        {"cavitation": "jfo", "cavity_pressure": "trailing_gas"},
    ],
    ids=["jfo", "jfo_starved", "jfo_trailing_gas"],
)
def test_design_corners_with_the_new_film_models(cold, physics):
    """The 16 design corners at two speeds and two liner temperatures: finite results,
    h0 > 0, the load balanced at every unflagged step, flags where it is not."""
    base = cold.with_physics(**physics).with_numerics(**FAST)
    cases = [
        base.with_ring(**dict(zip(CORNERS, v[:4]))).with_operating(speed_rpm=v[4], liner_temperature=v[5])
        for v in itertools.product(*CORNERS.values(), (1000, 8000), (348.0, 423.0))
    ]
    for r in ringlube.run_many(cases, workers=2, progress=False):
        assert np.isfinite(r.h0).all() and (r.h0 > 0).all()
        assert np.isfinite(r.friction).all() and np.isfinite(r.energy_loss)
        unflagged = r.flags == 0
        assert (np.abs(r.load_residual[unflagged]) <= 3e-3 * (1 + 1e-9)).all()
        if ((r.flags & ~2) != 0).any():  # flag 2 (lift-off at h0_ceiling) is an answer
            assert not r.converged


def test_liner_and_supply_figures(cold, tmp_path):
    from ringlube.plot import liner_figure, plot_results, supply_figure

    r = ringlube.run(cold.with_physics(cavitation="jfo", inlet="starved").with_numerics(**FAST))
    files = plot_results([r], tmp_path, formats=("png",))
    assert {f.stem.rsplit("_", 1)[1] for f in files} == {"friction", "film", "supply", "liner", "gas"}
    fig = liner_figure([r])
    np.testing.assert_allclose(fig.axes[0].lines[0].get_ydata(), r.liner["liner_oil_film"] * 1e6)
    fig = supply_figure([r])
    np.testing.assert_array_equal(fig.axes[0].lines[0].get_ydata(), r.inlet_fill)


@pytest.mark.slow
def test_study_trades_friction_against_oil_transport(tmp_path, cold):
    """oil_to_chamber as a study objective: recorded for every design of a starved
    base deck, fitted and optimised; refused, naming the deck, where a base deck does not
    produce it."""
    from ringlube.study import run_study
    from ringlube.study.deck import read_study

    deck = tmp_path / "starved.nml"
    cold.with_physics(cavitation="jfo", inlet="starved").with_numerics(**FAST).to_namelist(deck)
    study = tmp_path / "oil.nml"
    study.write_text(
        "&study\n  name = 'oil'\n"
        f"  cases = '{deck}'\n  labels = 'cold'\n"
        "  variables = 'width', 'crown_offset'\n"
        "  objectives = 'energy_loss', 'oil_to_chamber'\n"
        "  samples = 24, sampler = 'sobol', seed = 3\n"
        "  population = 16, generations = 6, repeats = 2\n/\n"
    )
    st = run_study(study, tmp_path / "out", executor=Executor(serial=True), progress=False, figures=False)
    assert "oil_to_chamber" in st.s.outputs
    j = st.s.outputs.index("oil_to_chamber")
    oil = st.cases["cold"].runs.outputs[:, j]
    assert np.isfinite(oil).all() and (oil > 0).all()
    assert "oil_to_chamber" in st.cases["cold"].surfaces
    assert st.cases["cold"].front.f.shape[1] == 2
    flooded = tmp_path / "flooded.nml"
    study.write_text(study.read_text().replace(str(deck), str(COLD)))
    with pytest.raises(
        ringlube.InputError,
        match=r"&study objectives: 'oil_to_chamber' needs "
        r"&physics inlet = 'starved'",
    ):
        read_study(study)
    assert not flooded.exists()


@pytest.mark.slow
def test_starved_hot_energy_converges_in_the_crank_step():
    """Refining the crank step from 0.25 to 0.125 deg moves the starved hot energy by under 2 %
    (with a gas-only trailing edge the face ran dry after TDC at 0.125 deg, 2.03 ->
    1.72 J; the liquid trailing edge encloses that cavity)."""
    case = Case.from_namelist(COLD.with_name("crf450r_4000rpm_full_hot.nml"))
    case = case.with_physics(cavitation="jfo", inlet="starved")
    case = case.with_numerics(nodes=201, pressure_tol=1e-8, load_tol=1e-6, cycle_tol=1e-4)
    case = case.with_numerics(max_cycles=20)
    for supply in (1e-6, 5e-6):
        runs = [
            ringlube.run(case.with_numerics(dpsi_deg=d).with_("lubricant", supply_film=supply))
            for d in (0.25, 0.125)
        ]
        # at 1 um the liner film's slow mode keeps the tight periodicity test from passing
        # within 20 cycles (h0 repeats to 1e-14; docs/model.md, "Periodicity")
        assert all(r.converged for r in runs) or supply < 5e-6, supply
        assert runs[1].energy_loss == pytest.approx(runs[0].energy_loss, rel=0.02), supply


def test_trailing_gas_cold_energy_converges_in_nodes():
    """Doubling the nodes must not change the trailing-gas energy by more than 2 % (it was
    0.72 / 0.59 J at 201 / 401 nodes). On the expansion stroke the chamber gas in the open
    cavity reaches the leading edge (the face is partly filled across its width, a blown face):
    the oil entering there was blown back out over one cell at a rate k dp/dx, so the face's
    fill, its shear and the load of the edge cell scaled with the cell size. The leading edge
    of a blown face admits gas only and its meniscus is at the edge (docs/model.md, "Blown
    face")."""
    case = Case.from_namelist(COLD).with_physics(cavitation="jfo", cavity_pressure="trailing_gas")
    case = case.with_numerics(dpsi_deg=0.25)
    coarse, fine = (ringlube.run(case.with_numerics(nodes=n)) for n in (201, 401))
    assert coarse.converged and fine.converged
    assert fine.energy_loss == pytest.approx(coarse.energy_loss, rel=0.02)


@pytest.mark.xfail(strict=True, reason="step-size bistability, not fixed")
@pytest.mark.parametrize(
    "physics",
    [
        {"cavitation": "jfo", "cavity_pressure": "trailing_gas"},
        {"cavitation": "jfo", "inlet": "starved"},
    ],
    ids=["trailing_gas", "starved"],
)
@pytest.mark.known_limitation
def test_default_preset_takes_the_branch_of_the_converged_run(physics):
    """The 'default' preset (51 nodes, 2 deg) within 0.5 % in energy of 'accurate' (201 nodes,
    0.25 deg; 0.04 % / -0.3 % from the 801-node, 0.125-deg reference) on the cold deck. It is
    not: two branches exist and the crank step picks one. On the shipped deck (tension read in
    N) 'trailing_gas' is 7.2 % low and the starved film 0.6 % (docs/performance.md, "Step-size
    bistability"). Read in N/m both are far apart: 'trailing_gas', after firing TDC the chamber
    gas in the open cavity blows through the face at 0.5 deg and below (0.426 J) but the film
    seals the face at 1-2 deg (0.78 J); starved, the intake-stroke applied load (elastic plus
    chamber pressure) is 0.45 % below the load of a face open to the crankcase gas, the film
    holds within that margin at 0.5 deg and below, and at 2 deg the face opens and the ring
    lifts off for 26.7 % of the cycle (2.250 against 2.861 J). With the plain start
    (`bdc_start = .false.`): with the BDC start, the default, 'accurate' is not periodic in its
    10 cycles either (its film near BDC still moving) and its last cycle happens to lie 0.49 %
    from 'default', which is no answer of this test."""
    case = Case.from_namelist(COLD).with_physics(**physics).with_numerics(bdc_start=False)
    default, accurate = (ringlube.run(case.with_numerics(preset=p)) for p in ("default", "accurate"))
    assert default.energy_loss == pytest.approx(accurate.energy_loss, rel=5e-3)


def test_lifted_ring_energy_does_not_depend_on_the_ceiling():
    """Where the film carries more than the load at every h0 (the intake stroke of the 3000
    r/min half-load deck, starved) h0 is held at h0_ceiling and the ring is lifted: its
    friction is that of unbounded separation (none), so neither energy nor oil depends on the
    numerical bound (it was 0.95 / 1.50 / 6.99 J at 1e-4 / 1e-3 / 1e-2 m; with the shear
    of the oil in the lifted gap, 0.80475 J at 1e-4 m against 0.80244 J at 1e-2 m, 0.29 %).
    At a 5 um supply film."""
    case = per_length(COLD.with_name("crf450r_3000rpm_half_cold.nml"))
    case = case.with_physics(cavitation="jfo", inlet="starved").with_("lubricant", supply_film=5e-6)
    runs = [ringlube.run(case.with_numerics(h0_ceiling=c)) for c in (1e-4, 1e-3, 1e-2)]
    lifted = [int(((r.flags & FLAGS["h0_ceiling"]) > 0).sum()) for r in runs]
    assert lifted[0] > 100 and lifted[0] == lifted[1] == lifted[2], lifted
    for r in runs[:2]:
        assert r.energy_loss == pytest.approx(runs[2].energy_loss, rel=1e-3)
        assert r.oil_to_chamber == pytest.approx(runs[2].oil_to_chamber, rel=1e-3)
    for r in runs:
        assert (r.friction[(r.flags & FLAGS["h0_ceiling"]) > 0] == 0).all()


def test_connectivity_cycles_of_five_sets_end():
    """A starved trailing-gas design whose connectivity loop met cycles of up to five sets of
    cavity pressures: with a history of four it ran 100 of its film solves to the cap of 200
    (135,786 Newton iterations a run); now every cycle ends in one more solve. A count, not a
    time."""
    case = Case.from_namelist(COLD).with_("calibration", file="")
    case = case.with_physics(
        cavitation="jfo", inlet="starved", cavity_pressure="trailing_gas", contact_area="lumped"
    )
    case = case.with_ring(tension_unit="N", width=1e-3).with_("surface", zeta_kappa_sigma=0.1)
    r = ringlube.run(case.with_operating(pressure_scale=1.2))
    assert r.converged
    assert r.reynolds_solves < 10 * r.total_film_solves, (r.reynolds_solves, r.total_film_solves)


@pytest.mark.parametrize("cavity", ["vapour", "trailing_gas"])
@pytest.mark.parametrize("nodes", [6, 11])
def test_oil_balance_at_round_off_on_coarse_grids(cold, nodes, cavity):
    """Starved trailing-gas runs on coarse grids closed the oil balance only
    to 6e-5 (6 nodes) and 2e-6 (11 nodes); with the caps inside the solve at both edges, the
    Gauss-Seidel fallback applying them too, it closes to round-off. At a reversal the liner
    changes first (the bank left on it, the lower rings' film): the oil the edges may draw
    on in that step is on the changed liner (1e-4 at 11 nodes, 'vapour', when the inlet's cap
    was taken from the liner before the change)."""
    case = cold.with_physics(cavitation="jfo", inlet="starved", cavity_pressure=cavity)
    r = ringlube.run(case.with_numerics(nodes=nodes))
    assert r.oil_balance_error <= 1e-12, r.oil_balance_error


def test_oil_balance_at_round_off_at_the_design_corner(cold):
    """The corner of the study's ranges (width 1.34 mm, crown 13 um, offset
    -54 um), starved trailing gas, closed the oil balance only to 2.6e-6; with the caps inside
    the solve at both edges it closes to round-off."""
    case = cold.with_physics(cavitation="jfo", inlet="starved", cavity_pressure="trailing_gas")
    r = ringlube.run(case.with_ring(width=1.34e-3, crown_height=13e-6, crown_offset=-54e-6))
    assert r.converged
    assert r.oil_balance_error <= 1e-12, r.oil_balance_error


@pytest.mark.slow
def test_damped_rule_that_does_not_contract_ends_flagged(cold):
    """With damping 0.999 the study's damped rule overshoots and oscillates;
    a starved run then spent max_load_iterations (2000) film solves at every step (over 100 s).
    It now stops a step once its best residual no longer falls (flagged 4): a count, not a
    time."""
    case = cold.with_physics(cavitation="jfo", inlet="starved").with_numerics(
        preset="fast", h0_update="damped", damping=0.999
    )
    r = ringlube.run(case)
    steps = r.crank_angle_deg.size * r.cycles_computed
    assert r.total_film_solves < 500 * steps, r.total_film_solves / steps
    assert not r.converged and ((r.flags & FLAGS["load"]) > 0).any()
    ok = ringlube.run(case.with_numerics(damping=0.005))
    assert ok.total_film_solves < 100 * steps


@pytest.mark.parametrize("deck", ["cold", "hot"])
def test_starved_ring_pack_default_preset_takes_the_branch_of_the_converged_run(deck):
    """Starved, with the ring pack's gas: 'default' (51 nodes, 2 deg) within 2 % in energy of
    'accurate' (201 nodes, 0.25 deg), both periodic (+0.5 % cold, +1.4 % hot). On the exhaust
    stroke the land pressure exceeds the chamber's and the face is blown; its leading edge
    admitted gas only, so at 0.5 deg and below the face stayed dry for the whole stroke, pushed
    the liner's oil ahead to the chamber (19 mm3 a cycle) and never repeated (cold 1.56 J
    against 2.86 J at 2 deg). It now admits the liner's oil by Couette transport
    (docs/model.md, "Blown face")."""
    case = Case.from_namelist(COLD if deck == "cold" else HOT)
    case = case.with_physics(cavitation="jfo", inlet="starved", ring_pack="gas")
    default, accurate = (ringlube.run(case.with_numerics(preset=p)) for p in ("default", "accurate"))
    assert default.converged and accurate.converged
    assert default.energy_loss == pytest.approx(accurate.energy_loss, rel=0.02)


@pytest.mark.parametrize(
    "deck",
    [
        "cold",
        pytest.param(
            "hot",
            marks=[
                pytest.mark.xfail(
                    strict=True, reason="hot: the default preset +18 % against the accurate one"
                ),
                pytest.mark.known_limitation,
            ],
        ),
    ],
)
def test_trailing_gas_ring_pack_default_preset_takes_the_branch_of_the_converged_run(deck):
    """Flooded 'trailing_gas' with the ring pack's gas: 'default' (51 nodes, 2 deg) within
    0.5 % in energy of 'accurate' (201 nodes, 0.25 deg). Cold it is (-0.17 %; without the ring
    pack +82 %, the strict xfail above), and the film converges in nodes there (0.648-0.641 J at
    51-401 nodes). Hot it is not (+18 %): on the exhaust stroke, land above chamber, the 2-deg
    steps fill the blown face again from about 548 deg and carry a sealing film to TDC; finer
    steps keep it blown (docs/performance.md, "Accuracy of the presets with the ring pack")."""
    case = per_length(COLD if deck == "cold" else HOT)
    case = case.with_physics(cavitation="jfo", cavity_pressure="trailing_gas", ring_pack="gas")
    default, accurate = (ringlube.run(case.with_numerics(preset=p)) for p in ("default", "accurate"))
    assert default.converged and accurate.converged
    assert default.energy_loss == pytest.approx(accurate.energy_loss, rel=5e-3)


@pytest.mark.parametrize("deck", ["cold", "hot"])
def test_oil_balance_at_round_off_with_zero_tension(deck):
    """With zero tension at 3000 r/min half load, starved 'trailing_gas', the
    ring lifts off for 38 % of the cycle and the balance closed only to 3e-8 (cold) and 1.1e-7
    (hot): at a reversal the edges' caps were taken from the liner before the reversal changed
    it (the bank left on it, the lower rings' film). The balance holds in every cycle, periodic
    or not: cold the run has no periodic state within cycle_tol (to cycle_tol 1e-7 its energy
    wanders over cycles 20-60 between 0.7692 and 0.7743 J, s.d. 0.14 %, and the liner film
    jumps by up to 2e-3 in a cycle), so whether it is reported converged in max_cycles is
    chance; the cycle reported has no flag but lift-off."""
    name = f"crf450r_3000rpm_half_{deck}.nml"
    case = per_length(COLD.with_name(name)).with_ring(tension=0)
    r = ringlube.run(case.with_physics(cavitation="jfo", inlet="starved", cavity_pressure="trailing_gas"))
    assert not (r.flags & ~FLAGS["h0_ceiling"]).any() and r.liner_lift_share > 30
    assert r.oil_balance_error <= 1e-10, r.oil_balance_error


@pytest.mark.parametrize(
    "deck, ring, ring_pack",
    [
        # (width, crown height, crown offset, tension in N/m) as drawn: whether a step meets a
        # long cycle is sensitive to the design's last digits
        (
            "3000rpm_half_hot",
            (9.625769015032538e-04, 1.4490533342674653e-05, 1.758688731345533e-04, 17.47423678563869),
            "none",
        ),
        (
            "4000rpm_full_hot",
            (1.4291863198433617e-03, 1.7240220572067936e-05, 5.7227551870431135e-05, 11.611268713147531),
            "none",
        ),
        (
            "4000rpm_full_cold",
            (1.1191850666587692e-03, 1.8498415437754826e-05, 7.556236065141224e-05, 15.963039638909876),
            "gas",
        ),
    ],
)
def test_connectivity_cycles_of_a_blown_face_end(deck, ring, ring_pack):
    """Starved 'trailing_gas' designs at the decks' numerics ('default': 51 nodes, 2 deg)
    whose face blows on the expansion stroke: with the blown face's leading edge at the
    face's gas level the connectivity loop met cycles of 17 or 18 sets of cavity pressures,
    and with a history of the last 16 it ran to its cap of 200 solves at every
    pressure-viscosity iteration of the step (flags 16, 4 and 8, not converged; the first
    design 0.1 s -> 9-18 s a run). Every cycle is now detected, however long (review of the
    blown-face change: 3 of 250 random designs of the study's ranges on the shipped decks).
    (max_cycles 20: the 4000 r/min cold design's liner film settles by 0.74 a cycle after its
    face's state changes in cycle 8, and is periodic within cycle_tol, judged at that rate,
    after 12 cycles; judged on its last change alone it was taken after 9.)"""
    width, crown_height, crown_offset, tension = ring
    case = Case.from_namelist(COLD.with_name(f"crf450r_{deck}.nml")).with_numerics(max_cycles=20)
    case = case.with_physics(
        cavitation="jfo", inlet="starved", cavity_pressure="trailing_gas", ring_pack=ring_pack
    )
    case = case.with_ring(width=width, crown_height=crown_height, crown_offset=crown_offset, tension=tension)
    r = ringlube.run(case)
    assert not (r.flags & (FLAGS["cavitation"] | FLAGS["load"] | FLAGS["viscosity"])).any()
    assert r.converged
    assert r.reynolds_solves < 10 * r.total_film_solves, (r.reynolds_solves, r.total_film_solves)


def test_lower_rings_beyond_the_stroke_lay_no_oil(cold):
    """`lower_ring_distance` may exceed the stroke (range 0-0.2 m): the lower rings then reach
    no part of the liner. At each BDC the film of their strip beyond the liner's grid was put
    on its last cell (37 mm of 'film' at 0.1 m, 142 mm at 0.2 m in /liner/oil_film_m, counted
    as oil supplied, so that the balance's scale grew with the distance and its error shrank:
    2.0e-12 / 5.2e-13 where the run closes to 9e-10). Beyond the stroke the distance changes
    nothing."""
    case = cold.with_physics(cavitation="jfo", inlet="starved")
    runs = [ringlube.run(case.with_ring(lower_ring_distance=d)) for d in (0.1, 0.2)]
    for r in runs:
        assert r.liner["liner_oil_film"].max() < 1e-3
    assert runs[0].energy_loss == runs[1].energy_loss
    assert runs[0].oil_balance_error == runs[1].oil_balance_error
    np.testing.assert_array_equal(runs[0].liner["liner_oil_film"], runs[1].liner["liner_oil_film"])


def test_oil_to_chamber_at_1_um_falls_with_the_crank_step(cold):
    """At the shipped 1 um supply film the oil to the chamber is a crank-step effect: the
    starved inlet takes in the oil it meets at the step's end speed times dt, less than the
    strip it sweeps on the slowing approach to TDC, and the bank left above the ring scales
    with dpsi^2 (0.036 mm3 a cycle at 2 deg, cold deck, 'trailing_gas'; docs/model.md,
    "Starved inlet"). Halving the step must divide it by about four: a transport the model
    resolved would converge to a finite value instead."""
    case = cold.with_physics(cavitation="jfo", inlet="starved", cavity_pressure="trailing_gas")
    oil = [ringlube.run(case.with_numerics(dpsi_deg=d)).oil_to_chamber for d in (2.0, 1.0, 0.5)]
    assert oil[0] > 0
    for coarse, fine in zip(oil, oil[1:]):
        assert 3.5 < coarse / fine < 4.5, oil


@pytest.mark.parametrize("cavity", ["vapour", "trailing_gas"])
@pytest.mark.parametrize("nodes", [11, 51])
def test_edge_cells_oil_balance_closes_over_the_cycle(cold, cavity, nodes):
    """`film_edge_cells = 'edge'` (the volumes next to the edges reach them; an inflow edge
    pushed back through takes the lesser of the supply and the full film's flux): still in
    flux form, so the cycle's oil balance closes to round-off with the gap's oil counted on
    the same volumes, and no edge draws more oil than there is."""
    case = cold.with_physics(cavitation="jfo", inlet="starved", cavity_pressure=cavity)
    num = {"film_time_scheme": "bdf2", "nodes": nodes, "max_cycles": 20}
    r = ringlube.run(case.with_numerics(film_edge_cells="edge", **num))
    assert r.converged, r.cycles_run
    assert r.oil_balance_error <= 1e-10, r.oil_balance_error
    assert (r.oil_bank >= 0).all() and (r.oil_left >= 0).all()
    assert r.liner["liner_oil_film"].min() >= 0
    assert not (r.flags & FLAGS["inlet_overdraw"]).any(), "the inlet drew more oil than there was"
    face = ringlube.run(case.with_numerics(film_edge_cells="face", **num))
    assert r.energy_loss != face.energy_loss, "the option reaches the film"


def test_edge_cells_oil_balance_closes_in_a_one_cycle_run():
    """A run whose first cycle is its answer (hot, 5 um: one cycle at 'default') counts the
    gap's oil at the cycle's start on the edges' cells too (the film starts full, so the half
    cells' oil is there from the first step)."""
    case = Case.from_namelist(HOT).with_physics(cavitation="jfo", inlet="starved")
    case = case.with_("lubricant", supply_film=5e-6)
    r = ringlube.run(case.with_numerics(film_time_scheme="bdf2", film_edge_cells="edge"))
    assert r.cycles_run == 1, r.cycles_run
    assert r.oil_balance_error <= 1e-10, r.oil_balance_error


def test_edge_cells_oil_to_chamber_nearer_the_fine_grid():
    """The hot deck starved at 1 um (BDF2, 2 deg): at 51 nodes the oil to the chamber was
    +53 % off the 401-node answer (0.1150 against 0.0754 mm^3), because the film's volumes
    ended half a cell in from the edges: near the top dead centre the leading edge's half
    cell took no oil and the film turned it back into the bank a node early. With the edges'
    cells the 51-node answer is +17 % off (0.0885), less than half the error (docs/film_model.md,
    "Edge cells")."""
    case = Case.from_namelist(HOT).with_physics(cavitation="jfo", inlet="starved")
    case = case.with_("lubricant", supply_film=1e-6).with_numerics(film_time_scheme="bdf2")
    ref = ringlube.run(case.with_numerics(nodes=401, film_edge_cells="face")).oil_to_chamber
    face = ringlube.run(case.with_numerics(nodes=51, film_edge_cells="face")).oil_to_chamber
    edge = ringlube.run(case.with_numerics(nodes=51, film_edge_cells="edge")).oil_to_chamber
    assert abs(edge - ref) < abs(face - ref) / 2, (face, edge, ref)


@pytest.mark.parametrize("supply", [1e-6, 2e-6])
def test_front_cells_close_the_oil_balance_and_come_nearer_the_fine_grid(supply):
    """`film_edge_cells = 'front'` (experimental: 'edge' with the reformation fronts' cells
    holding their front's oil): the content the cycle carries from step to step is the
    fronts' content (not theta h), so the oil balance closes to round-off only if the cycle
    hands that content on (theta h left it off by about 1e-3); at 'default' no step is
    flagged; and the hot deck's oil to the chamber at 51 nodes is nearer the 401-node 'edge'
    answer than 'edge''s own at 51 nodes (docs/film_model.md, "The reformation front")."""
    case = Case.from_namelist(HOT).with_physics(cavitation="jfo", inlet="starved")
    case = case.with_("lubricant", supply_film=supply).with_numerics(film_time_scheme="bdf2")
    r = ringlube.run(case.with_numerics(film_edge_cells="front"))
    assert r.oil_balance_error <= 1e-11, r.oil_balance_error
    assert r.flagged_steps == 0, r.flagged_steps
    ref = ringlube.run(case.with_numerics(nodes=401, film_edge_cells="edge")).oil_to_chamber
    edge = ringlube.run(case.with_numerics(film_edge_cells="edge")).oil_to_chamber
    assert abs(r.oil_to_chamber - ref) < abs(edge - ref) / 2, (r.oil_to_chamber, edge, ref)
