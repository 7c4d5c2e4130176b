"""Shared fixtures: paths to the shipped inputs and the standalone solver."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
INPUTS = ROOT / "inputs"
DECKS = sorted(INPUTS.glob("crf450r_*.nml"))
COLD = INPUTS / "crf450r_4000rpm_full_cold.nml"
HOT = INPUTS / "crf450r_4000rpm_full_hot.nml"
#: The calibration of the tension read in N/m (the shipped decks read it in N).
PER_LENGTH_CALIBRATION = INPUTS / "calibration_n_per_m.nml"


def per_length(case):
    """A shipped deck's case (a Case or a deck path) with the tension read in N/m and that
    reading's calibration: the inputs the shipped decks had before they were read in N, for
    tests whose scenario is that reading (the intake-stroke lift-off, its two-cycles)."""
    import ringlube

    if not isinstance(case, ringlube.Case):
        case = ringlube.Case.from_namelist(case)
    case = case.with_ring(tension_unit="N/m")
    return case.with_("calibration", file=str(PER_LENGTH_CALIBRATION))


@pytest.fixture(scope="session")
def solver() -> str:
    """The ringlube-solve executable (the CMake build, else the one pip installed)."""
    built = ROOT / "build" / "ringlube-solve"
    if built.exists():
        return str(built)
    found = shutil.which("ringlube-solve")
    if not found:
        pytest.fail("ringlube-solve not found: run `make test` (it builds it)")
    return found


@pytest.fixture()
def quick_case():
    """The cold deck at coarse numerics (a few tens of ms per run)."""
    import ringlube

    return ringlube.Case.from_namelist(COLD).with_numerics(nodes=41, dpsi_deg=2.0)


#: the ctest labels (tests/fortran/tests.cmake, registered as markers in pyproject.toml) of
#: each test module; besides these, a test that uses the `solver` fixture is `cli`, a strict
#: xfail is `known_limitation` and the tests of SLOW are `slow`. Select with
#: `pytest -m numerics`, `pytest -m "not slow"`.
MODULE_LABELS = {
    "test_batch_and_deck_edge_cases": ("unit", "io"),
    "test_bore_results": ("numerics", "io"),
    "test_branch_risk": ("numerics",),
    "test_calibration_targets": ("unit", "cli"),
    "test_calibrator": ("unit",),
    "test_case": ("unit",),
    "test_case_api": ("unit",),
    "test_cli_errors": ("cli",),
    "test_convergence": ("numerics",),
    "test_deck_items": ("unit", "io"),
    "test_convergence_progress": ("numerics",),
    "test_docs": ("unit",),
    "test_docstrings": ("unit",),
    "test_face_profile": ("numerics",),
    "test_flutter_margin": ("numerics",),
    "test_gas": ("unit",),
    "test_oil": ("unit", "numerics"),
    "test_gas_model": ("unit", "numerics"),
    "test_gas_wall_heat": ("unit", "numerics"),
    "test_groove_volume": ("unit",),
    "test_hdf5_layout": ("io",),
    "test_hostile_inputs": ("unit", "io"),
    "test_implausible_inputs": ("numerics",),
    "test_input_mistakes": ("unit",),
    "test_liner_film": ("numerics",),
    "test_liner_temperature": ("numerics",),
    "test_markers": ("unit",),
    "test_oil_supply": ("numerics",),
    "test_output_safety": ("io",),
    "test_own_engine_walkthrough": ("cli",),
    "test_packaging": ("io",),
    "test_plot_cli": ("cli", "io"),
    "test_periodic_state": ("numerics",),
    "test_pressure_shift": ("numerics",),
    "test_progress": ("cli",),
    "test_readings": ("numerics",),
    "test_ring_pack_cycle": ("numerics",),
    "test_ring_pack_study": ("numerics",),
    "test_run": ("numerics",),
    "test_scheduler_connection": ("unit",),
    "test_stability": ("numerics",),
    "test_study": ("numerics",),
    "test_study_constraints": ("unit",),
    "test_study_docstrings": ("unit",),
    "test_study_mistakes_and_interruptions": ("io",),
    "test_study_outputs": ("io",),
    "test_study_point_constraints": ("unit",),
    "test_study_resume": ("io",),
    "test_study_verification": ("numerics",),
    "test_study_weighting": ("numerics",),
    "test_unclear_inputs": ("unit",),
    "test_validation": ("numerics",),
    "test_validation_sections": ("numerics",),
    "test_width_story": ("numerics",),
}


#: tests over 2 s on the 2-core machine shared by five jobs (about 1 s alone, the ctest `slow`),
#: measured with `pytest --durations=0 --durations-min=1` (call or fixture set-up); `slow`
SLOW = {
    "test_small_study_end_to_end",
    "test_dask_study_is_quiet_and_interrupts_in_one_line",
    "test_starved_hot_energy_converges_in_the_crank_step",
    "test_dask_cluster_matches_serial_and_survives_a_killed_worker",
    "test_own_engine_walkthrough",
    "test_width_page_blocks_are_the_script_s_output[mechanism]",
    "test_width_page_blocks_are_the_script_s_output[gas]",
    "test_study_trades_friction_against_oil_transport",
    "test_tradeoff_is_drawn_without_ring_mass_and_names_designs",
    "test_tradeoff_files_follow_the_objectives",
    "test_resume_after_changed_weights_recomputes_the_scene",
    "test_docstring_examples_run[gas]",
    "test_sigterm_during_cluster_start_ends_quietly",
    "test_constraint_binds_the_surrogate_front",
    "test_deck_over_64_kib_is_kept_whole",
    "test_shipped_calibration_is_the_declared_fit",
    "test_imep_of_the_written_trace_is_the_target",
    "test_damped_rule_that_does_not_contract_ends_flagged",
    "test_real_process_prints_one_line",
    "test_figure_beside_the_trace",
    "test_direct_nsga2_resumes_from_its_last_generation",
    "test_unreachable_scheduler_is_one_error",
    "test_a_trace_fitted_to_peak_and_imep_reproduces_both[woschni]",
    "test_a_trace_fitted_to_peak_and_imep_reproduces_both[hohenberg]",
    "test_the_pages_gas_lines_are_what_the_commands_print",
    "test_a_relative_constraint_is_the_absolute_one_from_the_references_value",
    "test_a_per_point_constraint_binds_only_its_point",
    "test_the_report_says_which_designs_satisfy_every_points_constraints",
    "test_ringlube_plot_draws_the_bore",
    "test_study_draws_the_knee_of_a_distorted_case",
}


def pytest_collection_modifyitems(config, items):
    """Give every test the markers of its module, `cli` and `known_limitation` (see
    MODULE_LABELS)."""
    for item in items:
        labels = set(MODULE_LABELS.get(item.module.__name__.rpartition(".")[2], ()))
        if item.name in SLOW:
            labels.add("slow")
        if "solver" in getattr(item, "fixturenames", ()):
            labels.add("cli")
        xfail = item.get_closest_marker("xfail")
        if xfail is not None and xfail.kwargs.get("strict", False):
            labels.add("known_limitation")
        for label in sorted(labels):
            item.add_marker(label)
