"""Friction power and FMEP as study objectives, and a scene weighted by the time each
operating point runs (``&study weighting = 'time'``): rates by the time, amounts per cycle by
the cycles run."""

from __future__ import annotations

import numpy as np
import pytest

from ringlube.errors import InputError
from ringlube.executor import Executor
from ringlube.study.deck import read_study
from ringlube.study.runs import run_samples, sample, scene_results
from ringlube.study.settings import StudySettings
from ringlube.study.store import Study
from ringlube.study.variables import PER_CYCLE
from ringlube.tables import SCALARS

from conftest import INPUTS

pytestmark = pytest.mark.numerics

COLD = INPUTS / "crf450r_4000rpm_full_cold.nml"


def deck_at(tmp_path, rpm: float) -> str:
    """The cold deck at another speed (its trace and calibration by absolute path)."""
    text = (
        COLD.read_text()
        .replace("speed_rpm = 4000", f"speed_rpm = {rpm:g}")
        .replace("'calibration.nml'", f"'{INPUTS}/calibration.nml'")
        .replace("pressure/", f"{INPUTS}/pressure/")
    )
    path = tmp_path / f"at_{rpm:g}.nml"
    path.write_text(text)
    return str(path)


def study_deck(tmp_path, cases, objectives="'friction_power', 'fmep'", **extra) -> str:
    lines = [
        "&study",
        "  name = 'w'",
        "  cases = " + ", ".join(f"'{c}'" for c in cases),
        "  labels = " + ", ".join(f"'p{i}'" for i in range(len(cases))),
        "  variables = 'width', lower = 0.8e-3, upper = 1.2e-3",
        f"  objectives = {objectives}",
        "  samples = 8, folds = 2, population = 8, generations = 2, repeats = 1",
    ]
    lines += [f"  {k} = {v}" for k, v in extra.items()]
    path = tmp_path / "w.nml"
    path.write_text("\n".join(lines + ["/"]) + "\n")
    return str(path)


def test_friction_power_and_fmep_are_objectives(tmp_path):
    s = read_study(study_deck(tmp_path, [str(COLD)]))
    assert s.objectives == ["friction_power", "fmep"]
    assert {"friction_power", "fmep"} <= set(s.outputs)  # recorded because named
    s = read_study(study_deck(tmp_path, [str(COLD)], objectives="'engine_friction_power', 'fmep_bar'"))
    assert {"engine_friction_power", "fmep_bar"} <= set(s.outputs)
    # a numerics diagnostic is not a design quantity
    with pytest.raises(InputError, match=r"unknown objective 'run_time' \(known: .*friction_power"):
        read_study(study_deck(tmp_path, [str(COLD)], objectives="'run_time'"))


def test_per_cycle_results_are_the_kernels_amounts_per_cycle():
    # every name is a scalar of the kernel, in a unit of an amount per cycle
    assert PER_CYCLE <= set(SCALARS)
    assert {SCALARS[o].unit for o in PER_CYCLE} <= {"J", "kPa", "bar", "mm^3", "mg", "1"}


def test_time_weights_count_cycles_for_amounts_and_time_for_rates(tmp_path):
    # two operating points, 2000 and 6000 r/min, one hour each: the 6000 r/min point runs
    # three times the cycles. The scene's friction power is the mean over the time, its energy
    # per cycle the energy of all cycles over their number, and the two agree:
    # P_scene = E_scene x (cycles of both) / (time of both).
    cases = [deck_at(tmp_path, 2000), deck_at(tmp_path, 6000)]
    hours = [1.0, 1.0]
    objectives = "'friction_power', 'energy_loss'"
    time = {"scene": ".true.", "weights": "1.0, 1.0", "weighting": "'time'"}
    deck = study_deck(tmp_path, cases, objectives=objectives, **time)
    s = read_study(deck)
    assert s.cycle_rates == [2000 / 120, 6000 / 120]
    study = Study(s, tmp_path / "w.h5")
    study.x = sample(s)
    run_samples(study, Executor(serial=True), progress=False)
    scene_results(study)
    j = {o: s.outputs.index(o) for o in ("friction_power", "energy_loss", "mixed_share")}
    p = [study.cases[label].runs.outputs for label in s.labels]
    rates = np.array(s.cycle_rates)
    power = (hours[0] * p[0][:, j["friction_power"]] + hours[1] * p[1][:, j["friction_power"]]) / sum(hours)
    cycles = np.array(hours) * rates
    energy = (cycles[0] * p[0][:, j["energy_loss"]] + cycles[1] * p[1][:, j["energy_loss"]]) / cycles.sum()
    scene = study.cases["scene"].runs.outputs
    np.testing.assert_allclose(scene[:, j["friction_power"]], power, rtol=1e-14)
    np.testing.assert_allclose(scene[:, j["energy_loss"]], energy, rtol=1e-14)
    np.testing.assert_allclose(scene[:, j["friction_power"]], energy * cycles.sum() / sum(hours), rtol=1e-13)
    # a share of the cycle's time is a share of the running time: weighed by the time
    share = (p[0][:, j["mixed_share"]] + p[1][:, j["mixed_share"]]) / 2
    np.testing.assert_allclose(scene[:, j["mixed_share"]], share, rtol=1e-14)
    # equal weights per case ('case', the default) undercount the fast point's energy per
    # hour by its threefold cycles: the mean of the two energies per cycle
    case = StudySettings("c", cases, s.labels, [1.0, 1.0], ["width"], [0.8e-3], [1.2e-3], s.objectives)
    assert case.scene_weights(["energy_loss"]).ravel().tolist() == [0.5, 0.5]
    assert s.scene_weights(["energy_loss"]).ravel().tolist() == pytest.approx([0.25, 0.75], rel=1e-15)


def test_time_weighting_needs_a_fixed_speed_per_case(tmp_path):
    deck = study_deck(tmp_path, [str(COLD)], weighting="'time'")
    text = (
        open(deck)
        .read()
        .replace(
            "variables = 'width', lower = 0.8e-3, upper = 1.2e-3",
            "variables = 'width', 'operating:speed_rpm', lower = 0.8e-3, 2000, upper = 1.2e-3, 6000",
        )
    )
    open(deck, "w").write(text.replace("samples = 8", "samples = 12"))
    with pytest.raises(InputError, match=r"&study weighting: 'time' weighs results per cycle"):
        read_study(deck)
