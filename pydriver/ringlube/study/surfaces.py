"""The quadratic surfaces of a study: fitted to the runs of every case, and evaluated."""

from __future__ import annotations

import numpy as np

from ..errors import RinglubeError
from .store import Study

__all__ = ["fit_surfaces", "surfaces_of", "predict"]


def fit_surfaces(study: Study) -> None:
    """Fit a quadratic surface of every result on every case (and the scene).

    Only samples that ran, converged and did not fail are fitted.

    Parameters
    ----------
    study : Study

    Raises
    ------
    RinglubeError
        Too few usable samples on a case for a quadratic.

    Example
    -------
    >>> fit_surfaces(study); study.cases["cold"].surfaces["energy_loss"].r2  # doctest: +SKIP
    """
    from .surrogate import cross_validate, fit_quadratic, n_terms

    s = study.s
    for label, c in study.cases.items():
        ok = c.runs.usable()
        if ok.sum() < n_terms(len(s.variables)) + s.folds:
            raise RinglubeError(
                f"case '{label}': only {int(ok.sum())} of {s.samples} samples "
                "ran, converged and did not fail: too few for a quadratic "
                "surface (see the errors in the study file)"
            )
        x = study.x[ok]
        for j, o in enumerate(s.outputs):
            y = c.runs.outputs[ok, j]
            surf = fit_quadratic(x, y, s.lower, s.upper)
            surf.cv_rmse, surf.cv_rel = cross_validate(x, y, s.lower, s.upper, k=s.folds, seed=s.seed)
            c.surfaces[o] = surf


def surfaces_of(study: Study, label: str, names: list[str] | None = None) -> list:
    """The fitted surfaces of a case as callables.

    Parameters
    ----------
    study : Study
    label : str
        Case label or ``scene``.
    names : list of str, optional
        Results (default: the objectives).

    Returns
    -------
    list of QuadraticSurface

    Example
    -------
    >>> energy, = surfaces_of(study, "cold", ["energy_loss"])   # doctest: +SKIP
    >>> energy(study.x[:3])                                    # doctest: +SKIP
    """
    c = study.cases[label]
    return [c.surfaces[o] for o in (names or study.s.objectives)]


def predict(study: Study, label: str, x: np.ndarray) -> np.ndarray:
    """Every recorded result at the designs ``x`` as the case's surfaces predict it.

    Parameters
    ----------
    study : Study
    label : str
        Case label or ``scene``.
    x : ndarray, shape (k, d)
        Designs.

    Returns
    -------
    ndarray, shape (k, len(outputs))

    Example
    -------
    >>> predict(study, "cold", study.x[:3]).shape              # doctest: +SKIP
    (3, 5)
    """
    return np.column_stack([f(x) for f in surfaces_of(study, label, list(study.s.outputs))])
