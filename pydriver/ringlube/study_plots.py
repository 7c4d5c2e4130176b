"""Figures of a design study: goodness of fit (study Fig 9), trade-off sets (Fig 10) and
two-variable maps of each objective (Figs 4 and 7)."""

from __future__ import annotations

import itertools
import json
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from .plot import save_metadata  # noqa: E402
from .study import (OBJECTIVES, STUDY_OPTIMUM, UNITS_LABEL, UNITS_SCALE, Study,  # noqa: E402
                    _objective_matrix, surfaces_of)

__all__ = ["study_figures"]


def _save(fig, out: Path, stem: str) -> list[Path]:
    files = []
    for fmt in ("png", "pdf"):
        p = out / f"{stem}.{fmt}"
        fig.savefig(p, dpi=130, metadata=save_metadata(fmt))
        files.append(p)
    plt.close(fig)
    return files


def fit_figure(study: Study, label: str) -> plt.Figure:
    s = study.s
    c = study.cases[label]
    x, y = _objective_matrix(study, label)
    surfs = surfaces_of(study, label)
    fig, axes = plt.subplots(1, len(s.objectives), figsize=(4.2 * len(s.objectives), 4), layout="constrained")
    for j, (ax, o) in enumerate(zip(np.atleast_1d(axes), s.objectives)):
        pred = surfs[j](x)
        ax.scatter(y[:, j], pred, s=4, alpha=0.5)
        lo, hi = min(y[:, j].min(), pred.min()), max(y[:, j].max(), pred.max())
        ax.plot([lo, hi], [lo, hi], "k-", lw=0.8)
        sf = c["surface"][o]
        ax.set_title(f"{o} ({label}): R$^2$ {sf['r2']:.4f}, adj {sf['r2_adj']:.4f}\n"
                     f"{study.s.folds}-fold CV error {sf['cv_rel']:.2%}", fontsize=9)
        ax.set_xlabel(f"simulated [{OBJECTIVES[o]}]")
        ax.set_ylabel(f"quadratic surface [{OBJECTIVES[o]}]")
    return fig


def tradeoff_figure(study: Study) -> plt.Figure:
    s = study.s
    if "ring_mass" not in s.objectives:
        raise ValueError("trade-off plot needs ring_mass")
    jm = s.objectives.index("ring_mass")
    others = [j for j in range(len(s.objectives)) if j != jm]
    fig, axes = plt.subplots(1, len(others), figsize=(5.5 * len(others), 4.4), layout="constrained")
    for ax, j in zip(np.atleast_1d(axes), others):
        for label in study.cases:
            fr = study.cases[label].get("front")
            if fr is None:
                continue
            f = np.asarray(fr["f"])
            sc = ax.scatter(f[:, jm], f[:, j], s=6, alpha=0.6, label=f"{label}: Pareto set")
            ch = study.cases[label].get("chosen")
            if ch is not None:
                ft = np.asarray(ch["f_true"])
                ax.scatter(ft[:, jm], ft[:, j], marker="x", color=sc.get_facecolor()[0], s=40,
                           label=f"{label}: chosen, re-simulated")
            so = study.cases[label].get("study_optimum")
            if so is not None:
                ft = np.asarray(so["f_true"])
                ax.scatter(ft[:, jm], ft[:, j], marker="*", s=140, edgecolor="k",
                           color=sc.get_facecolor()[0], label=f"{label}: study's optimum ring")
        ax.set_xlabel(f"ring mass [{OBJECTIVES['ring_mass']}]")
        ax.set_ylabel(f"{s.objectives[j]} [{OBJECTIVES[s.objectives[j]]}]")
        ax.legend(fontsize=7)
    return fig


def map_figure(study: Study, label: str, j: int) -> plt.Figure:
    s = study.s
    d = len(s.variables)
    pairs = list(itertools.combinations(range(d), 2))
    ncol = 3
    nrow = int(np.ceil(len(pairs) / ncol))
    fig, axes = plt.subplots(nrow, ncol, figsize=(4.2 * ncol, 3.6 * nrow), layout="constrained",
                             squeeze=False)
    surf = surfaces_of(study, label)[j]
    lo, hi = np.array(s.lower), np.array(s.upper)
    mid = 0.5 * (lo + hi)
    for ax, (a, b) in zip(axes.flat, pairs):
        ga, gb = np.meshgrid(np.linspace(lo[a], hi[a], 60), np.linspace(lo[b], hi[b], 60))
        x = np.tile(mid, (ga.size, 1))
        x[:, a] = ga.ravel()
        x[:, b] = gb.ravel()
        z = surf(x).reshape(ga.shape)
        sa, sb = UNITS_SCALE.get(s.variables[a], 1.0), UNITS_SCALE.get(s.variables[b], 1.0)
        cs = ax.contourf(ga * sa, gb * sb, z, levels=20, cmap="viridis")
        fig.colorbar(cs, ax=ax, label=f"{s.objectives[j]} [{OBJECTIVES[s.objectives[j]]}]")
        ax.set_xlabel(UNITS_LABEL.get(s.variables[a], s.variables[a]))
        ax.set_ylabel(UNITS_LABEL.get(s.variables[b], s.variables[b]))
    for ax in list(axes.flat)[len(pairs):]:
        ax.axis("off")
    fig.suptitle(f"{s.objectives[j]} ({label}), quadratic surface, other variables at mid-range",
                 fontsize=10)
    return fig


def study_figures(study: Study, out: Path) -> list[Path]:
    out = Path(out)
    files = []
    for label in study.cases:
        if "surface" not in study.cases[label]:
            continue
        files += _save(fit_figure(study, label), out, f"fit_{label}")
        for j, o in enumerate(study.s.objectives):
            files += _save(map_figure(study, label, j), out, f"map_{label}_{o}")
    if "ring_mass" in study.s.objectives:
        files += _save(tradeoff_figure(study), out, "tradeoff")
    return files
