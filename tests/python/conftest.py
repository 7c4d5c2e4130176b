"""Shared fixtures: paths to the shipped inputs and the standalone solver."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
INPUTS = ROOT / "inputs"
DECKS = sorted(INPUTS.glob("crf450r_*.nml"))
COLD = INPUTS / "crf450r_4000rpm_full_cold.nml"


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
#: each test module; besides these, a test that uses the `solver` fixture is `cli`, and a
#: strict xfail is `known_limitation`. Select with `pytest -m numerics`, `pytest -m "not slow"`.
MODULE_LABELS = {
    "test_batch_and_deck_edge_cases": ("unit", "io"),
    "test_case": ("unit",),
    "test_case_api": ("unit",),
    "test_cli_errors": ("cli",),
    "test_convergence": ("numerics", "slow"),
    "test_convergence_progress": ("numerics",),
    "test_docs": ("unit",),
    "test_docstrings": ("unit",),
    "test_gas": ("unit",),
    "test_gas_model": ("unit", "numerics"),
    "test_hdf5_layout": ("io",),
    "test_implausible_inputs": ("numerics",),
    "test_input_mistakes": ("unit",),
    "test_oil_supply": ("numerics", "slow"),
    "test_markers": ("unit",),
    "test_output_safety": ("io",),
    "test_own_engine_walkthrough": ("cli", "slow"),
    "test_packaging": ("io", "slow"),
    "test_plot_cli": ("cli", "io"),
    "test_readings": ("numerics",),
    "test_ring_pack_cycle": ("numerics",),
    "test_run": ("numerics",),
    "test_scheduler_connection": ("unit",),
    "test_stability": ("numerics", "slow"),
    "test_study": ("numerics", "slow"),
    "test_study_constraints": ("unit",),
    "test_study_docstrings": ("unit",),
    "test_study_mistakes_and_interruptions": ("io",),
    "test_study_outputs": ("io",),
    "test_study_resume": ("io",),
    "test_study_verification": ("numerics", "slow"),
    "test_validation": ("numerics",),
}


def pytest_collection_modifyitems(config, items):
    """Give every test the markers of its module, `cli` and `known_limitation` (see
    MODULE_LABELS)."""
    for item in items:
        labels = set(MODULE_LABELS.get(item.module.__name__.rpartition(".")[2], ()))
        if "solver" in getattr(item, "fixturenames", ()):
            labels.add("cli")
        xfail = item.get_closest_marker("xfail")
        if xfail is not None and xfail.kwargs.get("strict", False):
            labels.add("known_limitation")
        for label in sorted(labels):
            item.add_marker(label)
