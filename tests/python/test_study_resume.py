"""Resuming a study: settings that change stored results (weights, scene, fit and GA sizes)
recompute what depends on them from the kept runs; the direct NSGA-II resumes per generation."""

from __future__ import annotations

import numpy as np
import pytest

from ringlube.executor import Executor
from ringlube.study import run_study

from conftest import INPUTS

pytestmark = pytest.mark.io

COLD = INPUTS / "crf450r_4000rpm_full_cold.nml"
HOT = INPUTS / "crf450r_4000rpm_full_hot.nml"


def write(tmp_path, name="r", generations=4, **extra) -> str:
    lines = [
        "&study",
        f"  name = '{name}', cases = '{COLD}', '{HOT}', labels = 'cold', 'hot'",
        "  variables = 'width', 'crown_offset', lower = 0.8e-3, -40e-6, upper = 1.2e-3, 40e-6",
        "  objectives = 'energy_loss', 'mixed_share'",
        f"  samples = 24, seed = 3, population = 12, generations = {generations}, repeats = 2",
        "  direct_population = 6, direct_generations = 3, batch = 3",
    ]
    lines += [f"  {k} = {v}" for k, v in extra.items()]
    path = tmp_path / f"{name}.nml"
    path.write_text("\n".join(lines + ["/"]) + "\n")
    return str(path)


def same_study(a, b) -> None:
    for label in ("cold", "hot", "scene"):
        ca, cb = a.cases[label], b.cases[label]
        np.testing.assert_array_equal(ca.runs.outputs, cb.runs.outputs)
        for o in a.s.outputs:
            np.testing.assert_array_equal(ca.surfaces[o].coef, cb.surfaces[o].coef)
        np.testing.assert_array_equal(ca.front.f, cb.front.f)
        np.testing.assert_array_equal(ca.chosen.f_true, cb.chosen.f_true)


@pytest.mark.slow
def test_resume_after_changed_weights_recomputes_the_scene(tmp_path):
    out = tmp_path / "out"
    first = run_study(
        write(tmp_path, scene=".true.", weights="1.0, 1.0"),
        out,
        executor=Executor(serial=True),
        progress=False,
        figures=False,
    )
    again = run_study(
        write(tmp_path, scene=".true.", weights="1.0, 100.0"),
        out,
        executor=Executor(serial=True),
        progress=False,
        figures=False,
    )
    assert again.runs_executed == 0  # no sample re-run
    w = np.array([1.0, 100.0]) / 101.0
    np.testing.assert_allclose(
        again.cases["scene"].runs.outputs,
        w[0] * again.cases["cold"].runs.outputs + w[1] * again.cases["hot"].runs.outputs,
    )
    assert not np.array_equal(first.cases["scene"].front.f, again.cases["scene"].front.f)
    fresh = run_study(
        write(tmp_path, name="fresh", scene=".true.", weights="1.0, 100.0"),
        tmp_path / "fresh",
        executor=Executor(serial=True),
        progress=False,
        figures=False,
    )
    same_study(again, fresh)


@pytest.mark.parametrize("setting", ["population", "generations", "repeats", "folds", "surrogate"])
def test_fit_and_ga_settings_are_in_the_key_of_derived_results(setting):
    s = read_study_settings()
    before = s.derived_key("cold"), s.derived_key("scene"), s.derived_key("cold", direct=True)
    setattr(s, setting, getattr(s, setting) + (1 if setting != "surrogate" else "-other"))
    after = s.derived_key("cold"), s.derived_key("scene"), s.derived_key("cold", direct=True)
    assert all(a != b for a, b in zip(before, after))


def read_study_settings():
    from ringlube.study.settings import StudySettings

    return StudySettings("s", ["a.nml"], ["cold"], [1.0], ["width"], [0.0], [1.0], ["energy_loss"])


def test_a_finished_scene_study_resumes_unchanged(tmp_path):
    """A scene study with a reference run again on the same folder keeps every stored record
    of the scene: before, the scene's state was rebuilt by position and, with the candidates
    added to it, its chosen designs became the candidates, the reference the chosen and the
    direct results the reference; the report then failed ('surrogate knee' not in list)."""
    import ringlube.study.pipeline as study_mod

    deck = write(tmp_path, scene=".true.", reference="1.0e-3, 0.0")
    out = tmp_path / "out"
    first = run_study(deck, out, executor=Executor(serial=True), progress=False, figures=False)
    calls = []
    real = study_mod.how_sure
    study_mod.how_sure = lambda *a, **k: (calls.append(1), real(*a, **k))[1]
    try:
        again = run_study(deck, out, executor=Executor(serial=True), progress=False, figures=False)
    finally:
        study_mod.how_sure = real
    assert again.runs_executed == 0 and calls == []  # nothing finished is redone, "how sure" neither
    for label in ("cold", "hot", "scene"):
        a, b = first.cases[label], again.cases[label]
        assert b.candidates.names[:3] == [
            "surrogate min energy_loss",
            "surrogate min mixed_share",
            "surrogate knee",
        ]
        assert b.chosen.names == ["min energy_loss", "min mixed_share", "knee"]
        assert b.reference.names == ["reference"]
        for key in ("candidates", "chosen", "reference"):
            np.testing.assert_array_equal(getattr(a, key).f_true, getattr(b, key).f_true)
    assert "surrogate's own knee" in (out / "report.md").read_text()
