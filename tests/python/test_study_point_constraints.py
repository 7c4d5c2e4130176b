"""Constraints relative to the reference ring (`'NAME <= FACTOR * reference'`) and per operating
point (`at LABEL`), and the report that says which designs satisfy every point's constraints
and which only their own point's."""

from __future__ import annotations

import re
import shutil

import numpy as np
import pytest

from ringlube.case import Case
from ringlube.errors import InputError
from ringlube.executor import Executor
from ringlube.solve import run_designs
from ringlube.study import run_study
from ringlube.study.bounds import constraint_bounds
from ringlube.study.constraints import parse_constraint
from ringlube.study.deck import read_study
from ringlube.study.surfaces import surfaces_of

from conftest import INPUTS

pytestmark = pytest.mark.unit

BOX = "variables = 'width', 'crown_offset', lower = 0.8e-3, -40e-6, upper = 1.2e-3, 40e-6"
SIZES = "samples = 24, seed = 3, population = 16, generations = 8, repeats = 2, batch = 8"


@pytest.fixture(scope="module")
def decks(tmp_path_factory):
    """The cold and hot decks at the 'fast' preset, beside their calibration file and trace."""
    d = tmp_path_factory.mktemp("points")
    (d / "pressure").mkdir()
    shutil.copy(INPUTS / "pressure" / "crf450r_4000rpm_full.csv", d / "pressure")
    shutil.copy(INPUTS / "calibration.nml", d)
    for name in ("cold", "hot"):
        text = (INPUTS / f"crf450r_4000rpm_full_{name}.nml").read_text()
        assert "preset = 'default'" in text
        (d / f"{name}.nml").write_text(text.replace("preset = 'default'", "preset = 'fast'"))
    return d


def _deck(folder, name, constraints="", two=True):
    cases = (
        "cases = 'cold.nml', 'hot.nml', labels = 'cold', 'hot', scene = .true."
        if two
        else ("cases = 'cold.nml', labels = 'cold'")
    )
    path = folder / f"{name}.nml"
    path.write_text(f"""&study
  name = '{name}', {cases}
  {BOX}
  objectives = 'energy_loss', 'mixed_share'
  {SIZES}
  reference = 1.004e-3, -38.3e-6
  {f"constraints = {constraints}" if constraints else ""}
/
""")
    return path


def test_the_normal_form_keeps_every_digit():
    """A study keeps its constraints as text and parses them again: 'min_film >= 0.7123456e-6'
    came back as 0.712346e-6 (six digits)."""
    texts = ("min_film >= 0.7123456e-6", "max_friction <= 201.902887695998", "fmep <= 1.0000001 * reference")
    for text in texts:
        c = parse_constraint(text)
        assert parse_constraint(str(c)) == c


def test_syntax_and_normal_form():
    c = parse_constraint("blowby<=1.05*reference at 'r8000'")
    assert (c.name, c.sense, c.value, c.factor, c.at) == ("blowby", "<=", None, 1.05, "r8000")
    assert str(c) == "blowby <= 1.05 * reference at r8000" and parse_constraint(str(c)) == c
    reversed_ = parse_constraint('min_film >= reference * 0.9 at "cold"')
    assert str(reversed_) == "min_film >= 0.9 * reference at cold"
    assert str(parse_constraint("fmep <= 3 at scene")) == "fmep <= 3 at scene"
    assert parse_constraint("max_friction <= reference").bound(12.0) == 12.0
    assert parse_constraint("max_friction <= 1.05 * reference").bound(12.0) == 1.05 * 12.0


@pytest.mark.parametrize(
    "constraint, why",
    [
        ("'max_friction <= 0 * reference'", "the factor of the reference must be a positive number, not 0"),
        ("'max_friction <= -1 * reference'", "must be a positive number, not -1"),
        ("'max_friction <= x * reference'", "the factor 'x' of the reference is not a number"),
        ("'max_friction <= 3 at warm'", "at 'warm' is not a case label (cold, hot) nor the scene"),
        ("'max_friction <= 3 at'", "'3 at' is neither a number nor 'reference'"),
    ],
)
def test_malformed_entries_name_file_group_and_variable(decks, constraint, why):
    path = _deck(decks, "bad", constraint)
    with pytest.raises(InputError) as exc:
        read_study(path)
    msg = str(exc.value)
    assert re.match(rf"{re.escape(str(path))}:\d+: &study constraints: ", msg), msg
    assert why in msg and "\n" not in msg


def test_at_scene_needs_a_scene(decks):
    path = _deck(decks, "one", "'max_friction <= 3 at scene'", two=False)
    with pytest.raises(InputError, match="'at scene' needs scene = .true. and two cases or more"):
        read_study(path)


@pytest.mark.slow
def test_a_relative_constraint_is_the_absolute_one_from_the_references_value(decks):
    """'max_friction <= 1.05 * reference' and 'max_friction <= B' with B = 1.05 times the
    reference's true max_friction give the same bound and the same study: the same Pareto set
    and the same chosen designs, bit for bit."""
    rel = run_study(
        _deck(decks, "relative", "'max_friction <= 1.05 * reference'", two=False),
        decks / "out_relative",
        executor=Executor(serial=True),
        progress=False,
        figures=False,
    )
    j = rel.s.outputs.index("max_friction")
    reference = float(rel.cases["cold"].reference.f_true[0, j])
    (bound,) = constraint_bounds(rel, "cold")
    assert bound.value == 1.05 * reference and bound.point == "cold"
    absolute = run_study(
        _deck(decks, "absolute", f"'max_friction <= {1.05 * reference!r}'", two=False),
        decks / "out_absolute",
        executor=Executor(serial=True),
        progress=False,
        figures=False,
    )
    (same,) = constraint_bounds(absolute, "cold")
    assert same.value == bound.value
    a, b = rel.cases["cold"], absolute.cases["cold"]
    np.testing.assert_array_equal(a.front.x, b.front.x)
    np.testing.assert_array_equal(a.chosen.x, b.chosen.x)
    np.testing.assert_array_equal(a.chosen.f_true, b.chosen.f_true)
    # the constraint bound the front: the reference is not inside it everywhere
    (friction,) = surfaces_of(rel, "cold", ["max_friction"])
    assert np.all(friction(a.front.x) <= 1.05 * reference * (1 + 1e-9))


@pytest.fixture(scope="module")
def per_point(decks):
    """The same two-point study (cold, hot and their scene) without a constraint and with
    'max_friction <= B at hot', B inside the range of the hot front's max_friction."""
    free = run_study(
        _deck(decks, "free"),
        decks / "out_free",
        executor=Executor(serial=True),
        progress=False,
        figures=False,
    )
    (friction,) = surfaces_of(free, "hot", ["max_friction"])
    values = friction(free.cases["hot"].front.x)
    bound = float(np.quantile(values, 0.3))
    assert values.max() > bound  # it binds at hot
    study = run_study(
        _deck(decks, "bound", f"'max_friction <= {bound!r} at hot'"),
        decks / "out_bound",
        executor=Executor(serial=True),
        progress=False,
        figures=False,
    )
    return free, study, bound, decks / "out_bound"


@pytest.mark.slow
def test_a_per_point_constraint_binds_only_its_point(per_point):
    """At hot the front holds only designs within the bound (on the surface); the cold front is
    that of the study without the constraint, bit for bit; the scene's designs are bound at
    hot, on hot's surface."""
    free, study, bound, _ = per_point
    hot, cold = study.cases["hot"], study.cases["cold"]
    (friction,) = surfaces_of(study, "hot", ["max_friction"])
    assert np.all(friction(hot.front.x) <= bound * (1 + 1e-9))
    np.testing.assert_array_equal(cold.front.x, free.cases["cold"].front.x)
    np.testing.assert_array_equal(cold.front.f, free.cases["cold"].front.f)
    assert [b.point for b in constraint_bounds(study, "cold")] == []
    assert [(b.point, b.value) for b in constraint_bounds(study, "scene")] == [("hot", bound)]
    assert np.all(friction(study.cases["scene"].front.x) <= bound * (1 + 1e-9))
    assert np.max(friction(free.cases["scene"].front.x)) > bound  # it bound the scene too


@pytest.mark.slow
def test_the_report_says_which_designs_satisfy_every_points_constraints(per_point, decks):
    """Every chosen design of cold is run at hot too; the report's row says 'all satisfied'
    exactly where its max_friction at hot (computed here, independently) is within the bound."""
    _, study, bound, out = per_point
    report = (out / "report.md").read_text()
    assert "## Constraints at every operating point" in report
    cold = study.cases["cold"].chosen
    values, conv, _ = run_designs(
        Case.from_namelist(decks / "hot.nml"), ["width", "crown_offset"], cold.x, ["max_friction"]
    )
    j = study.s.outputs.index("max_friction")
    np.testing.assert_array_equal(cold.points["hot"][:, j], np.where(conv, values[:, 0], np.nan))
    section = report.split("## Constraints at every operating point")[1]
    every, own_only = [], []
    for n, v in zip(cold.names, values[:, 0]):
        row = next(line for line in section.splitlines() if line.startswith(f"| cold | {n} |"))
        ok = v <= bound  # the constraint, written out here
        assert row.rstrip(" |").endswith("all satisfied") == ok, row
        assert ("INFEASIBLE at hot: max_friction" in row) == (not ok), row
        (every if ok else own_only).append(f"cold {n}")
    assert f"satisfy only their own point's: {', '.join(own_only) or 'none'}" in section
    for n in study.cases["scene"].chosen.names:  # the scene's were chosen against hot's bound
        assert f"| scene | {n} | feasible | all satisfied |" in section
