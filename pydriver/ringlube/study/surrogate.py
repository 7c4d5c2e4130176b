"""Quadratic response surfaces fitted by LAPACK least squares (docs/optimisation.md).

:class:`QuadraticSurface` is both the callable surface and the record a study stores of it
(:meth:`QuadraticSurface.to_h5`, :meth:`QuadraticSurface.from_h5`).
"""

from __future__ import annotations

import dataclasses
import itertools

import h5py
import numpy as np
import scipy.linalg

from .h5 import put

__all__ = [
    "QuadraticSurface",
    "quadratic_features",
    "fit_quadratic",
    "cross_validate",
    "term_names",
    "n_terms",
]


def n_terms(d: int) -> int:
    """Number of terms of the full quadratic in ``d`` variables.

    Parameters
    ----------
    d : int
        Number of variables.

    Returns
    -------
    int
        ``1 + 2 d + d (d - 1) / 2``.

    Example
    -------
    >>> n_terms(4)
    15
    """
    return 1 + 2 * d + d * (d - 1) // 2


def quadratic_features(z: np.ndarray) -> np.ndarray:
    """Columns 1, z_i, z_i^2, z_i z_j (i < j) of the full second-order polynomial.

    Parameters
    ----------
    z : ndarray, shape (n, d)
        Scaled variables.

    Returns
    -------
    ndarray, shape (n, n_terms(d))

    Example
    -------
    >>> quadratic_features(np.array([[2.0, 3.0]])).tolist()
    [[1.0, 2.0, 3.0, 4.0, 9.0, 6.0]]
    """
    z = np.atleast_2d(z)
    n, d = z.shape
    cols = [np.ones(n)]
    cols += [z[:, i] for i in range(d)]
    cols += [z[:, i] ** 2 for i in range(d)]
    cols += [z[:, i] * z[:, j] for i, j in itertools.combinations(range(d), 2)]
    return np.column_stack(cols)


def term_names(variables: list[str]) -> list[str]:
    """Names of the columns of :func:`quadratic_features`.

    Parameters
    ----------
    variables : list of str

    Returns
    -------
    list of str

    Example
    -------
    >>> term_names(["a", "b"])
    ['1', 'a', 'b', 'a^2', 'b^2', 'a*b']
    """
    d = len(variables)
    return (
        ["1"]
        + list(variables)
        + [f"{v}^2" for v in variables]
        + [f"{variables[i]}*{variables[j]}" for i, j in itertools.combinations(range(d), 2)]
    )


@dataclasses.dataclass
class QuadraticSurface:
    """y ~ c . features(z), z the variables scaled to [-1, 1] over [lower, upper].

    Parameters
    ----------
    lower, upper : ndarray
        The box the variables are scaled over.
    coef : ndarray
        Coefficients of :func:`quadratic_features`.
    r2, r2_adj, cv_rmse, cv_rel : float
        Goodness of fit; k-fold cross-validated RMSE (the result's unit) and relative to the
        mean |y| (NaN until :func:`cross_validate` is run by the study).
    n : int
        Samples fitted.

    Example
    -------
    >>> s = QuadraticSurface(np.zeros(1), np.ones(1), np.array([1.0, 2.0, 0.0]))
    >>> s(np.array([[1.0]])).tolist()
    [3.0]
    """

    lower: np.ndarray
    upper: np.ndarray
    coef: np.ndarray
    r2: float = np.nan
    r2_adj: float = np.nan
    cv_rmse: float = np.nan
    cv_rel: float = np.nan
    n: int = 0

    def scale(self, x: np.ndarray) -> np.ndarray:
        """Variables scaled to [-1, 1] over the box.

        Parameters
        ----------
        x : ndarray, shape (n, d)

        Returns
        -------
        ndarray

        Example
        -------
        >>> QuadraticSurface(np.zeros(1), np.ones(1), np.zeros(3)).scale([0.5]).tolist()
        [0.0]
        """
        return 2 * (np.asarray(x) - self.lower) / (self.upper - self.lower) - 1

    def __call__(self, x: np.ndarray) -> np.ndarray:
        """The surface at designs ``x`` (rows)."""
        return quadratic_features(self.scale(x)) @ self.coef

    def to_h5(self, group: h5py.Group, variables: list[str], unit: str) -> None:
        """Write the fit into ``group``: ``coef`` (columns: :func:`term_names`) and attributes.

        The box is not written: it is the study's (:meth:`from_h5` takes it back).

        Parameters
        ----------
        group : h5py.Group
            An empty group (``/cases/LABEL/surface/RESULT``).
        variables : list of str
            The design variables (the names of the terms).
        unit : str
            Unit of the fitted result.

        Example
        -------
        >>> s = QuadraticSurface(np.zeros(1), np.ones(1), np.array([1.0, 2.0, 0.0]), n=5)
        >>> with h5py.File("x.h5", "w", driver="core", backing_store=False) as f:
        ...     s.to_h5(f.create_group("surface/energy_loss"), ["width"], "J")
        ...     QuadraticSurface.from_h5(f["surface/energy_loss"], [0.0], [1.0])(np.ones((1, 1)))
        array([3.])
        """
        put(group, "coef", self.coef, term_names(variables))
        for k in ("r2", "r2_adj", "cv_rmse", "cv_rel", "n"):
            group.attrs[k] = getattr(self, k)
        group.attrs["unit"] = unit

    @classmethod
    def from_h5(cls, group: h5py.Group, lower, upper) -> QuadraticSurface:
        """The surface :meth:`to_h5` wrote, over the box ``[lower, upper]``.

        Parameters
        ----------
        group : h5py.Group
        lower, upper : array_like
            The study's design box.

        Returns
        -------
        QuadraticSurface

        Example
        -------
        >>> QuadraticSurface.from_h5(f["cases/cold/surface/energy_loss"], s.lower, s.upper)  # doctest: +SKIP
        """
        return cls(
            np.asarray(lower, float),
            np.asarray(upper, float),
            group["coef"][()],
            *(float(group.attrs[k]) for k in ("r2", "r2_adj", "cv_rmse", "cv_rel")),
            int(group.attrs["n"]),
        )


def fit_quadratic(x: np.ndarray, y: np.ndarray, lower, upper) -> QuadraticSurface:
    """Least-squares fit through LAPACK (gelsd) with R^2 and adjusted R^2.

    Parameters
    ----------
    x : ndarray, shape (n, d)
        Designs.
    y : ndarray, shape (n,)
        Values.
    lower, upper : array_like
        The box the variables are scaled over.

    Returns
    -------
    QuadraticSurface

    Example
    -------
    >>> x = np.linspace(0, 1, 5)[:, None]
    >>> round(float(fit_quadratic(x, 3 * x[:, 0] ** 2, [0], [1])(np.array([[0.5]]))[0]), 12)
    0.75
    """
    lower, upper = np.asarray(lower, float), np.asarray(upper, float)
    surf = QuadraticSurface(lower, upper, np.zeros(0))
    a = quadratic_features(surf.scale(x))
    coef, *_ = scipy.linalg.lstsq(a, y, lapack_driver="gelsd")
    surf.coef = coef
    resid = y - a @ coef
    ss_res = float(resid @ resid)
    ss_tot = float(((y - y.mean()) ** 2).sum())
    n, p = a.shape
    surf.n = n
    surf.r2 = 1 - ss_res / ss_tot if ss_tot > 0 else 1.0
    surf.r2_adj = 1 - (1 - surf.r2) * (n - 1) / (n - p) if n > p else np.nan
    return surf


def cross_validate(
    x: np.ndarray, y: np.ndarray, lower, upper, k: int = 5, seed: int = 0
) -> tuple[float, float]:
    """k-fold cross-validated RMSE and RMSE relative to the mean |y|.

    Parameters
    ----------
    x, y : ndarray
        Designs and values.
    lower, upper : array_like
        The box.
    k : int
        Folds.
    seed : int
        Seed of the fold split.

    Returns
    -------
    rmse, relative : float
        ``relative`` is 0 for an exact fit of all-zero data.

    Example
    -------
    >>> x = np.linspace(0, 1, 12)[:, None]
    >>> cross_validate(x, 1 + x[:, 0], [0], [1], k=3)[0] < 1e-12
    True
    """
    n = len(y)
    idx = np.random.default_rng(seed).permutation(n)
    folds = np.array_split(idx, k)
    err = np.empty(n)
    for f in folds:
        train = np.setdiff1d(idx, f)
        s = fit_quadratic(x[train], y[train], lower, upper)
        err[f] = s(x[f]) - y[f]
    rmse = float(np.sqrt(np.mean(err**2)))
    scale = float(np.mean(np.abs(y)))
    return rmse, (rmse / scale if scale > 0 else (0.0 if rmse == 0 else np.inf))
