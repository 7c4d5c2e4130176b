"""Quadratic response surfaces fitted by LAPACK least squares (SPEC section 12, step 2)."""

from __future__ import annotations

import dataclasses
import itertools

import numpy as np
import scipy.linalg

__all__ = ["QuadraticSurface", "quadratic_features", "fit_quadratic", "cross_validate"]


def quadratic_features(z: np.ndarray) -> np.ndarray:
    """Columns 1, z_i, z_i^2, z_i z_j (i < j) of the full second-order polynomial."""
    z = np.atleast_2d(z)
    n, d = z.shape
    cols = [np.ones(n)]
    cols += [z[:, i] for i in range(d)]
    cols += [z[:, i] ** 2 for i in range(d)]
    cols += [z[:, i] * z[:, j] for i, j in itertools.combinations(range(d), 2)]
    return np.column_stack(cols)


def term_names(variables: list[str]) -> list[str]:
    d = len(variables)
    return (["1"] + list(variables) + [f"{v}^2" for v in variables]
            + [f"{variables[i]}*{variables[j]}" for i, j in itertools.combinations(range(d), 2)])


@dataclasses.dataclass
class QuadraticSurface:
    """y ~ c . features(z), z the variables scaled to [-1, 1] over [lower, upper]."""

    lower: np.ndarray
    upper: np.ndarray
    coef: np.ndarray
    r2: float = np.nan
    r2_adj: float = np.nan
    cv_rmse: float = np.nan
    cv_rel: float = np.nan

    def scale(self, x: np.ndarray) -> np.ndarray:
        return 2 * (np.asarray(x) - self.lower) / (self.upper - self.lower) - 1

    def __call__(self, x: np.ndarray) -> np.ndarray:
        return quadratic_features(self.scale(x)) @ self.coef


def fit_quadratic(x: np.ndarray, y: np.ndarray, lower, upper) -> QuadraticSurface:
    """Least-squares fit through LAPACK (gelsd) with R^2 and adjusted R^2."""
    lower, upper = np.asarray(lower, float), np.asarray(upper, float)
    surf = QuadraticSurface(lower, upper, np.zeros(0))
    a = quadratic_features(surf.scale(x))
    coef, *_ = scipy.linalg.lstsq(a, y, lapack_driver="gelsd")
    surf.coef = coef
    resid = y - a @ coef
    ss_res = float(resid @ resid)
    ss_tot = float(((y - y.mean()) ** 2).sum())
    n, p = a.shape
    surf.r2 = 1 - ss_res / ss_tot if ss_tot > 0 else 1.0
    surf.r2_adj = 1 - (1 - surf.r2) * (n - 1) / (n - p) if n > p else np.nan
    return surf


def cross_validate(x: np.ndarray, y: np.ndarray, lower, upper, k: int = 5,
                   seed: int = 0) -> tuple[float, float]:
    """k-fold cross-validated RMSE and RMSE relative to the mean |y|."""
    n = len(y)
    idx = np.random.default_rng(seed).permutation(n)
    folds = np.array_split(idx, k)
    err = np.empty(n)
    for f in folds:
        train = np.setdiff1d(idx, f)
        s = fit_quadratic(x[train], y[train], lower, upper)
        err[f] = s(x[f]) - y[f]
    rmse = float(np.sqrt(np.mean(err**2)))
    return rmse, rmse / float(np.mean(np.abs(y)))
