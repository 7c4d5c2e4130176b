"""A study's designs run on the true model: the sample of the design box, the one batch call
of every study (:func:`_run_designs`), the samples run on every case, the weighted scene."""

from __future__ import annotations

import dataclasses
import time

import numpy as np

from ..case import Case
from ..executor import Executor
from .settings import StudySettings
from .state import CaseState, Runs
from .store import Study

__all__ = ["sample", "run_samples", "run_in_batches", "case_key", "scene_results"]


def _run_designs(
    base_case: Case,
    variables: list[tuple[str, str]],
    x: np.ndarray,
    outputs: list[str],
    kernel: str | None = None,
) -> tuple[np.ndarray, np.ndarray, list[str]]:
    """Run designs ``x`` (rows) of ``base_case``: the one batch call of every study.

    Parameters
    ----------
    base_case : Case
        The base deck.
    variables : list of (group, name)
        What the columns of ``x`` set.
    x : ndarray, shape (k, d)
        Designs.
    outputs : list of str
        Scalar results to return (attributes of :class:`~ringlube.CycleResult`).
    kernel : str, optional
        The study's kernel id (:func:`ringlube.kernel_id` where the study runs): a worker with
        another kernel build refuses the batch, so a study never mixes runs of two models.

    Returns
    -------
    values : ndarray, shape (k, len(outputs))
        NaN for a failed design.
    converged : ndarray of bool, shape (k,)
    errors : list of str
        The kernel's message for each failed design, "" for the others.

    Raises
    ------
    RinglubeError
        This process's kernel is not ``kernel``.

    Example
    -------
    >>> v, ok, err = _run_designs(case, [("ring", "width")], np.array([[1e-3]]),
    ...                           ["energy_loss"])                   # doctest: +SKIP
    """
    from .._version import kernel_id
    from ..errors import RinglubeError
    from ..solve import run_designs

    if kernel is not None and kernel != kernel_id():
        import socket

        raise RinglubeError(
            f"a worker on {socket.gethostname()} runs another ringlube kernel ({kernel_id()}) than "
            f"this study ({kernel}): install the same build on every worker "
            "(`ringlube-solve --version` prints it)"
        )

    values, converged, errs = run_designs(
        base_case, [f"{g}:{n}" for g, n in variables], np.atleast_2d(np.asarray(x, float)), list(outputs)
    )
    errors = [(e.splitlines()[0] if e else "") if e is not None else "" for e in errs]
    return values, converged, errors


def study_kernel() -> str:
    """The kernel id the study's batches must run on: this process's (:func:`ringlube.kernel_id`).

    Example
    -------
    >>> len(study_kernel())
    12
    """
    from .._version import kernel_id

    return kernel_id()


def sample(s: StudySettings) -> np.ndarray:
    """Sobol or Latin hypercube sample of the design box (scipy.stats.qmc).

    Parameters
    ----------
    s : StudySettings
        ``sampler``, ``samples``, ``seed``, ``lower``, ``upper``.

    Returns
    -------
    ndarray, shape (samples, len(variables))

    Example
    -------
    >>> x = sample(read_study("inputs/study_default.nml"))   # doctest: +SKIP
    >>> x.shape                                               # doctest: +SKIP
    (1025, 4)
    """
    from scipy.stats import qmc

    d = len(s.variables)
    if s.sampler == "sobol":
        eng = qmc.Sobol(d=d, scramble=True, seed=s.seed)
        m = int(np.ceil(np.log2(s.samples)))
        u = eng.random_base2(m)[: s.samples]
    else:
        u = qmc.LatinHypercube(d=d, seed=s.seed).random(s.samples)
    return qmc.scale(u, s.lower, s.upper)


def _chunks(n: int, batch: int) -> list[np.ndarray]:
    """Row indices ``0..n-1`` split into tasks of at most ``batch`` designs (none for ``n = 0``)."""
    return [c for c in np.array_split(np.arange(n), max(1, int(np.ceil(n / batch)))) if len(c)]


def case_key(case: Case) -> str:
    """The key of the deck a design runs on in the later stages (:func:`run_in_batches`): its
    name and the SHA-256 of its text as run (every value set, the variant's change and preset
    included; the contents of the files it names are in the study's key).

    Parameters
    ----------
    case : Case

    Returns
    -------
    str

    Example
    -------
    >>> case_key(Case({"ring": {"width": 1e-3}}))[:5]
    'case '
    """
    import hashlib

    return f"{case.name} {hashlib.sha256(case.to_namelist().encode('utf-8', 'surrogateescape')).hexdigest()}"


def run_in_batches(
    study: Study, ex: Executor, jobs: list[tuple[object, Case, np.ndarray]]
) -> dict[object, tuple[np.ndarray, np.ndarray, list[str]]]:
    """Run the designs of several jobs (a key, a base case, designs as rows) on the true
    model, in parallel tasks of at most the deck's ``batch`` designs of one deck (as the
    samples are), and put each job's results back together in the order of its rows.

    A design asked for on the same deck (:func:`case_key`) by several jobs runs once; a run
    already in :attr:`Study.check_runs <ringlube.study.store.Study.check_runs>` (the same
    deck as run and the same design) is reused, not run again; each finished run is added
    there and the study file saved as for the samples' runs (at most every 2 s while runs
    finish, and when interrupted).

    Parameters
    ----------
    study : Study
    ex : Executor
    jobs : list of (key, Case, ndarray)
        Keys are the caller's (distinct, hashable).

    Returns
    -------
    dict
        Per key: ``(values, converged, errors)`` as :func:`_run_designs` returns them for
        all the job's rows.

    Example
    -------
    >>> out = run_in_batches(study, Executor(serial=True), [("a", case, x)])   # doctest: +SKIP
    >>> out["a"][0].shape == (len(x), len(study.s.outputs))                    # doctest: +SKIP
    True
    """
    s = study.s
    kernel = study_kernel()
    out: dict[object, tuple[np.ndarray, np.ndarray, list[str]]] = {}
    # each design to run once per deck, whichever jobs ask for it: (deck key, design) -> rows
    todo: dict[str, tuple[Case, dict[bytes, tuple[np.ndarray, list[tuple[object, int]]]]]] = {}
    for key, case, xs in jobs:
        xs = np.atleast_2d(np.asarray(xs, float))
        values, converged, errors = (
            np.full((len(xs), len(s.outputs)), np.nan),
            np.zeros(len(xs), bool),
            [""] * len(xs),
        )
        out[key] = (values, converged, errors)
        ck = case_key(case)
        for i, x in enumerate(xs):
            x = np.ascontiguousarray(x)
            done = study.check_runs.get((ck, x.tobytes()))
            if done is None:
                todo.setdefault(ck, (case, {}))[1].setdefault(x.tobytes(), (x, []))[1].append((key, i))
            else:
                values[i], converged[i], errors[i] = done[1], done[2], done[3]
    tasks, where = [], []
    for ck, (case, designs) in todo.items():
        rows = list(designs.values())
        for chunk in _chunks(len(rows), s.batch):
            xs = np.array([rows[j][0] for j in chunk])
            tasks.append((case, s.groups_names, xs, list(s.outputs), kernel))
            where.append((ck, [rows[j] for j in chunk]))

    def on_result(i, result):
        ck, rows = where[i]
        for j, (x, dest) in enumerate(rows):
            v, ok, e = np.array(result[0][j], float), bool(result[1][j]), result[2][j]
            study.check_runs[(ck, x.tobytes())] = (x, v, ok, e)
            for key, row in dest:
                values, converged, errors = out[key]
                values[row], converged[row], errors[row] = v, ok, e
        study.checks_executed += len(rows)
        study.save(force=False)

    if not tasks:
        return out
    try:
        ex.map(_run_designs, tasks, on_result, on_idle=study.save_pending)
    finally:
        study.save()
    return out


def _bases(s: StudySettings) -> list[Case]:
    return [Case.from_namelist(deck) for deck in s.cases]


def run_samples(study: Study, ex: Executor, progress: bool = True, stop_after: int | None = None) -> None:
    """Run every sample on every case; finished runs are kept across interruptions.

    Parameters
    ----------
    study : Study
        With ``x`` sampled.
    ex : Executor
        Where the batches run.
    progress : bool
        Show a progress bar.
    stop_after : int, optional
        Test hook: raise KeyboardInterrupt once this many runs finished in this process.

    Example
    -------
    >>> run_samples(study, Executor(serial=True), progress=False)   # doctest: +SKIP
    """
    from tqdm.auto import tqdm

    s = study.s
    for label in s.labels:
        if label not in study.cases:
            study.cases[label] = CaseState(Runs.empty(s.samples, len(s.outputs)))
    tasks, where = [], []
    for label, base in zip(s.labels, _bases(s)):
        todo = np.flatnonzero(~study.cases[label].runs.done)
        for rows in _chunks(len(todo), s.batch):
            chunk = todo[rows]
            tasks.append((base, s.groups_names, study.x[chunk], list(s.outputs), study_kernel()))
            where.append((label, chunk))
    total = sum(len(c) for _, c in where)
    if total == 0:
        return
    bar = tqdm(total=total, desc="true-model runs", unit="run", disable=not progress)
    t0 = time.perf_counter()

    def on_result(i, result):
        values, converged, errors = result
        label, chunk = where[i]
        r = study.cases[label].runs
        r.outputs[chunk] = values
        r.converged[chunk] = converged
        r.failed[chunk] = [bool(e) for e in errors]
        for j, e in zip(chunk, errors):
            r.errors[j] = e
        r.done[chunk] = True
        study.runs_executed += len(chunk)
        bar.update(len(chunk))
        study.save(force=False)
        if stop_after is not None and study.runs_executed >= stop_after:
            raise KeyboardInterrupt("stop_after reached (test hook)")

    try:
        ex.map(_run_designs, tasks, on_result, on_idle=study.save_pending)
    finally:
        bar.close()
        wall = time.perf_counter() - t0
        for label in s.labels:
            study.cases[label].runs.wall_s += wall / len(s.labels)
        study.save()


def scene_results(study: Study) -> None:
    """The weighted scene: every result averaged over the cases with their weights.

    Parameters
    ----------
    study : Study
        With every case run.

    Example
    -------
    >>> scene_results(study); study.cases["scene"].runs.outputs.shape   # doctest: +SKIP
    (1025, 5)
    """
    s = study.s
    w = s.scene_weights()
    runs = [study.cases[label].runs for label in s.labels]
    out = Runs(
        sum(wi * r.outputs for wi, r in zip(w, runs)),
        np.all([r.done for r in runs], axis=0),
        np.all([r.converged for r in runs], axis=0),
        np.any([r.failed for r in runs], axis=0),
        ["; ".join(e for e in errs if e) for errs in zip(*(r.errors for r in runs))],
    )
    old = study.cases.get("scene")
    study.cases["scene"] = (
        CaseState(out)
        if old is None
        # (the same settings: every derived record of the scene is kept, as for the cases)
        else dataclasses.replace(old, runs=out)
    )
