"""A design whose true-model run did not converge is never reported as verified nor ranked
as a good design; the direct NSGA-II resumes from its last finished generation."""

from __future__ import annotations

import numpy as np
import pytest

import ringlube.study.runs as runs_mod
from ringlube.executor import Executor
from ringlube.study import run_study
from ringlube.study.format import NOT_CONVERGED
from ringlube.study.report import write_report
from ringlube.study.summary import summary

from conftest import COLD

pytestmark = pytest.mark.numerics

#: designs with a crown offset above this are made 'unconverged' by the tests' stand-in
OFFSET_LIMIT = 0.0


def write(tmp_path, name="v", samples=32, generations=4) -> str:
    path = tmp_path / f"{name}.nml"
    path.write_text(
        f"&study\n  name = '{name}', cases = '{COLD}', labels = 'cold'\n"
        "  variables = 'width', 'crown_offset', lower = 0.8e-3, -40e-6, upper = 1.2e-3, 40e-6\n"
        "  objectives = 'energy_loss', 'mixed_share'\n"
        f"  samples = {samples}, seed = 3, population = 12, generations = 4, repeats = 2\n"
        f"  direct_population = 6, direct_generations = {generations}, batch = 6\n/\n"
    )
    return str(path)


def some_unconverged(real):
    """``_run_designs`` whose runs at a large crown offset report 'not converged'."""

    def run(base, variables, x, outputs, kernel=None):
        values, converged, errors = real(base, variables, x, outputs, kernel)
        return values, converged & (np.asarray(x)[:, 1] <= OFFSET_LIMIT), errors

    return run


def test_direct_nsga2_never_ranks_an_unconverged_run(tmp_path, monkeypatch):
    monkeypatch.setattr(runs_mod, "_run_designs", some_unconverged(runs_mod._run_designs))
    study = run_study(
        write(tmp_path),
        tmp_path / "out",
        executor=Executor(serial=True),
        with_direct=True,
        progress=False,
        figures=False,
    )
    d = study.cases["cold"].direct
    assert d.unconverged > 0
    assert np.all(d.x[:, 1] <= OFFSET_LIMIT), "an unconverged design is in the direct front"
    assert "not converged, 0 lifted off the liner: never in its front" in summary(study)


def test_direct_nsga2_never_ranks_a_lifted_run(tmp_path, monkeypatch):
    """A design that lifts the ring off the liner is ranked below every design
    that does not (the tests' stand-in lifts designs with a large crown offset)."""
    real = runs_mod._run_designs

    def some_lifted(base, variables, x, outputs, kernel=None):
        values, converged, errors = real(base, variables, x, outputs, kernel)
        values[:, list(outputs).index("liner_lift_share")] = np.where(
            np.asarray(x)[:, 1] > OFFSET_LIMIT, 5.0, 0.0
        )
        return values, converged, errors

    monkeypatch.setattr(runs_mod, "_run_designs", some_lifted)
    study = run_study(
        write(tmp_path),
        tmp_path / "out",
        executor=Executor(serial=True),
        with_direct=True,
        progress=False,
        figures=False,
    )
    d = study.cases["cold"].direct
    assert d.lifted > 0 and d.unconverged == 0
    assert np.all(d.x[:, 1] <= OFFSET_LIMIT), "a lifted design is in the direct front"
    assert f"{d.lifted} lifted off the liner: never in its front" in summary(study)


def test_unconverged_recheck_is_marked_in_summary_and_report(tmp_path):
    study = run_study(
        write(tmp_path, generations=1),
        tmp_path / "out",
        executor=Executor(serial=True),
        progress=False,
        figures=False,
    )
    chosen = study.cases["cold"].chosen
    chosen.converged[:] = True
    chosen.converged[1] = False
    text = summary(study)
    marked = [line for line in text.splitlines() if NOT_CONVERGED in line]
    assert len(marked) == 1 and marked[0].strip().startswith(chosen.names[1])
    report = write_report(study, tmp_path / "out").read_text()
    assert f"| {chosen.names[1]} ({NOT_CONVERGED}) |" in report
    assert f"| {chosen.names[0]} |" in report


@pytest.mark.slow
def test_direct_nsga2_resumes_from_its_last_generation(tmp_path, monkeypatch):
    real = runs_mod._run_designs
    deck = write(tmp_path)
    run_study(deck, tmp_path / "out", executor=Executor(serial=True), progress=False, figures=False)
    fresh_deck = write(tmp_path, name="fresh")
    run_study(fresh_deck, tmp_path / "fresh", executor=Executor(serial=True), progress=False, figures=False)
    rows: list[int] = []

    def counting(base, variables, x, outputs, kernel=None):  # one call per generation (batch = population)
        if stop_at is not None and len(rows) == stop_at:
            raise KeyboardInterrupt("test: interrupted during the direct NSGA-II")
        rows.append(len(x))
        return real(base, variables, x, outputs, kernel)

    monkeypatch.setattr(runs_mod, "_run_designs", counting)
    stop_at = None
    fresh = run_study(
        fresh_deck,
        tmp_path / "fresh",
        executor=Executor(serial=True),
        with_direct=True,
        progress=False,
        figures=False,
    )
    all_rows, rows[:] = list(rows), []
    assert len(all_rows) == 4  # the test's premise: one call per generation
    stop_at = 2
    with pytest.raises(KeyboardInterrupt):
        run_study(
            deck,
            tmp_path / "out",
            executor=Executor(serial=True),
            with_direct=True,
            progress=False,
            figures=False,
        )
    assert rows == all_rows[:2]
    rows[:], stop_at = [], None
    resumed = run_study(
        deck,
        tmp_path / "out",
        executor=Executor(serial=True),
        with_direct=True,
        progress=False,
        figures=False,
    )
    assert rows == all_rows[2:]  # the two finished generations were not re-run
    a, b = resumed.cases["cold"].direct, fresh.cases["cold"].direct
    np.testing.assert_array_equal(a.x, b.x)
    np.testing.assert_array_equal(a.f, b.f)
    assert a.runs == b.runs == sum(all_rows)


def test_lifted_design_is_marked_in_summary_report_and_pareto_csv(tmp_path, monkeypatch):
    """A design whose true-model run lifted the ring off the liner (liner_lift_share
    > 0) is marked like an unconverged one, never shown as a good design; the Pareto CSV marks
    the designs the surfaces predict to lift off."""
    import csv

    import ringlube.study.pareto as pareto_mod
    from ringlube.study.format import LIFTED, LIFTED_COLUMN
    from ringlube.study.pareto import write_pareto_csv

    study = run_study(
        write(tmp_path, generations=1),
        tmp_path / "out",
        executor=Executor(serial=True),
        progress=False,
        figures=False,
    )
    chosen = study.cases["cold"].chosen
    j = list(study.s.outputs).index("liner_lift_share")
    chosen.f_true[:, j] = 0.0
    chosen.f_true[0, j] = 12.5
    text = summary(study)
    marked = [line for line in text.splitlines() if LIFTED in line]
    assert len(marked) == 1 and marked[0].strip().startswith(chosen.names[0])
    assert "12.5 % of the cycle" in marked[0]
    report = write_report(study, tmp_path / "out").read_text()
    assert f"| {chosen.names[0]} ({LIFTED} (12.5 % of the cycle)) |" in report
    assert f"| {chosen.names[1]} |" in report
    # the CSV: a design predicted to lift off (above the surface's CV error) is marked
    real = pareto_mod.predict

    def lifting(st, label, x):
        pred = real(st, label, x)
        pred[:, j] = 0.0
        pred[0, j] = 50.0
        return pred

    monkeypatch.setattr(pareto_mod, "predict", lifting)
    (path,) = write_pareto_csv(study, tmp_path / "out")
    with open(path) as fh:
        rows = list(csv.reader(fh))
    assert rows[0][-1] == LIFTED_COLUMN
    assert [r[-1] for r in rows[1:]] == ["yes"] + ["no"] * (len(rows) - 2)


def test_chosen_designs_are_the_true_models_best_of_the_front(tmp_path, monkeypatch):
    """The surfaces choose the candidates, the true model chooses among them: a surrogate knee
    that lifts the ring off the liner by the true model is not the chosen knee, and the chosen
    designs are the extremes and the knee, by the true values, of the Pareto set of the good
    candidates (converged, on the liner), recomputed here by brute force. (The tests' stand-in
    lifts only the surrogate's knee, which is no sample, so the surfaces and the front are
    those of the plain study.)"""
    plain = run_study(
        write(tmp_path), tmp_path / "plain", executor=Executor(serial=True), progress=False, figures=False
    )
    cand = plain.cases["cold"].candidates
    assert cand.names[: len(plain.s.objectives) + 1] == [
        *(f"surrogate min {o}" for o in plain.s.objectives),
        "surrogate knee",
    ]
    knee = cand.x[cand.names.index("surrogate knee")]
    assert not (np.asarray(plain.x) == knee).all(axis=1).any()
    real = runs_mod._run_designs

    def knee_lifts(base, variables, x, outputs, kernel=None):
        values, converged, errors = real(base, variables, x, outputs, kernel)
        at = (np.asarray(x) == knee).all(axis=1)
        values[at, list(outputs).index("liner_lift_share")] = 3.0
        return values, converged, errors

    monkeypatch.setattr(runs_mod, "_run_designs", knee_lifts)
    study = run_study(
        write(tmp_path), tmp_path / "out", executor=Executor(serial=True), progress=False, figures=False
    )
    c = study.cases["cold"]
    np.testing.assert_array_equal(c.front.x, plain.cases["cold"].front.x)
    f = c.candidates.f_true
    j_lift = list(study.s.outputs).index("liner_lift_share")
    good = np.flatnonzero(c.candidates.converged & (f[:, j_lift] == 0))
    assert len(good) == len(f) - 1  # only the knee lifted
    obj = f[good][:, [list(study.s.outputs).index(o) for o in study.s.objectives]]
    pareto = [
        i for i in range(len(obj)) if not (np.all(obj <= obj[i], axis=1) & np.any(obj < obj[i], axis=1)).any()
    ]
    po = obj[pareto]
    z = (po - po.min(0)) / (po.max(0) - po.min(0))
    rows = [int(np.argmin(po[:, k])) for k in range(po.shape[1])] + [int(np.argmin(np.hypot(*z.T)))]
    np.testing.assert_array_equal(c.chosen.x, c.candidates.x[good[np.array(pareto)[rows]]])
    assert not (c.chosen.x == knee).all(axis=1).any()
    assert (c.chosen.f_true[:, j_lift] == 0).all()
    assert "is not the chosen knee: lifted off the liner" in summary(study)
    report = write_report(study, tmp_path / "out").read_text()
    assert "is not the chosen knee: lifted off the liner" in report
