"""The Pareto sets of a design study as CSV files, with every result as the surfaces predict it."""

from __future__ import annotations

import csv
import os
from pathlib import Path

import numpy as np

from ..outputs import atomic_path
from .format import LIFTED_COLUMN
from .store import Study
from .surfaces import predict
from .variables import output_units

__all__ = ["write_pareto_csv"]


def write_pareto_csv(study: Study, out: str | os.PathLike) -> list[Path]:
    """Write each case's Pareto set as ``OUT/pareto_LABEL.csv``.

    Columns: the variables (SI), then every result as the surfaces predict it; the header
    gives each column's unit, e.g. ``width [m]``, ``energy_loss [J]``. The last column,
    :data:`LIFTED_COLUMN`, is ``yes`` where the surfaces predict the ring to lift off the
    liner (``liner_lift_share`` above its surface's cross-validation error), else ``no``.

    Parameters
    ----------
    study : Study
    out : path

    Returns
    -------
    list of Path

    Example
    -------
    >>> write_pareto_csv(study, "out/s")                     # doctest: +SKIP
    """
    s, units = study.s, output_units()
    files = []
    for label, c in study.cases.items():
        if c.front is None:
            continue
        pred = predict(study, label, c.front.x)
        for j, o in enumerate(s.objectives):  # the GA's own values of its objectives
            pred[:, study.s.outputs.index(o)] = c.front.f[:, j]
        path = Path(out) / f"pareto_{label}.csv"
        with atomic_path(path, [study.path]) as tmp, open(tmp, "w", newline="") as fh:
            w = csv.writer(fh)
            w.writerow(
                [f"{v} [{u}]" if u else v for v, u in zip(s.variables, s.units)]
                + [f"{o} [{units[o]}] (surrogate)" for o in study.s.outputs]
                + [LIFTED_COLUMN]
            )
            lifted = _predicted_lift(study, label, pred)
            for x, y, up in zip(c.front.x, pred, lifted):
                w.writerow([repr(float(v)) for v in (*x, *y)] + ["yes" if up else "no"])
        files.append(path)
    return files


def _predicted_lift(study: Study, label: str, pred: np.ndarray) -> np.ndarray:
    """Designs whose predicted ``liner_lift_share`` exceeds its surface's CV error (a
    quadratic surface of a share that is mostly 0 is not exactly 0 anywhere)."""
    outputs = list(study.s.outputs)
    if "liner_lift_share" not in outputs:
        return np.zeros(len(pred), bool)
    sf = study.cases[label].surfaces.get("liner_lift_share")
    noise = float(sf.cv_rmse) if sf is not None and np.isfinite(sf.cv_rmse) else 0.0
    return pred[:, outputs.index("liner_lift_share")] > max(noise, 0.0)
