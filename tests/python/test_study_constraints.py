"""Constraints, trade-off figures of the chosen objectives and the "How sure" section of a
design study."""

from __future__ import annotations

import re

import numpy as np
import pytest

import ringlube
from ringlube.case import Case
from ringlube.errors import InputError
from ringlube.executor import Executor
from ringlube.solve import run_designs
from ringlube.study import run_study
from ringlube.study.bounds import feasibility
from ringlube.study.constraints import parse_constraint
from ringlube.study.deck import read_study
from ringlube.study.figures import tradeoff_stems
from ringlube.study.sure import UNCERTAIN
from ringlube.study.surfaces import surfaces_of

from conftest import INPUTS

pytestmark = pytest.mark.unit

COLD = INPUTS / "crf450r_4000rpm_full_cold.nml"
BOX = "variables = 'width', 'crown_offset', lower = 0.8e-3, -40e-6, upper = 1.2e-3, 40e-6"


def deck(tmp_path, name="k", extra="", objectives="'energy_loss', 'mixed_share'", base=COLD):
    path = tmp_path / f"{name}.nml"
    path.write_text(f"""&study
  name = '{name}', cases = '{base}', labels = 'cold'
  {BOX}
  objectives = {objectives}
  samples = 24, seed = 3, population = 16, generations = 8, repeats = 2
  direct_population = 8, direct_generations = 3, batch = 4
  reference = 1.004e-3, -38.3e-6
  {extra}
/
""")
    return path


@pytest.mark.parametrize(
    "constraints, why",
    [
        ("'leakage <= 10'", "unknown result 'leakage'"),
        ("'blowby <= 10'", "needs &physics ring_pack = 'gas'"),
        ("'energy_loss < 2'", "is not 'NAME <= VALUE'"),
        ("'energy_loss <= two'", "'two' is neither a number nor 'reference'"),
        ("'energy_loss <= 2', 'energy_loss<=2'", "given twice"),
        ("'oil_to_chamber <= 1'", "needs &physics inlet = 'starved'"),
        ("3", "must be quoted names"),
    ],
)
def test_constraint_errors_name_file_group_and_variable(tmp_path, constraints, why):
    path = deck(tmp_path, extra=f"constraints = {constraints}")
    with pytest.raises(InputError) as exc:
        read_study(path)
    msg = str(exc.value)
    assert re.match(rf"{re.escape(str(path))}:\d+: &study constraints: ", msg), msg
    assert why in msg and "\n" not in msg


def test_reference_bound_needs_a_reference(tmp_path):
    path = deck(tmp_path, extra="constraints = 'max_friction <= reference'")
    path.write_text(path.read_text().replace("reference = 1.004e-3, -38.3e-6", ""))
    with pytest.raises(InputError, match=r"&study constraints: .*give &study reference"):
        read_study(path)


def test_constraint_violation_sign_and_scale():
    le, ge = parse_constraint("fmep <= 2"), parse_constraint("min_film >= 1e-6")
    assert le.violation(3.0, 2.0) == pytest.approx(0.5) and le.violation(1.0, 2.0) == pytest.approx(-0.5)
    assert ge.violation(0.5e-6, 1e-6) == pytest.approx(0.5) and ge.violation(2e-6, 1e-6) == pytest.approx(
        -1.0
    )
    assert parse_constraint("fmep <= 0").violation(0.25, 0.0) == pytest.approx(0.25)  # scale 1 at 0


def test_constrained_outputs_are_recorded_and_keyed(tmp_path):
    s = read_study(deck(tmp_path, extra="constraints = 'fmep <= 3', 'max_friction <= reference'"))
    assert "fmep" in s.outputs and "max_friction" in s.outputs
    assert s.constraints == ["fmep <= 3", "max_friction <= reference"]
    assert '"constraints"' in s.derived_key("cold") and '"reference"' in s.derived_key("cold")


@pytest.fixture(scope="module")
def constrained(tmp_path_factory):
    """Two objectives, a bound by the reference ring and a number, and the direct NSGA-II."""
    d = tmp_path_factory.mktemp("constrained")
    path = deck(d, extra="constraints = 'max_friction <= reference', 'min_film >= 0.7e-6'")
    study = run_study(path, d / "out", executor=Executor(serial=True), progress=False, with_direct=True)
    return study, d / "out", d


def _reference_friction(study):
    j = study.s.outputs.index("max_friction")
    return study.cases["cold"].reference.f_true[0, j]


@pytest.mark.slow
def test_constraint_binds_the_surrogate_front(constrained, tmp_path):
    study, _, _ = constrained
    c = study.cases["cold"]
    bound = _reference_friction(study)
    friction, film = surfaces_of(study, "cold", ["max_friction", "min_film"])
    assert np.all(friction(c.front.x) <= bound * (1 + 1e-9))
    assert np.all(film(c.front.x) >= 0.7e-6 * (1 - 1e-9))
    assert feasibility(study, "cold", c.chosen.f_surrogate).all()
    # without the constraint the same study's front goes beyond the reference's friction
    free = run_study(
        deck(tmp_path, name="free"),
        tmp_path / "out",
        executor=Executor(serial=True),
        progress=False,
        figures=False,
    )
    assert np.max(friction(free.cases["cold"].front.x)) > bound


def test_report_marks_chosen_designs_by_the_true_model(constrained):
    study, out, _ = constrained
    c = study.cases["cold"]
    report = (out / "report.md").read_text()
    assert "## Constraints" in report and "`max_friction <= reference`" in report
    assert f"<= {_reference_friction(study):.4g} N" in report and ">= 0.7 µm" in report
    jf, jm = study.s.outputs.index("max_friction"), study.s.outputs.index("min_film")
    for n, ft in zip(c.chosen.names, c.chosen.f_true):
        ok = ft[jf] <= _reference_friction(study) and ft[jm] >= 0.7e-6  # independent of the code
        row = next(line for line in report.splitlines() if line.startswith(f"| {n} |"))
        assert row.rstrip(" |").endswith("feasible") == ok, row
        assert ("INFEASIBLE" in row) == (not ok)


def test_direct_front_satisfies_the_constraints_by_the_true_model(constrained):
    study, _, _ = constrained
    d = study.cases["cold"].direct
    assert d is not None and len(d.x) > 0
    base = Case.from_namelist(COLD)
    values, conv, _ = run_designs(base, ["width", "crown_offset"], d.x, ["max_friction", "min_film"])
    assert conv.all()
    assert np.all(values[:, 0] <= _reference_friction(study)) and np.all(values[:, 1] >= 0.7e-6)
    gen = study.cases["cold"].direct_generations[0]
    assert gen.f.shape[1] == 5  # the objectives, the two constrained results, liner_lift_share


def test_resume_with_changed_constraints_recomputes_the_front(constrained):
    study, out, d = constrained
    path = d / "k.nml"
    path.write_text(path.read_text().replace("min_film >= 0.7e-6", "min_film >= 0.723e-6"))
    again = run_study(path, out, executor=Executor(serial=True), progress=False, figures=False)
    assert again.runs_executed == 0  # the samples' runs are kept
    film = surfaces_of(again, "cold", ["min_film"])[0]
    assert np.all(film(again.cases["cold"].front.x) >= 0.723e-6 * (1 - 1e-9))
    assert ">= 0.723 µm" in (out / "report.md").read_text()
    # a constraint on a result not recorded before needs new runs: another study
    path.write_text(path.read_text().replace("'min_film >= 0.723e-6'", "'fmep <= 100'"))
    with pytest.raises(InputError, match="recorded results"):
        run_study(path, out, executor=Executor(serial=True), progress=False, figures=False)


def test_min_film_in_micrometres(constrained):
    report = (constrained[1] / "report.md").read_text()
    assert "min_film [µm]" in report and "min_film [m]" not in report


@pytest.mark.slow
def test_tradeoff_files_follow_the_objectives(constrained, tmp_path):
    _, out, _ = constrained
    assert tradeoff_stems(["energy_loss", "mixed_share"]) == ["tradeoff_energy_loss_vs_mixed_share"]
    assert (out / "tradeoff_energy_loss_vs_mixed_share.png").is_file()
    assert not (out / "tradeoff.png").exists()
    three = run_study(
        deck(tmp_path, name="three", objectives="'energy_loss', 'max_friction', 'ring_mass'"),
        tmp_path / "out3",
        executor=Executor(serial=True),
        progress=False,
    )
    stems = tradeoff_stems(three.s.objectives)
    assert stems == [
        "tradeoff_energy_loss_vs_max_friction",
        "tradeoff_energy_loss_vs_ring_mass",
        "tradeoff_max_friction_vs_ring_mass",
        "tradeoff_parallel",
    ]
    for stem in stems:
        assert (tmp_path / "out3" / f"{stem}.png").stat().st_size > 1000
    report = (tmp_path / "out3" / "report.md").read_text()
    assert all(f"({stem}.png)" in report for stem in stems)
    assert "mixed_share" not in "".join(stems)


def test_how_sure_section(constrained, tmp_path):
    study, out, _ = constrained
    report = (out / "report.md").read_text()
    section = report.split("## How sure is this answer", 1)[1]
    for part in (
        "### Numerical error of the film model",
        "### Calibration",
        "### Designs on a bound of the design box",
        "### Sensitivity to the uncertain inputs",
    ):
        assert part in section
    assert "preset = 'default'" in section and "calibrated (`&calibration file" in section
    assert re.search(r"ranking of the designs of cold .*(same|changes)", section)
    su = study.cases["cold"].sure
    # supply_film applies only to a starved inlet: this deck is flooded
    assert su.inputs == ["surface:zeta_kappa_sigma", "operating:pressure_scale"]
    # the stored extra runs are the true model's, recomputed here independently
    base = Case.from_namelist(COLD)
    x = su.x[-1:]  # the reference design
    acc, _, _ = run_designs(
        base.with_numerics(preset="accurate"), ["width", "crown_offset"], x, ["energy_loss"]
    )
    assert su.accurate[-1, 0] == acc[0, 0]
    f = UNCERTAIN[("operating", "pressure_scale")]
    cal = Case.from_namelist(INPUTS / "calibration.nml")  # read as the kernel reads it
    calibrated = cal["operating", "pressure_scale"]
    deck_text = COLD.read_text().replace("&calibration file = 'calibration.nml' /", "")
    deck_text = deck_text.replace("&operating ", f"&operating pressure_scale = {calibrated * f!r},")
    deck_text = deck_text.replace(
        "&surface   ", f"&surface   zeta_kappa_sigma = {cal['surface', 'zeta_kappa_sigma']!r}, "
    )
    varied = tmp_path / "varied.nml"
    varied.write_text(deck_text.replace("'pressure/", f"'{INPUTS}/pressure/"))
    hi, _, _ = run_designs(Case.from_namelist(varied), ["width", "crown_offset"], x, ["energy_loss"])
    assert su.high[1, -1, 0] == pytest.approx(hi[0, 0], rel=1e-12)
    # a chosen design on a bound is named
    on = [
        n
        for n, xi in zip(study.cases["cold"].chosen.names, study.cases["cold"].chosen.x)
        if np.isclose(xi[0], 0.8e-3) or np.isclose(xi[0], 1.2e-3)
    ]
    for n in on:
        assert f"cold, {n}: width at its" in section


def test_uncalibrated_case_is_said(tmp_path):
    text = COLD.read_text().replace("&calibration file = 'calibration.nml' /", "")
    base = tmp_path / "uncal.nml"
    base.write_text(text.replace("'pressure/", f"'{INPUTS}/pressure/"))
    study = run_study(
        deck(tmp_path, name="u", base=base),
        tmp_path / "outu",
        executor=Executor(serial=True),
        progress=False,
        figures=False,
    )
    assert "cold: **not calibrated**" in (tmp_path / "outu" / "report.md").read_text()
    assert study.cases["cold"].sure is not None
    assert ringlube  # imported for with_<group>


def test_constraint_bound_on_a_drawn_objective_is_a_line():
    from ringlube.study.plots import TradeoffSeries, tradeoff_figure

    fig = tradeoff_figure(
        [TradeoffSeries("rated", np.array([[0.3, 2.0], [0.4, 1.9]]), [("knee", 0.35, 1.95, "chosen")])],
        "oil [mm^3]",
        "energy [J]",
        limits=[("x", 0.461, "rated: oil_to_chamber <= reference (constraint)")],
    )
    ax = fig.axes[0]
    assert [line.get_xdata()[0] for line in ax.lines] == [0.461]
    assert "rated: oil_to_chamber <= reference (constraint)" in [
        t.get_text() for t in ax.get_legend().get_texts()
    ]


def test_summary_gives_constraints_and_feasibility(constrained):
    from ringlube.study.summary import summary

    text = summary(constrained[0])
    assert "constraints: max_friction <= reference; min_film >= 7e-07" in text
    assert text.count("; feasible") + text.count("; INFEASIBLE") == 4  # three chosen and the reference


def test_unchanged_resume_keeps_the_how_sure_runs(tmp_path, monkeypatch):
    import ringlube.study.pipeline as study_module

    path = deck(tmp_path, name="keep", extra="constraints = 'max_friction <= reference'")
    first = run_study(path, tmp_path / "out", executor=Executor(serial=True), progress=False, figures=False)

    def fail(*args, **kwargs):
        raise AssertionError("how_sure re-ran on an unchanged resume")

    monkeypatch.setattr(study_module, "how_sure", fail)
    again = run_study(path, tmp_path / "out", executor=Executor(serial=True), progress=False, figures=False)
    np.testing.assert_array_equal(again.cases["cold"].sure.high, first.cases["cold"].sure.high)
    assert again.cases["cold"].sure.names == first.cases["cold"].sure.names


def test_a_reference_that_did_not_converge_is_said_where_it_bounds(constrained, tmp_path):
    """'max_friction <= reference' with a reference design marked NOT CONVERGED: the bound is
    still its value, but a warning says so (one line from the command), and so do the
    report's constraint table and the summary (the bound was taken without a word)."""
    import dataclasses
    import warnings

    from ringlube.study.bounds import UnconvergedReferenceWarning, constraint_bounds
    from ringlube.study.report import write_report
    from ringlube.study.summary import summary

    study = constrained[0]
    c = study.cases["cold"]
    kept = c.reference
    assert "did NOT CONVERGE" not in summary(study)  # a converged reference: no word
    try:
        c.reference = dataclasses.replace(kept, converged=np.array([False]))
        said = r"case 'cold': the reference design did NOT CONVERGE"
        with pytest.warns(UnconvergedReferenceWarning, match=said):
            bounds = constraint_bounds(study, "cold")
        assert bounds[0].value == _reference_friction(study)  # the bound is still its value
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", UnconvergedReferenceWarning)
            text = summary(study)
            report = write_report(study, tmp_path).read_text()
        assert f"warning: {said}, so max_friction <= reference" in text
        row = next(line for line in report.splitlines() if line.startswith("| `max_friction <= reference` |"))
        assert row.endswith("N (its reference did NOT CONVERGE) |"), row
        assert "Warning: case 'cold': the reference design did NOT CONVERGE" in report
    finally:
        c.reference = kept
