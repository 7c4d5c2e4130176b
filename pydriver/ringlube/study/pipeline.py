"""Design optimisation: sample -> run -> fit -> NSGA-II -> check.

The pipeline of ``ringlube optimise`` (:func:`run_study`). Its stages live in their own
modules: :mod:`ringlube.study.runs` (sample, run), :mod:`ringlube.study.surfaces` (fit),
:mod:`ringlube.study.optimise` (NSGA-II on the surfaces, chosen designs),
:mod:`ringlube.study.check` (the chosen designs re-simulated), :mod:`ringlube.study.sure`
(how sure the answer is), :mod:`ringlube.study.direct` (NSGA-II on the true model); and
what they use: :mod:`ringlube.study.deck` (the ``&study`` deck), :mod:`ringlube.study.settings`,
:mod:`ringlube.study.variables`, :mod:`ringlube.study.constraints`,
:mod:`ringlube.study.state` (typed state), :mod:`ringlube.study.store` and
:mod:`ringlube.study.layout` (the HDF5 study file), :mod:`ringlube.executor` (serial,
processes or Dask), :mod:`ringlube.study.surrogate` (quadratic surfaces),
:mod:`ringlube.study.plots` (figures from plain arrays), and :mod:`ringlube.study.summary`,
:mod:`ringlube.study.report`, :mod:`ringlube.study.pareto` and :mod:`ringlube.study.figures`
(summary, report.md, Pareto CSV, figures).

Every finished piece of work is checkpointed, so an interrupted study started again with
the same command resumes and re-runs nothing that finished. A design the kernel rejects
(an invalid combination inside the box) is recorded as failed with its message and the
study goes on.
"""

from __future__ import annotations

import os
from collections.abc import Callable
from pathlib import Path

import numpy as np

from ..errors import InputError
from ..executor import Executor, require
from ..outputs import check_output
from .check import check_designs, dominating_samples
from .deck import read_study
from .direct import direct
from .optimise import optimise
from .runs import run_samples, sample, scene_results
from .settings import StudySettings
from .store import Study
from .sure import how_sure
from .surfaces import fit_surfaces

__all__ = ["run_study"]


def _out_folder(out: str | os.PathLike | None, s: StudySettings) -> Path:
    out = Path(out) if out is not None else Path("out") / s.name
    if out.exists() and not out.is_dir():
        raise InputError(f"--out {out}: exists and is not a folder")
    if out.is_dir():
        other = _other_study(out, s.name)
        if other:
            raise InputError(
                f"--out {out}: holds the outputs of the study '{other}' (report.md, pareto_*.csv, "
                f"figures), which study '{s.name}' would replace; give each study its own --out folder"
            )
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise InputError(f"--out {out}: cannot create the folder ({exc.strerror or exc})") from None
    return out


def _other_study(out: Path, name: str) -> str | None:
    """The name of another study whose outputs are in ``out`` (its study file, or the title of
    its report), else None."""
    import h5py

    from .h5 import text
    from .layout import FORMAT

    for p in sorted(out.glob("*.h5")):
        if p.stem == name or not p.is_file() or not h5py.is_hdf5(p):
            continue
        try:
            with h5py.File(p, "r") as f:
                if text(f.attrs.get("format", "")) == FORMAT:
                    return p.stem
        except OSError:
            continue
    report = out / "report.md"
    if report.is_file():
        with open(report, encoding="utf-8", errors="replace") as fh:
            first = fh.readline()
        title = "# Design study `"
        if first.startswith(title) and first.rstrip().endswith("`"):
            found = first.rstrip()[len(title) : -1]
            if found != name:
                return found
    return None


def run_study(
    deck: str | os.PathLike,
    out: str | os.PathLike | None = None,
    *,
    executor: Executor | Callable[[], Executor] | None = None,
    with_direct: bool = False,
    figures: bool = True,
    progress: bool = True,
    restart: bool = False,
    stop_after: int | None = None,
) -> Study:
    """The whole pipeline; resumes from the study file in ``out`` if there is one.

    Parameters
    ----------
    deck : path
        The study deck (``&study``).
    out : path, optional
        Output folder (default ``out/NAME``); the study file is ``OUT/NAME.h5``.
    executor : Executor or callable, optional
        Where the runs go. An :class:`~ringlube.executor.Executor` is used as it is and left
        open (it is the caller's); a function of no arguments that returns one (e.g.
        ``functools.partial(Executor, workers=4)``) is called once the deck and the study
        file are checked, and what it returns is closed at the end. Default: ``Executor()``
        (a local Dask cluster), made and closed the same way.
    with_direct : bool
        Also NSGA-II on the true model, compared with the surrogate front.
    figures : bool
        Write the figures (the report and CSV files are always written).
    progress : bool
        Progress bars.
    stop_after : int, optional
        Test hook (see :func:`run_samples`).
    restart : bool
        Start afresh: a study file already in ``out`` is removed (under the study's lock)
        and none of its runs used.

    Returns
    -------
    Study

    Raises
    ------
    InputError
        Bad study deck, base deck, output folder or study file.
    RinglubeError
        Another process works on the same study, the scheduler is unreachable, too few
        usable samples.

    Example
    -------
    >>> study = run_study("inputs/study_default.nml", executor=Executor(serial=True))   # doctest: +SKIP
    """
    from .report import output_names, study_inputs

    s = read_study(deck)
    out = _out_folder(out, s)
    for name in [f"{s.name}.h5", *output_names(s)]:  # before the work, not after it
        check_output(out / name, study_inputs(s), "--out")
    path = out / f"{s.name}.h5"
    study = Study.open(s, path, lock=True, restart=restart)
    try:
        _pipeline(study, executor, with_direct=with_direct, progress=progress, stop_after=stop_after)
        from .report import write_outputs

        write_outputs(study, out, figures=figures)
    finally:
        study.unlock()
    return study


def _pipeline(
    study: Study, executor: Executor | Callable[[], Executor] | None, *, with_direct, progress, stop_after
) -> None:
    s = study.s
    if study.x is None:
        study.x = sample(s)
        study.stages.add("sampled")
        study.save()
    require("pymoo", "ringlube optimise")  # before any run, not hours later
    ours = not isinstance(executor, Executor)  # made here: closed here
    ex = executor if not ours else (executor or Executor)()
    try:
        run_samples(study, ex, progress=progress, stop_after=stop_after)
        study.stages.add("ran")
        if s.scene and len(s.labels) > 1:
            scene_results(study)
        if "fitted" not in study.stages or any(not c.surfaces for c in study.cases.values()):
            fit_surfaces(study)
            study.stages.add("fitted")
            study.save()
        if _reference_stale(study):  # before the GA: a constraint may be bounded by it
            check_designs(study, ex, which=("reference",))
            for c in study.cases.values():
                c.sure = None
            study.save()
        optimise(study, ex, progress=progress)
        study.stages.add("optimised")
        if "checked" not in study.stages or any(
            c.chosen is None or c.candidates is None for c in study.cases.values()
        ):
            check_designs(study, ex, which=("chosen",))
            for c in study.cases.values():
                c.sure = None
            study.stages.add("checked")
            study.save()
        if any(c.chosen is not None and c.dominating is None for c in study.cases.values()):
            for label, c in study.cases.items():  # a file written before the comparison was stored
                if c.chosen is not None and c.dominating is None:
                    c.dominating = dominating_samples(study, label)
            study.save()
        if any(c.sure is None for c in study.cases.values()):
            how_sure(study, ex)
            study.stages.add("sure")
            study.save()
        if with_direct:
            direct(study, ex, progress=progress)
            study.stages.add("direct")
            study.save()
    finally:
        if ours:
            ex.close()


def _reference_stale(study: Study) -> bool:
    """Is a stored reference check missing or for another reference than the deck's now?"""
    ref = study.s.reference
    for c in study.cases.values():
        if ref is not None and c.reference is None:
            return True
        have = None if c.reference is None else np.asarray(c.reference.x)[0].tolist()
        if have != (None if ref is None else list(ref)):
            return True
    return False
