"""Design studies under user mistakes and interruptions."""

from __future__ import annotations

import json
import shutil
import socket
import subprocess

import h5py
import numpy as np
import pytest

import ringlube
from ringlube import InputError, RinglubeError
from ringlube.case import Case
from ringlube.executor import Executor
from ringlube.study import run_study, summary
from ringlube.study.deck import read_study
from ringlube.study.runs import _run_designs, sample
from ringlube.study.store import Study
from ringlube.study.variables import OUTPUTS

from conftest import INPUTS

pytestmark = pytest.mark.io

COLD = INPUTS / "crf450r_4000rpm_full_cold.nml"


def study_deck(tmp_path, *, name="h", cases=(COLD,), labels=("cold",), samples=24, **extra) -> str:
    lines = [
        "&study",
        f"  name = '{name}'",
        "  cases = " + ", ".join(f"'{c}'" for c in cases),
        "  labels = " + ", ".join(f"'{x}'" for x in labels),
        f"  samples = {samples}, seed = 5",
        "  population = 12, generations = 4, repeats = 2",
    ]
    lines += [f"  {k} = {v}" for k, v in extra.items()]
    path = tmp_path / f"{name}.nml"
    path.write_text("\n".join(lines + ["/"]) + "\n")
    return str(path)


TWO_VARS = dict(variables="'width', 'crown_offset'", lower="0.8e-3, -40e-6", upper="1.2e-3, 40e-6")


def own_inputs(tmp_path):
    """A copy of the cold deck with its calibration file and pressure trace."""
    (tmp_path / "pressure").mkdir()
    shutil.copy(INPUTS / "pressure" / "crf450r_4000rpm_full.csv", tmp_path / "pressure")
    shutil.copy(INPUTS / "calibration.nml", tmp_path)
    shutil.copy(COLD, tmp_path / "cold.nml")
    return tmp_path / "cold.nml"


# --- item 1: resume from any interruption ---------------------------------------------


def test_resume_from_a_file_holding_only_samples(tmp_path):
    deck = study_deck(tmp_path, **TWO_VARS)
    s = read_study(deck)
    out = tmp_path / "out"
    out.mkdir()
    early = Study(s, out / "h.h5")  # what an interruption before the first batch leaves
    early.x = sample(s)
    early.stages.add("sampled")
    early.save()
    with h5py.File(out / "h.h5") as f:
        assert "cases" not in f
    study = run_study(deck, out, executor=Executor(serial=True), progress=False, figures=False)
    assert study.runs_executed == 24 and study.cases["cold"].runs.done.all()


def test_second_process_on_the_same_study_is_refused(tmp_path):
    s = read_study(study_deck(tmp_path, **TWO_VARS))
    first = Study.open(s, tmp_path / "h.h5", lock=True)
    try:
        with pytest.raises(RinglubeError, match="another ringlube optimise is working"):
            Study.open(s, tmp_path / "h.h5", lock=True)
    finally:
        first.unlock()
    Study.open(s, tmp_path / "h.h5", lock=True).unlock()  # free again


@pytest.mark.parametrize("garbage", [b"not hdf5 at all", b"\x89HDF\r\n\x1a\n" + b"\0" * 64])
def test_corrupt_study_file_is_an_input_error(tmp_path, garbage):
    deck = study_deck(tmp_path, **TWO_VARS)
    (tmp_path / "out").mkdir()
    (tmp_path / "out" / "h.h5").write_bytes(garbage)
    with pytest.raises(InputError, match=r"h\.h5: .*(not a study file|not a readable study)"):
        run_study(deck, tmp_path / "out", executor=Executor(serial=True), progress=False, figures=False)


# --- item 4: the study is keyed on the content of its inputs -----------------------------


@pytest.mark.parametrize("edit", ["cold.nml", "calibration.nml", "pressure/crf450r_4000rpm_full.csv"])
def test_resume_after_an_edited_input_is_refused(tmp_path, edit):
    deck = own_inputs(tmp_path)
    study = study_deck(tmp_path, cases=(deck,), **TWO_VARS)
    out = tmp_path / "out"
    with pytest.raises(KeyboardInterrupt):
        run_study(study, out, executor=Executor(serial=True), progress=False, figures=False, stop_after=4)
    target = tmp_path / edit
    target.write_text(
        target.read_text().replace("1", "2", 1)
        if edit.endswith(".csv")
        else target.read_text() + "! edited\n"
    )
    with pytest.raises(InputError, match=rf"other contents of .*{edit.split('/')[-1]}"):
        run_study(study, out, executor=Executor(serial=True), progress=False, figures=False)


def test_a_worker_with_another_kernel_refuses_the_batches(tmp_path, monkeypatch):
    """A Dask worker with another build of the kernel would add runs of another model to the
    study (the resume check compares the study file with the client's kernel only): every batch
    carries the study's kernel id and a worker whose own differs refuses it with a message naming
    both (noticed 2026-11-26). Here the study's id is made to differ from the worker's."""
    from ringlube.study import runs as study_runs

    case = Case.from_namelist(COLD)
    args = (case, [("ring", "width")], np.array([[1e-3]]), ["energy_loss"])
    _, ok, _ = _run_designs(*args, kernel=ringlube.kernel_id())
    assert ok.all()
    with pytest.raises(RinglubeError, match=r"install the same build on every worker"):
        _run_designs(*args, kernel="0123456789ab")
    study = study_deck(tmp_path, **TWO_VARS, direct_population=6, direct_generations=2, batch=6)
    # every batch a study sends: the samples, the checks of the chosen designs, how sure they
    # are, the direct NSGA-II
    sent = []
    real = study_runs._run_designs

    def spy(*task):
        sent.append(task[4] if len(task) > 4 else None)
        return real(*task)

    with monkeypatch.context() as m:
        m.setattr(study_runs, "_run_designs", spy)
        run_study(
            study,
            tmp_path / "ok",
            executor=Executor(serial=True),
            with_direct=True,
            progress=False,
            figures=False,
        )
    assert len(sent) > 4 and set(sent) == {ringlube.kernel_id()}, set(sent)
    monkeypatch.setattr(study_runs, "study_kernel", lambda: "0123456789ab")
    with pytest.raises(
        RinglubeError,
        match=rf"runs another ringlube kernel \({ringlube.kernel_id()}\) than this study \(0123456789ab\)",
    ):
        run_study(study, tmp_path / "out", executor=Executor(serial=True), progress=False, figures=False)


def test_resume_under_another_kernel_is_refused(tmp_path):
    """A study resumed after the kernel changed would fit one surface to runs of two models:
    a study file records the kernel build's id (ringlube.kernel_id(), a hash of the kernel's
    sources, compiler and flags) and a resume under another one is refused, like an edited
    input. Found on 2026-11-26: a study folder of an earlier session resumed silently and
    reported 4 designs 'not converged' that today's kernel converges."""
    study = study_deck(tmp_path, **TWO_VARS)
    out = tmp_path / "out"
    with pytest.raises(KeyboardInterrupt):
        run_study(study, out, executor=Executor(serial=True), progress=False, figures=False, stop_after=4)
    with h5py.File(out / "h.h5", "r") as f:
        assert f.attrs["kernel_id"] == ringlube.kernel_id()
    with h5py.File(out / "h.h5", "a") as f:
        f.attrs["kernel_id"] = "0123456789ab"
    with pytest.raises(
        InputError, match=r"h\.h5: the study's runs were made by another ringlube kernel \(0123456789ab"
    ):
        run_study(study, out, executor=Executor(serial=True), progress=False, figures=False)
    with h5py.File(out / "h.h5", "a") as f:
        del f.attrs["kernel_id"]  # a study file of a ringlube that did not record it
    with pytest.raises(InputError, match=r"another ringlube kernel \(not recorded"):
        run_study(study, out, executor=Executor(serial=True), progress=False, figures=False)
    # --restart (ringlube optimise) starts afresh under the lock: a new file of this kernel
    fresh = run_study(study, out, executor=Executor(serial=True), progress=False, figures=False, restart=True)
    assert fresh.cases["cold"].runs.done.all()
    with h5py.File(out / "h.h5", "r") as f:
        assert f.attrs["kernel_id"] == ringlube.kernel_id()


# --- item 14: variables of other groups, misspelt names ---------------------------------


def test_variable_of_another_group(tmp_path):
    deck = study_deck(
        tmp_path, variables="'width', 'operating:speed_rpm'", lower="0.8e-3, 3000", upper="1.2e-3, 5000"
    )
    s = read_study(deck)
    assert s.groups_names == [("ring", "width"), ("operating", "speed_rpm")]
    assert s.units == ["m", "r/min"]  # units from the kernel's input table
    base = Case.from_namelist(COLD)
    values, conv, errors = _run_designs(base, s.groups_names, np.array([[1e-3, 3000.0]]), ["energy_loss"])
    r = ringlube.run(base.with_ring(width=1e-3).with_operating(speed_rpm=3000.0))
    assert errors == [""] and values[0, 0] == r.energy_loss


@pytest.mark.parametrize(
    "extra, message",
    [
        (
            dict(variables="'widht'", lower="1e-3", upper="2e-3"),
            r"&study variables: 'widht' is not a variable of &ring",
        ),
        (
            dict(variables="'engine:speed'", lower="1", upper="2"),
            r"&study variables: 'engine:speed' is not a variable of &engine",
        ),
        (dict(variables="'nogroup:x'", lower="1", upper="2"), r"&study variables: 'nogroup:x'"),
        (
            dict(variables="'width', 'operating:speed_rpm'"),
            r"&study lower: required: default ranges exist only for the ring variables",
        ),
        (dict(variables="'width'", lower="0.5e-3"), r"&study upper: required when 'lower'"),
        (dict(direct_generations="1000000"), r"&study direct_generations: "),
        (
            dict(cases=("nonexistent.nml",), labels=("x",)),
            r"h\.nml:3: &study cases: base deck 'x': .*not found",
        ),
        (
            dict(variables="'width'", lower="-1e-3", upper="1e-3"),
            r"&study lower: width = -0.001 is rejected by base deck 'cold'.*must be in",
        ),
    ],
)
def test_bad_variables_name_study_variables(tmp_path, extra, message):
    with pytest.raises(InputError, match=message):
        read_study(study_deck(tmp_path, **extra))


@pytest.mark.parametrize("value", ["2000000000", "1"])
def test_population_out_of_range_is_refused_before_any_run(tmp_path, value):
    """A population of 2e9 ran every sample and then failed in NSGA-II allocating 60 GiB; one of
    1 ran a one-design 'Pareto set' (a review, 2026-11-26): both are input errors now."""
    path = study_deck(tmp_path, **TWO_VARS)
    text = open(path).read().replace("population = 12", f"population = {value}")
    open(path, "w").write(text)
    with pytest.raises(InputError, match=r"h\.nml:\d+: &study population: "):
        read_study(path)


def test_default_bounds_only_when_none_given(tmp_path):
    s = read_study(
        study_deck(tmp_path, variables="'crown_height', 'tension'", lower="7e-6, 9", upper="8e-6, 10")
    )
    assert (s.lower, s.upper) == ([7e-6, 9.0], [8e-6, 10.0])
    s = read_study(study_deck(tmp_path, variables="'crown_height', 'tension'"))
    assert (s.lower, s.upper) == ([6e-6, 8.0], [13e-6, 26.0])


# --- item 15: invalid designs inside the box -------------------------------------------


def test_invalid_designs_are_recorded_and_the_study_goes_on(tmp_path):
    # |crown_offset| < width/2 is required: the corners (small width, large offset) fail
    deck = study_deck(
        tmp_path,
        samples=32,
        variables="'width', 'crown_offset'",
        lower="0.1e-3, -0.2e-3",
        upper="1.0e-3, 0.2e-3",
    )
    study = run_study(deck, tmp_path / "out", executor=Executor(serial=True), progress=False, figures=False)
    r = study.cases["cold"].runs
    x = study.x
    expect = np.abs(x[:, 1]) >= x[:, 0] / 2
    assert expect.any() and not expect.all()
    np.testing.assert_array_equal(r.failed, expect)
    assert r.done.all() and np.isnan(r.outputs[r.failed]).all()
    assert all("crown_offset" in r.errors[i] for i in np.flatnonzero(expect))
    assert study.cases["cold"].surfaces["energy_loss"].n == int((~expect & r.converged).sum())
    from ringlube.study.summary import summary

    text = summary(study)
    assert f"{int(expect.sum())} failed (invalid designs)" in text
    assert f"{int(expect.sum())} |" in (tmp_path / "out" / "report.md").read_text()
    with h5py.File(study.path) as f:
        errors = [e.decode() for e in f["cases/cold/runs/errors"][()]]
        assert [bool(e) for e in errors] == expect.tolist()


def test_run_designs_reports_each_failure():
    base = Case.from_namelist(COLD)
    values, conv, errors = _run_designs(base, [("ring", "width")], np.array([[1e-3], [-1e-3]]), list(OUTPUTS))
    assert errors[0] == "" and "&ring width" in errors[1]
    assert np.isfinite(values[0]).all() and np.isnan(values[1]).all()
    assert conv.tolist() == [True, False]


# --- item 16: executor inputs --------------------------------------------------------


@pytest.mark.parametrize("workers", [0, -2])
def test_executor_refuses_fewer_than_one_worker(workers):
    with pytest.raises(InputError, match="--workers"):
        Executor(workers=workers, backend="processes")


@pytest.mark.slow
def test_unreachable_scheduler_is_one_error(monkeypatch):
    import ringlube.executor as ex

    with socket.socket() as sock:  # a free port nobody listens on
        sock.bind(("127.0.0.1", 0))
        port = sock.getsockname()[1]
    with pytest.raises(
        RinglubeError,
        match=rf"--scheduler tcp://127.0.0.1:{port}: cannot "
        r"connect within 2 s",
    ):
        ex.Executor(scheduler=f"tcp://127.0.0.1:{port}", connect_timeout=2)


def test_local_cluster_keeps_a_worker_whose_batch_outlasts_the_heartbeat_ttl():
    """A kernel call holds the GIL for its whole batch: the worker sends no heartbeat while it
    runs. The local cluster must not drop a worker for that (Dask's default worker-ttl of 5
    minutes dropped the workers of a bore study's 'accurate' checks on a loaded machine, and
    ran their batches again until Dask gave them up)."""
    with Executor(workers=1) as ex:
        assert ex.cluster.scheduler.worker_ttl is None
        assert "worker-ttl" not in ex.cluster.scheduler.periodic_callbacks


def test_process_backend_matches_serial():
    tasks = [(i, 3) for i in range(7)]
    a, b = {}, {}
    with Executor(serial=True) as ex:
        ex.map(pow, tasks, a.__setitem__)
    with Executor(backend="processes", workers=2) as ex:
        ex.map(pow, tasks, b.__setitem__)
    assert a == b == {i: i**3 for i in range(7)}


@pytest.mark.parametrize("backend", ["processes", "dask"])
def test_parallel_backends_call_on_idle_while_they_wait(tmp_path, backend):
    """While a task runs, the executor calls ``on_idle`` in this process (the study saves a
    run that was too soon after the last save from there). The task waits for the file that
    only ``on_idle`` writes: without the call it gives up and returns 1."""
    flag = tmp_path / "idle"
    script = f"for i in $(seq 2400); do [ -e '{flag}' ] && exit 0; sleep 0.05; done; exit 1"
    out, idle = {}, []

    def on_idle():
        idle.append(1)
        flag.touch()

    with Executor(backend=backend, workers=1) as ex:
        ex.map(subprocess.call, [(["sh", "-c", script],)], out.__setitem__, on_idle=on_idle)
    assert out == {0: 0}
    assert idle


def test_a_save_skipped_as_too_soon_is_made_while_waiting(tmp_path):
    """A run that finishes within 2 s of the last save is not written then; ``save_pending``
    (called while the executor waits) writes it once 2 s have passed, and rewrites nothing
    when nothing is pending."""
    s = read_study(study_deck(tmp_path, **TWO_VARS))
    st = Study(s, tmp_path / "h.h5")
    st.x = sample(s)
    st.save()
    x = np.array([1.0e-3, 0.0])
    st.check_runs[("cold abc", x.tobytes())] = (x, np.zeros(len(s.outputs)), True, "")
    st.save(force=False)
    with h5py.File(tmp_path / "h.h5") as f:
        assert "check_runs" not in f
    st._last_save -= 2.0
    st.save_pending()
    with h5py.File(tmp_path / "h.h5") as f:
        assert "check_runs" in f
    inode = (tmp_path / "h.h5").stat().st_ino
    st._last_save -= 2.0
    st.save_pending()
    assert (tmp_path / "h.h5").stat().st_ino == inode


# --- items 24 and 25: labelled matrices, the optional reference --------------------------


def test_study_file_labels_its_columns_and_the_reference(tmp_path):
    deck = study_deck(tmp_path, reference="1.004e-3, -38.3e-6", **TWO_VARS)
    study = run_study(deck, tmp_path / "out", executor=Executor(serial=True), progress=False, figures=False)
    with h5py.File(study.path) as f:
        d = f["samples/x"]
        assert list(d.attrs["columns"]) == ["width", "crown_offset"]
        assert list(d.attrs["units"]) == ["m", "m"]
        d = f["cases/cold/runs/outputs"]
        assert list(d.attrs["columns"]) == list(OUTPUTS)
        assert list(d.attrs["units"])[:3] == ["J", "%", "g"]
        assert list(f["cases/cold/front/f"].attrs["columns"]) == ["energy_loss", "mixed_share", "ring_mass"]
        assert json.loads(f.attrs["settings"])["reference"] == [1.004e-3, -38.3e-6]
    ref = study.cases["cold"].reference
    r = ringlube.run(Case.from_namelist(COLD).with_ring(width=1.004e-3, crown_offset=-38.3e-6))
    assert ref.names == ["reference"]
    np.testing.assert_array_equal(ref.f_true[0], [getattr(r, o) for o in OUTPUTS])
    assert "reference" in (tmp_path / "out" / "report.md").read_text()
    # without a reference: none computed, none reported
    deck = study_deck(tmp_path, name="noref", **TWO_VARS)
    study = run_study(deck, tmp_path / "out2", executor=Executor(serial=True), progress=False, figures=False)
    assert study.cases["cold"].reference is None
    assert "reference" not in (tmp_path / "out2" / "report.md").read_text()


def test_shipped_study_decks_read(tmp_path):
    for deck in ("study_default.nml", "study_full.nml"):
        s = read_study(INPUTS / deck)
        assert s.reference == [1.004e-3, 9.31e-6, -38.3e-6, 8.0]
        assert s.units == ["m", "m", "m", "N"]  # the decks read the tension in N


def test_reference_added_on_resume_is_computed(tmp_path):
    deck = study_deck(tmp_path, **TWO_VARS)
    study = run_study(deck, tmp_path / "out", executor=Executor(serial=True), progress=False, figures=False)
    assert study.cases["cold"].reference is None
    text = open(deck).read().replace("/\n", "  reference = 1.0e-3, 0.0\n/\n")
    open(deck, "w").write(text)
    study = run_study(deck, tmp_path / "out", executor=Executor(serial=True), progress=False, figures=False)
    assert study.runs_executed == 0
    np.testing.assert_array_equal(study.cases["cold"].reference.x, [[1.0e-3, 0.0]])


def test_old_layout_file_is_refused(tmp_path):
    deck = study_deck(tmp_path, **TWO_VARS)
    (tmp_path / "out").mkdir()
    with h5py.File(tmp_path / "out" / "h.h5", "w") as f:  # layout 1: no format attribute
        f.attrs["key"] = read_study(deck).key()
        f["samples/x"] = np.zeros((24, 2))
    with pytest.raises(InputError, match="not a ringlube study file"):
        run_study(deck, tmp_path / "out", executor=Executor(serial=True), progress=False, figures=False)


@pytest.mark.parametrize("missing, what", [("dask", "--workers"), ("pymoo", "serial")])
def test_missing_optional_package_says_how_to_install(tmp_path, monkeypatch, missing, what):
    import sys

    for name in list(sys.modules):
        if name == missing or name.startswith(missing + "."):
            monkeypatch.delitem(sys.modules, name)
    monkeypatch.setitem(sys.modules, missing, None)  # import now fails
    if missing == "dask":
        monkeypatch.setitem(sys.modules, "dask.distributed", None)
    deck = study_deck(tmp_path, **TWO_VARS)
    kw = (
        dict(executor=lambda: Executor(workers=1))
        if what == "--workers"
        else dict(executor=Executor(serial=True))
    )
    with pytest.raises(RinglubeError, match=r"pip install ringlube\[study\]"):
        run_study(deck, tmp_path / "out", progress=False, figures=False, **kw)


def test_run_study_leaves_the_callers_executor_open_and_closes_the_one_it_made(tmp_path):
    """run_study's executor: an Executor given is the caller's (used, left open); a function
    that makes one is called only once the deck is checked, and what it made is closed."""

    class Counting(Executor):
        made, closed = 0, 0

        def __init__(self, *args, **kwargs):
            type(self).made += 1
            super().__init__(*args, **kwargs)

        def close(self):
            type(self).closed += 1
            super().close()

    bad = tmp_path / "bad.nml"
    bad.write_text("&study\n  name = 'b'\n  samples = -1\n/\n")
    with pytest.raises(InputError):
        run_study(bad, tmp_path / "out", executor=lambda: Counting(serial=True), progress=False)
    assert (Counting.made, Counting.closed) == (0, 0)  # the deck refused before any executor
    deck = study_deck(tmp_path, **TWO_VARS)
    mine = Counting(serial=True)
    run_study(deck, tmp_path / "out", executor=mine, progress=False, figures=False)
    assert (Counting.made, Counting.closed) == (1, 0)
    again = run_study(
        deck, tmp_path / "out", executor=lambda: Counting(serial=True), progress=False, figures=False
    )
    assert again.runs_executed == 0 and (Counting.made, Counting.closed) == (2, 1)


# --- the later stages' runs are kept across interruptions too ------------------------------


class _Stopping(Executor):
    """A serial executor that counts the designs it runs and raises KeyboardInterrupt (what
    Ctrl-C raises) once ``stop_at`` tasks of its ``stage``-th map call (0: the samples) have
    finished."""

    def __init__(self, stage=None, stop_at=None):
        super().__init__(serial=True)
        self.stage, self.stop_at, self.calls, self.designs = stage, stop_at, [], 0

    def map(self, fn, tasks, on_result, on_idle=None):
        if fn is not _run_designs:
            return super().map(fn, tasks, on_result)
        self.calls.append(0)
        call = len(self.calls) - 1

        def counted(i, value):
            on_result(i, value)
            self.calls[call] += 1
            self.designs += len(tasks[i][2])
            if call == self.stage and self.calls[call] == self.stop_at:
                raise KeyboardInterrupt("stopped by the test")

        super().map(fn, tasks, counted)


def _later_results(study):
    out = {}
    for label, c in study.cases.items():
        for key in ("candidates", "chosen", "reference"):
            ch = getattr(c, key)
            out[label, key] = (ch.x, ch.f_true, ch.converged, ch.errors, ch.points)
        out[label, "sure"] = (c.sure.names, c.sure.x, c.sure.accurate, c.sure.low, c.sure.high)
    return out


@pytest.mark.slow
@pytest.mark.parametrize("stage, stop_at", [("check", 5), ("chosen at the other point", 1), ("how sure", 5)])
def test_interrupted_check_and_how_sure_keep_their_finished_runs(tmp_path, stage, stop_at):
    """The check of the candidates and reference, the chosen designs at the other points and the
    how-sure runs kept their finished runs only in memory until the stage ended: an interruption
    lost them all. Now each finished run is in the study file and a resume runs only the others,
    with the results of a study never interrupted."""
    deck = study_deck(
        tmp_path,
        cases=(COLD, INPUTS / "crf450r_4000rpm_full_hot.nml"),
        labels=("cold", "hot"),
        scene=".true.",
        reference="1.0e-3, 0.0",
        constraints="'max_friction <= 1e6'",
        batch=2,
        **TWO_VARS,
    )
    whole = _Stopping()
    first = run_study(deck, tmp_path / "whole", executor=whole, progress=False, figures=False)
    # map calls of _run_designs: samples, reference, candidates, chosen at the other point, how sure
    assert len(whole.calls) == 5 and all(n >= 2 for n in whole.calls)
    total = sum(whole.calls[1:])  # tasks of the later stages
    assert first.checks_executed == whole.designs - first.runs_executed

    call = {"check": 2, "chosen at the other point": 3, "how sure": 4}[stage]
    assert stop_at < whole.calls[call]  # interrupted with some of the stage's tasks finished
    stopping = _Stopping(stage=call, stop_at=stop_at)
    out = tmp_path / "out"
    with pytest.raises(KeyboardInterrupt):
        run_study(deck, out, executor=stopping, progress=False, figures=False)
    made = stopping.designs - first.runs_executed  # the later stages' runs of the interrupted process
    with h5py.File(out / "h.h5") as f:
        assert len(f["check_runs/case"]) == made  # every finished one saved
        assert list(f["check_runs/x"].attrs["columns"]) == ["width", "crown_offset"]

    resumed = _Stopping()
    again = run_study(deck, out, executor=resumed, progress=False, figures=False)
    assert again.runs_executed == 0
    assert resumed.designs == again.checks_executed == first.checks_executed - made  # none run twice
    assert sum(resumed.calls) < total
    assert f"runs executed now: 0 (and {again.checks_executed} of the checks)" in summary(again)
    a, b = _later_results(first), _later_results(again)
    assert a.keys() == b.keys()
    for k in a:
        for u, v in zip(a[k], b[k]):
            if isinstance(u, dict):
                assert u.keys() == v.keys()
                for p in u:
                    np.testing.assert_array_equal(u[p], v[p])
            elif u is None:
                assert v is None
            else:
                np.testing.assert_array_equal(np.asarray(u), np.asarray(v), err_msg=str(k))

    third = _Stopping()  # a finished study resumed runs nothing
    run_study(deck, out, executor=third, progress=False, figures=False)
    assert third.designs == 0


def test_stored_check_runs_read_back_and_those_of_other_settings_are_dropped(tmp_path):
    """Files written before the later stages' runs were kept (no /check_runs) still resume;
    stored runs read back as written; runs stored with another ``key`` (variables, recorded
    results, kernel) are not used."""
    s = read_study(study_deck(tmp_path, **TWO_VARS))
    early = Study(s, tmp_path / "h.h5")
    early.x = sample(s)
    early.save()
    with h5py.File(tmp_path / "h.h5") as f:
        assert "check_runs" not in f
    assert Study.open(s, tmp_path / "h.h5").check_runs == {}

    x = np.array([1.0e-3, 0.0])
    v = np.arange(len(s.outputs), dtype=float)
    early.check_runs[("cold abc", x.tobytes())] = (x, v, False, "no film")
    early.save()
    back = Study.open(s, tmp_path / "h.h5").check_runs
    assert list(back) == [("cold abc", x.tobytes())]
    bx, bv, ok, err = back["cold abc", x.tobytes()]
    np.testing.assert_array_equal(bx, x)
    np.testing.assert_array_equal(bv, v)
    assert (ok, err) == (False, "no film")
    with h5py.File(tmp_path / "h.h5", "r+") as f:
        f["check_runs"].attrs["key"] = early.check_runs_key().replace("kernel", "other kernel")
    assert Study.open(s, tmp_path / "h.h5").check_runs == {}
