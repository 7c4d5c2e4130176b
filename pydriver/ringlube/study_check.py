"""The chosen designs (and the reference design) of a study re-simulated with the true model."""

from __future__ import annotations

import numpy as np

from . import study_runs
from .executor import Executor
from .study_optimise import choose_designs
from .study_runs import _bases
from .study_state_checks import Checked
from .study_store import Study
from .study_surfaces import predict

__all__ = ["check_designs"]


def check_designs(study: Study, ex: Executor, which: tuple[str, ...] = ("chosen", "reference")) -> None:
    """Re-simulate the chosen designs (and the reference design) with the true model.

    For the scene, each design runs on every base deck and the results are weighted.

    Parameters
    ----------
    study : Study
        With fronts (with surfaces only for ``which=("reference",)``).
    ex : Executor
    which : tuple of str
        ``chosen`` and/or ``reference``.

    Example
    -------
    >>> check_designs(study, Executor(serial=True))            # doctest: +SKIP
    """
    s = study.s
    bases = dict(zip(s.labels, _bases(s)))
    ref = None if s.reference is None else np.array([s.reference])
    if ref is None:
        for c in study.cases.values():
            c.reference = None
    jobs = []  # (label, key, names, xs)
    if "chosen" in which:
        for label, (names, xs) in choose_designs(study).items():
            jobs.append((label, "chosen", names, xs))
    if ref is not None and "reference" in which:
        for label in study.cases:
            jobs.append((label, "reference", ["reference"], ref))
    tasks, where = [], []
    for j, (label, _, _, xs) in enumerate(jobs):
        for base_label in [label] if label in bases else s.labels:
            tasks.append((bases[base_label], s.groups_names, xs, list(s.outputs), study_runs.study_kernel()))
            where.append((j, base_label))
    results: dict[tuple[int, str], tuple] = {}
    ex.map(study_runs._run_designs, tasks, lambda i, res: results.__setitem__(where[i], res))
    w = dict(zip(s.labels, np.array(s.weights) / sum(s.weights)))
    for j, (label, key, names, xs) in enumerate(jobs):
        parts = [(bl, results[(j, bl)]) for bl in ([label] if label in bases else s.labels)]
        if len(parts) == 1:
            values, conv, errors = parts[0][1]
        else:
            values = sum(w[bl] * r[0] for bl, r in parts)
            conv = np.all([r[1] for _, r in parts], axis=0)
            errors = [
                "; ".join(f"{bl}: {e}" for bl, e in zip((b for b, _ in parts), errs) if e)
                for errs in zip(*(r[2] for _, r in parts))
            ]
        setattr(
            study.cases[label],
            key,
            Checked(
                list(names),
                np.asarray(xs),
                np.asarray(values),
                predict(study, label, np.asarray(xs)),
                np.asarray(conv, bool),
                list(errors),
            ),
        )
