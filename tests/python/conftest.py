"""Shared fixtures: paths to the shipped inputs and the standalone solver."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
INPUTS = ROOT / "inputs"
#: the shipped CRF450R decks the per-deck tests run in full; the distorted ones (a film per
#: sector, up to a minute or more a run) are run at coarse settings in test_bore_study
DECKS = sorted(p for p in INPUTS.glob("crf450r_*.nml") if "distorted" not in p.name)
DISTORTED_DECKS = sorted(INPUTS.glob("*_distorted.nml"))
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
