"""The report compares each chosen design with the study's own samples, already run with the
true model: a good sample (converged, on the liner, within the constraints) that dominates a
chosen design is named, with its design and objectives beside the chosen design's; none is
said; ties within the tolerance are no domination. The studies answer from the closed form of
test_study (no kernel runs), so the samples' results can be set by hand."""

from __future__ import annotations

import h5py
import numpy as np
import pytest
from test_study import ClosedForm, write_study

from ringlube.study import run_study
from ringlube.study.check import DOMINANCE_RTOL, dominates, dominating_samples
from ringlube.study.report import dominating_lines, write_report
from ringlube.study.store import Study
from ringlube.study.summary import summary

pytestmark = pytest.mark.unit


def brute_force(f: np.ndarray, g: np.ndarray, rtol: float) -> list[int]:
    """Rows of ``f`` that dominate ``g`` with ties below ``rtol``, one pair of numbers at a time."""
    out = []
    for i, row in enumerate(f):
        no_worse, better = True, False
        for a, b in zip(row, g):
            tie = abs(a - b) <= rtol * max(abs(a), abs(b))
            no_worse &= tie or a < b
            better |= not tie and a < b
        if no_worse and better:
            out.append(i)
    return out


def study_of(tmp_path, name="dom", **extra) -> Study:
    return run_study(
        write_study(tmp_path, name=name, **extra),
        tmp_path / name,
        executor=ClosedForm(),
        progress=False,
        figures=False,
    )


def knee_beaten_by(study: Study, sample: int, label: str = "cold", factor: float = 0.95) -> np.ndarray:
    """Give ``sample`` the chosen knee's results with its first objective times ``factor``
    (every other result the knee's): a design the true model found that dominates the knee.
    Returns the sample's objectives."""
    c = study.cases[label]
    knee = c.chosen.f_true[c.chosen.names.index("knee")].copy()
    knee[study.objective_columns()[0]] *= factor
    c.runs.outputs[sample] = knee
    return knee[study.objective_columns()]


@pytest.fixture()
def plain(tmp_path) -> Study:
    return study_of(tmp_path)


def test_no_dominating_sample_is_said(plain, tmp_path):
    """A study none of whose samples dominates a chosen design says so in one sentence (so the
    reader knows it was checked), and stores an empty comparison of every good sample."""
    c = plain.cases["cold"]
    cols = plain.objective_columns()
    for g in c.chosen.f_true[:, cols]:  # the independent check that none does
        assert brute_force(c.runs.outputs[:, cols], g, DOMINANCE_RTOL) == []
    assert len(c.dominating.sample) == 0 and c.dominating.compared == plain.s.samples
    report = (tmp_path / "dom" / "report.md").read_text()
    assert (
        f"None of the {plain.s.samples} good samples of the design of experiments (run by the true "
        "model: converged, on the liner) dominates a chosen design (no worse in every objective and "
        "better in at least one, differences of at most 0.1% of the larger value counting as ties)."
    ) in report


def test_a_sample_that_dominates_the_knee_is_named(plain, tmp_path):
    """A good sample that beats the chosen knee by the true model is named in the report's
    sentence and table (its design, its objectives beside the knee's), and in the study file,
    which the report re-rendered from it shows the same; the chosen designs stay as they are."""
    c = plain.cases["cold"]
    chosen = c.chosen.x.copy()
    f = knee_beaten_by(plain, 11)
    c.dominating = dominating_samples(plain, "cold")
    assert c.dominating.chosen == ["knee"] and c.dominating.sample.tolist() == [11]
    np.testing.assert_array_equal(c.dominating.x[0], plain.x[11])
    np.testing.assert_array_equal(c.dominating.f[0], f)
    np.testing.assert_array_equal(c.chosen.x, chosen)
    lines = dominating_lines(plain, "cold")
    assert lines[0].startswith(
        f"**1 of the {plain.s.samples} good samples of the design of experiments (run by the true "
        "model: converged, on the liner) dominates a chosen design** ("
    )
    assert ": knee by sample 11. " in lines[0]
    knee = c.chosen.f_true[c.chosen.names.index("knee")]
    (row,) = [line for line in lines if line.startswith("| knee | 11 |")]
    width_mm = plain.x[11, 0] * 1e3
    assert f"| {width_mm:.4g} |" in row
    cols = plain.objective_columns()
    assert f"| {f[0]:.4g} / {knee[cols[0]]:.4g} |" in row  # better
    assert f"| {f[1]:.4g} / {knee[cols[1]]:.4g} (tie) |" in row  # the same value: a tie, said
    # the study file holds the same, and a report rendered from it says the same
    plain.save()
    with h5py.File(plain.path) as h:
        assert h["cases/cold/dominating/sample"][()].tolist() == [11]
    again = Study.open(plain.s, plain.path)
    assert again.cases["cold"].dominating.sample.tolist() == [11]
    (tmp_path / "again").mkdir()
    report = write_report(again, tmp_path / "again").read_text()
    assert "\n".join(lines) in report


def test_infeasible_lifted_or_unconverged_dominating_samples_are_not_named(tmp_path):
    """A sample that would dominate the knee but is outside the constraints, lifted the ring
    off the liner or did not converge is not a good design (the candidates' rules): not named,
    and not counted among those compared."""
    study = study_of(tmp_path, name="bad", constraints="'max_friction <= 100'")
    c = study.cases["cold"]
    j = list(study.s.outputs)
    for i in (3, 5, 7, 9):
        knee_beaten_by(study, i)
    c.runs.outputs[3, j.index("max_friction")] = 200.0  # outside the constraint
    c.runs.outputs[5, j.index("liner_lift_share")] = 2.0  # lifted off the liner
    c.runs.converged[7] = False  # not converged
    d = dominating_samples(study, "cold")
    assert d.sample.tolist() == [9]
    assert d.compared == study.s.samples - 3
    c.dominating = d
    text = "\n".join(dominating_lines(study, "cold"))
    assert "| knee | 9 |" in text and not any(f"| knee | {i} |" in text for i in (3, 5, 7))
    assert "within the constraints" in text


def test_differences_within_the_tolerance_are_ties():
    """Two values closer than the tolerance (relative to the larger) are a tie: a sample better
    only by less than it does not dominate, one better by more does, and one worse by less than
    it in another objective still does; the answer matches a brute-force comparison."""
    g = np.array([2.0, 1.0, 0.5])
    r = DOMINANCE_RTOL
    f = np.array(
        [
            [2.0 * (1 - 0.5 * r), 1.0, 0.5],  # better within the tolerance only: a tie
            [2.0 * (1 - 2 * r), 1.0, 0.5],  # better beyond it
            [2.0 * (1 - 2 * r), 1.0 * (1 + 0.5 * r), 0.5],  # and worse within it: still dominates
            [2.0 * (1 - 2 * r), 1.0 * (1 + 2 * r), 0.5],  # worse beyond it: does not
            [2.0, 1.0, 0.5],  # the same design
            [1.0, np.nan, 0.1],  # not a number: dominates nothing
        ]
    )
    assert dominates(f, g).tolist() == [False, True, True, False, False, False]
    assert np.flatnonzero(dominates(f[:5], g)).tolist() == brute_force(f[:5], g, r)
    assert not dominates(f, np.array([np.nan, 1.0, 0.5])).any()


def test_a_sample_within_the_tolerance_of_the_knee_is_not_named(plain):
    """In a study: a sample equal to the knee but for a first objective lower by half the
    tolerance is no domination; lower by twice the tolerance it is."""
    knee_beaten_by(plain, 20, factor=1 - 0.5 * DOMINANCE_RTOL)
    assert dominating_samples(plain, "cold").sample.tolist() == []
    knee_beaten_by(plain, 20, factor=1 - 2 * DOMINANCE_RTOL)
    assert dominating_samples(plain, "cold").sample.tolist() == [20]


def test_the_scene_judges_its_samples_by_every_points_constraints(tmp_path):
    """The scene's samples are good only within the constraints at every point (their results
    at each point are the cases' runs): a sample that beats the scene's knee but violates a
    constraint at one point is not named."""
    hot = "'max_friction <= 100 at hot'"
    study = study_of(tmp_path, name="scene", cases=("cold", "hot"), scene=".true.", constraints=hot)
    f = knee_beaten_by(study, 4, label="scene")
    knee_beaten_by(study, 6, label="scene")
    study.cases["hot"].runs.outputs[6, list(study.s.outputs).index("max_friction")] = 200.0
    d = dominating_samples(study, "scene")
    assert d.sample.tolist() == [4] and d.compared == study.s.samples - 1
    np.testing.assert_array_equal(d.f[0], f)


def test_a_resumed_study_file_without_the_comparison_gets_it(plain, tmp_path):
    """A study file written before the comparison was stored (no ``dominating`` group) is
    resumed with it computed from the stored runs, without a run."""
    with h5py.File(plain.path, "r+") as h:
        del h["cases/cold/dominating"]
    ex = ClosedForm()
    again = run_study(
        write_study(tmp_path, name="dom"), tmp_path / "dom", executor=ex, progress=False, figures=False
    )
    assert ex.sizes == []
    assert again.cases["cold"].dominating is not None
    assert (
        again.cases["cold"].dominating.compared == plain.cases["cold"].dominating.compared == plain.s.samples
    )
    with h5py.File(plain.path) as h:
        assert "cases/cold/dominating" in h


def test_one_or_no_good_sample_is_said(plain):
    """With one good sample the sentence names it as one; with none, it says the chosen designs
    were compared with none (not that none dominates)."""
    c = plain.cases["cold"]
    c.runs.converged[1:] = False
    c.dominating = dominating_samples(plain, "cold")
    assert c.dominating.compared == 1 and len(c.dominating.sample) == 0
    assert dominating_lines(plain, "cold")[0].startswith(
        "The one good sample of the design of experiments (run by the true model: converged, on the "
        "liner) does not dominate a chosen design ("
    )
    c.runs.converged[0] = False
    c.dominating = dominating_samples(plain, "cold")
    assert dominating_lines(plain, "cold") == [
        "No sample of the design of experiments is good by the true model: the chosen designs were "
        "compared with none."
    ]


def test_the_printed_summary_warns_of_a_dominating_sample(plain):
    """The summary printed at the end of a study warns where a good sample dominates a chosen
    design, and says nothing of it where none does."""
    assert "dominate a chosen design" not in summary(plain)
    knee_beaten_by(plain, 11)
    plain.cases["cold"].dominating = dominating_samples(plain, "cold")
    text = summary(plain)
    assert (
        f"  warning: 1 of the {plain.s.samples} good samples dominates a chosen design (knee) by the "
        "true model: the surfaces misplaced the front there (report.md names them)"
    ) in text.splitlines()
    knee_beaten_by(plain, 12)  # two: the plural
    plain.cases["cold"].dominating = dominating_samples(plain, "cold")
    two = f"  warning: 2 of the {plain.s.samples} good samples dominate a chosen design (knee)"
    assert two in summary(plain)
