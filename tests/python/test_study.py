"""Design optimisation: surrogate exactness, a small study end to end, resume
after an interruption, and a real Dask cluster on loopback (one worker killed mid-run)."""

from __future__ import annotations

import json
import signal
import subprocess
import sys
import time

import h5py
import numpy as np
import pytest

import ringlube
from ringlube.case import Case
from ringlube.executor import Executor
from ringlube.study import run_study, runs
from ringlube.study.deck import read_study
from ringlube.study.runs import run_samples, sample
from ringlube.study.store import Study
from ringlube.study.surrogate import fit_quadratic, quadratic_features

from conftest import INPUTS

pytestmark = pytest.mark.numerics

LOWER = [0.54e-3, 6e-6, -54e-6, 8.0]
UPPER = [1.34e-3, 13e-6, 67e-6, 26.0]


def write_study(tmp_path, name="t", samples=40, cases=("cold",), **extra) -> str:
    decks = {"cold": INPUTS / "crf450r_4000rpm_full_cold.nml", "hot": INPUTS / "crf450r_4000rpm_full_hot.nml"}
    lines = [
        "&study",
        f"  name = '{name}'",
        "  cases = " + ", ".join(f"'{decks[c]}'" for c in cases),
        "  labels = " + ", ".join(f"'{c}'" for c in cases),
        f"  samples = {samples}, sampler = 'sobol', seed = 7",
        "  population = 24, generations = 15, repeats = 2",
        "  direct_population = 8, direct_generations = 3, batch = 4",
    ]
    lines += [f"  {k} = {v}" for k, v in extra.items()]
    lines.append("/")
    path = tmp_path / f"{name}.nml"
    path.write_text("\n".join(lines) + "\n")
    return str(path)


def test_quadratic_fit_recovers_known_coefficients():
    rng = np.random.default_rng(3)
    coef = rng.normal(size=15)
    x = rng.uniform(LOWER, UPPER, size=(60, 4))
    probe = fit_quadratic(x, np.zeros(60), LOWER, UPPER)  # only for its scaling
    y = quadratic_features(probe.scale(x)) @ coef
    surf = fit_quadratic(x, y, LOWER, UPPER)
    np.testing.assert_allclose(surf.coef, coef, rtol=0, atol=1e-10)
    assert surf.r2 == pytest.approx(1.0, abs=1e-12)


@pytest.mark.slow
def test_small_study_end_to_end(tmp_path):
    deck = write_study(
        tmp_path, name="e2e", samples=40, cases=("cold", "hot"), scene=".true.", weights="3.0, 1.0"
    )
    study = run_study(
        deck, tmp_path / "out", executor=Executor(serial=True), with_direct=True, progress=False
    )
    s = study.s
    with h5py.File(study.path) as f:
        assert f["samples/x"].shape == (40, 4)
        for label in ("cold", "hot"):
            g = f[f"cases/{label}"]
            assert g["runs/done"][()].all()
            for o in s.objectives:
                assert f"surface/{o}/coef" in g and g[f"surface/{o}"].attrs["r2"] > 0.5
            assert g["front/f"].shape[1] == 3
            assert "chosen/f_true" in g and "direct/f" in g
        assert set(json.loads(f.attrs["stages"])) >= {
            "sampled",
            "ran",
            "fitted",
            "optimised",
            "checked",
            "direct",
        }
    # the weighted scene: 3:1 mean of the two cases' objectives, with its own front
    np.testing.assert_allclose(
        study.objectives("scene"),
        0.75 * study.objectives("cold") + 0.25 * study.objectives("hot"),
        rtol=1e-14,
    )
    assert study.cases["scene"].front.f.shape[1] == 3
    # stored objectives are the true model's: re-run two samples and one chosen design
    base = Case.from_namelist(s.cases[0])
    for i in (0, 17):
        r = ringlube.run(base.with_ring(**dict(zip(s.variables, study.x[i]))))
        np.testing.assert_array_equal(
            study.objectives("cold")[i], [r.energy_loss, r.mixed_share, r.ring_mass]
        )
    ch = study.cases["cold"].chosen
    r = ringlube.run(base.with_ring(**dict(zip(s.variables, ch.x[-1]))))
    np.testing.assert_array_equal(ch.f_true[-1, :3], [r.energy_loss, r.mixed_share, r.ring_mass])
    # the merged front is non-dominated
    f = study.cases["cold"].front.f
    dominated = [(np.all(f <= fi, axis=1) & np.any(f < fi, axis=1)).any() for fi in f]
    assert not any(dominated)
    for stem in (
        "energy_loss_vs_mixed_share",
        "energy_loss_vs_ring_mass",
        "mixed_share_vs_ring_mass",
        "parallel",
    ):
        assert (tmp_path / "out" / f"tradeoff_{stem}.png").stat().st_size > 1000
    assert (tmp_path / "out" / "fit_cold.png").stat().st_size > 1000


def test_resume_reruns_nothing_that_finished(tmp_path):
    deck = write_study(tmp_path, name="resume", samples=40)
    out = tmp_path / "out"
    with pytest.raises(KeyboardInterrupt):
        run_study(deck, out, executor=Executor(serial=True), progress=False, figures=False, stop_after=12)
    with h5py.File(out / "resume.h5") as f:
        done_before = int(f["cases/cold/runs/done"][()].sum())
    assert 12 <= done_before < 40
    study = run_study(deck, out, executor=Executor(serial=True), progress=False, figures=False)
    assert study.runs_executed == 40 - done_before
    again = run_study(deck, out, executor=Executor(serial=True), progress=False, figures=False)
    assert again.runs_executed == 0
    # and the results equal an uninterrupted study
    fresh = run_study(deck, tmp_path / "fresh", executor=Executor(serial=True), progress=False, figures=False)
    np.testing.assert_array_equal(again.objectives("cold"), fresh.objectives("cold"))


def closed_form(case: Case, x: np.ndarray, outputs: list[str]) -> np.ndarray:
    """Results of designs ``x`` (width, crown height, crown offset, tension) from a closed
    form instead of the kernel: each result a bowl centred elsewhere in the box (so the
    objectives conflict), the lift shares 0; 1 % higher at the 'accurate' preset, so a check
    can tell which case a row ran on."""
    u = (np.asarray(x) - LOWER) / (np.asarray(UPPER) - LOWER)
    centres = np.linspace(0.1, 0.9, len(outputs))
    values = np.array([((u - c) ** 2).sum(axis=1) + 0.1 * k for k, c in enumerate(centres)]).T
    values[:, [k for k, o in enumerate(outputs) if o.endswith("lift_share")]] = 0.0
    return values * (1.01 if case.value("numerics", "preset") == "accurate" else 1.0)


class ClosedForm(Executor):
    """A serial executor that answers every task from :func:`closed_form` and records how
    many designs each task held."""

    def __init__(self):
        super().__init__(serial=True)
        self.sizes: list[int] = []

    def map(self, fn, tasks, on_result, on_idle=None):
        if fn is not runs._run_designs:  # NSGA-II repeats on the surfaces
            return super().map(fn, tasks, on_result)
        for i, (case, _, x, outputs, _) in enumerate(tasks):
            self.sizes.append(len(x))
            on_result(i, (closed_form(case, x, outputs), np.ones(len(x), bool), [""] * len(x)))


def test_every_stage_runs_its_designs_in_tasks_of_batch_designs(tmp_path):
    """The deck's batch is the designs per parallel task for every true-model run of a study
    (samples, the candidates and the reference checked, the chosen designs at the other
    points, how sure), so that a study's checks spread over the workers; the results of each
    design come back on its own row."""
    deck = write_study(tmp_path, name="batched", cases=("cold", "hot"), constraints="'max_friction <= 100'")
    ex = ClosedForm()
    study = run_study(deck, tmp_path / "out", executor=ex, progress=False, figures=False)
    assert study.s.batch == 4 and max(ex.sizes) == 4  # 40 samples per case: tasks of 4
    assert sum(ex.sizes) > 2 * 40  # the checks ran too
    outputs = list(study.s.outputs)
    for label in ("cold", "hot"):
        c = study.cases[label]
        base = Case.from_namelist(study.s.cases[study.s.labels.index(label)])
        assert len(c.candidates.names) > 4  # more than one task's worth
        np.testing.assert_allclose(
            c.candidates.f_true, closed_form(base, c.candidates.x, outputs), rtol=1e-12
        )
        other = "hot" if label == "cold" else "cold"
        np.testing.assert_allclose(c.chosen.points[other], closed_form(base, c.chosen.x, outputs), rtol=1e-12)
        accurate = base.with_("numerics", preset="accurate")
        np.testing.assert_allclose(c.sure.accurate, closed_form(accurate, c.sure.x, outputs), rtol=1e-12)


@pytest.fixture()
def loopback_cluster(tmp_path):
    """A dask scheduler and two workers (no nanny) on 127.0.0.1, as separate processes."""
    sf = tmp_path / "scheduler.json"
    procs = [
        subprocess.Popen(
            [
                sys.executable,
                "-m",
                "distributed.cli.dask_scheduler",
                "--host",
                "127.0.0.1",
                "--port",
                "0",
                "--no-dashboard",
                "--scheduler-file",
                str(sf),
            ],
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
        )
    ]
    try:
        t0 = time.time()
        while not sf.exists():
            if time.time() - t0 > 60:
                pytest.fail("dask scheduler did not start")
            time.sleep(0.2)
        workers = []
        for _ in range(2):
            workers.append(
                subprocess.Popen(
                    [
                        sys.executable,
                        "-m",
                        "distributed.cli.dask_worker",
                        "--scheduler-file",
                        str(sf),
                        "--nthreads",
                        "1",
                        "--no-nanny",
                        "--no-dashboard",
                        "--host",
                        "127.0.0.1",
                    ],
                    stdout=subprocess.DEVNULL,
                    stderr=subprocess.DEVNULL,
                )
            )
        procs += workers
        from dask.distributed import Client

        with Client(scheduler_file=str(sf), timeout=60) as c:
            c.wait_for_workers(2, timeout=60)
            address = c.scheduler.address
        yield address, workers
    finally:
        for p in procs:
            if p.poll() is None:
                p.terminate()
        for p in procs:
            try:
                p.wait(timeout=20)
            except subprocess.TimeoutExpired:
                p.kill()


@pytest.mark.slow
def test_dask_cluster_matches_serial_and_survives_a_killed_worker(tmp_path, loopback_cluster):
    address, workers = loopback_cluster
    s = read_study(write_study(tmp_path, name="dask", samples=64))
    serial = Study(s, tmp_path / "serial.h5")
    serial.x = sample(s)
    run_samples(serial, Executor(serial=True), progress=False)

    on_cluster = Study(s, tmp_path / "cluster.h5")
    on_cluster.x = sample(s)
    ex = Executor(scheduler=address)
    killed = []
    original = ex.map

    def map_and_kill(fn, tasks, on_result, on_idle=None):
        def wrapped(i, value):
            on_result(i, value)
            if not killed:  # after the first finished batch, kill a worker outright
                workers[0].send_signal(signal.SIGKILL)
                killed.append(True)

        return original(fn, tasks, wrapped, on_idle)

    ex.map = map_and_kill
    try:
        run_samples(on_cluster, ex, progress=False)
    finally:
        ex.close()
    assert killed and workers[0].wait(timeout=10) == -signal.SIGKILL
    assert on_cluster.cases["cold"].runs.done.all()
    np.testing.assert_array_equal(on_cluster.objectives("cold"), serial.objectives("cold"))


def test_bad_study_deck_names_the_variable(tmp_path):
    from ringlube import InputError

    with pytest.raises(InputError, match=r"&study name: .../escape. must be a plain name"):
        read_study(_with_name(tmp_path, "../escape"))
    with pytest.raises(InputError, match=r"&study samples: need at least 20"):
        read_study(write_study(tmp_path, name="few", samples=10))
    with pytest.raises(InputError, match=r"&study bogus: unknown variable"):
        read_study(write_study(tmp_path, name="bogus", samples=40, bogus=1))


def _with_name(tmp_path, name: str) -> str:
    path = write_study(tmp_path, name="named", samples=40)
    text = open(path).read().replace("name = 'named'", f"name = '{name}'")
    open(path, "w").write(text)
    return path
