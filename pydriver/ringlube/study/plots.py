"""Figures of a design study, drawn from plain arrays (no study object needed).

- :func:`fit_figure`: surface against simulation per objective (study Fig 9);
- :func:`tradeoff_figure`: one objective against another of every case's Pareto set, the
  chosen designs and the reference design marked and named in the legend (Fig 10);
- :func:`parallel_figure`: parallel coordinates of three or more objectives;
- :func:`map_figure`: an objective over each pair of variables, the others at mid-range,
  chosen and reference designs marked (Figs 4 and 7).

:func:`ringlube.study.figures.study_figures` turns a study into these inputs.
"""

from __future__ import annotations

import dataclasses
import itertools
from collections.abc import Callable, Sequence
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from ..outputs import save_figure  # noqa: E402
from ..plot import save_metadata  # noqa: E402

__all__ = [
    "Axis",
    "FitPanel",
    "Mark",
    "TradeoffSeries",
    "fit_figure",
    "map_figure",
    "tradeoff_figure",
    "parallel_figure",
    "save",
    "CONSTANT_RTOL",
]

#: A field whose range is below this fraction of its magnitude is drawn as constant.
CONSTANT_RTOL = 1e-6
_MARKERS = {
    "chosen": dict(marker="X", s=60, color="k", edgecolor="w", linewidth=0.6),
    "reference": dict(marker="*", s=190, color="gold", edgecolor="k", linewidth=0.8),
}


@dataclasses.dataclass
class Axis:
    """A design variable as drawn: label with unit, scale to the drawn unit, bounds (SI).

    Example
    -------
    >>> Axis("width [mm]", 1e3, 0.5e-3, 1.3e-3).scale
    1000.0
    """

    label: str
    scale: float
    lower: float
    upper: float


@dataclasses.dataclass
class FitPanel:
    """One objective's goodness of fit: simulated and predicted values, statistics.

    Example
    -------
    >>> FitPanel("energy_loss", "J", np.ones(2), np.ones(2), 1.0, 1.0, 0.0).unit
    'J'
    """

    name: str
    unit: str
    simulated: np.ndarray
    predicted: np.ndarray
    r2: float
    r2_adj: float
    cv_rel: float


@dataclasses.dataclass
class Mark:
    """A named design to mark on maps (``style``: ``chosen`` or ``reference``).

    Example
    -------
    >>> Mark("knee", np.zeros(4), "chosen").style
    'chosen'
    """

    name: str
    x: np.ndarray
    style: str = "chosen"


@dataclasses.dataclass
class TradeoffSeries:
    """One case on the trade-off plot.

    Attributes
    ----------
    label : str
    front : ndarray, shape (k, 2) (or (k, m) for :func:`parallel_figure`)
        The objectives drawn of its Pareto set.
    points : list of (name, x, y, style) (or (name, values, style))
        Designs re-simulated with the true model.

    Example
    -------
    >>> TradeoffSeries("cold", np.zeros((0, 2)), []).label
    'cold'
    """

    label: str
    front: np.ndarray
    points: list = dataclasses.field(default_factory=list)


def save(fig: plt.Figure, out: str | Path, stem: str) -> list[Path]:
    """Write ``fig`` as ``OUT/STEM.png`` and ``.pdf`` (no timestamps) and close it.

    Parameters
    ----------
    fig : Figure
    out : path
        Folder.
    stem : str
        File name without suffix.

    Returns
    -------
    list of Path

    Example
    -------
    >>> save(plt.figure(), "/tmp", "empty")                   # doctest: +SKIP
    """
    files = []
    for fmt in ("png", "pdf"):
        files.append(save_figure(fig, Path(out) / f"{stem}.{fmt}", dpi=130, metadata=save_metadata(fmt)))
    plt.close(fig)
    return files


def fit_figure(label: str, panels: Sequence[FitPanel], folds: int) -> plt.Figure:
    """Quadratic surface against true model, one panel per objective (study Fig 9).

    Parameters
    ----------
    label : str
        Case label.
    panels : sequence of FitPanel
    folds : int
        Folds of the cross-validation (for the titles).

    Returns
    -------
    Figure

    Example
    -------
    >>> fig = fit_figure("cold", [FitPanel("e", "J", np.arange(3.0), np.arange(3.0), 1, 1, 0)],
    ...                  5)
    """
    fig, axes = plt.subplots(
        1, len(panels), figsize=(4.2 * len(panels), 4), layout="constrained", squeeze=False
    )
    for ax, p in zip(axes.flat, panels):
        ax.scatter(p.simulated, p.predicted, s=4, alpha=0.5)
        lo = min(np.min(p.simulated), np.min(p.predicted))
        hi = max(np.max(p.simulated), np.max(p.predicted))
        ax.plot([lo, hi], [lo, hi], "k-", lw=0.8)
        ax.set_title(
            f"{p.name} ({label}): R$^2$ {p.r2:.4f}, adj {p.r2_adj:.4f}\n{folds}-fold CV error {p.cv_rel:.2%}",
            fontsize=9,
        )
        ax.set_xlabel(f"simulated {p.name} [{p.unit}]")
        ax.set_ylabel(f"quadratic surface [{p.unit}]")
    return fig


def _constant(z: np.ndarray) -> bool:
    return float(np.ptp(z)) <= CONSTANT_RTOL * max(float(np.max(np.abs(z))), 1e-300)


def map_figure(
    title: str,
    zlabel: str,
    surface: Callable[[np.ndarray], np.ndarray],
    axes_: Sequence[Axis],
    marks: Sequence[Mark] = (),
) -> plt.Figure:
    """An objective over every pair of variables (the others at mid-range).

    One panel per pair, at most three a row (one square panel for two variables; a line
    for one variable). A panel where the objective is constant to :data:`CONSTANT_RTOL`
    is drawn in one colour and says so, instead of a colour scale of rounding noise.

    Parameters
    ----------
    title : str
        What is drawn (objective and case).
    zlabel : str
        Objective with unit, for the colour bar.
    surface : callable
        ``surface(x) -> values`` for designs ``x`` (rows, SI).
    axes_ : sequence of Axis
        The design variables.
    marks : sequence of Mark
        Designs to mark and name.

    Returns
    -------
    Figure

    Example
    -------
    >>> ax = [Axis("a", 1.0, 0.0, 1.0), Axis("b", 1.0, 0.0, 1.0)]
    >>> fig = map_figure("t", "z", lambda x: x[:, 0] + x[:, 1], ax)
    """
    d = len(axes_)
    lo = np.array([a.lower for a in axes_])
    hi = np.array([a.upper for a in axes_])
    mid = 0.5 * (lo + hi)
    if d == 1:
        fig, ax = plt.subplots(figsize=(5.5, 4), layout="constrained")
        g = np.linspace(lo[0], hi[0], 200)[:, None]
        ax.plot(g[:, 0] * axes_[0].scale, surface(g), lw=1.4)
        for m in marks:
            ax.scatter(m.x[0] * axes_[0].scale, surface(np.atleast_2d(m.x))[0], zorder=3, **_MARKERS[m.style])
            ax.annotate(
                m.name,
                (m.x[0] * axes_[0].scale, surface(np.atleast_2d(m.x))[0]),
                fontsize=7,
                xytext=(4, 4),
                textcoords="offset points",
            )
        ax.set_xlabel(axes_[0].label)
        ax.set_ylabel(zlabel)
        ax.set_title(f"{title}, quadratic surface", fontsize=10)
        return fig
    pairs = list(itertools.combinations(range(d), 2))
    ncol = min(3, len(pairs))
    nrow = int(np.ceil(len(pairs) / ncol))
    fig, axs = plt.subplots(
        nrow, ncol, figsize=(4.4 * ncol + 1.2, 3.8 * nrow + 0.4), layout="constrained", squeeze=False
    )
    grids = []
    for a, b in pairs:
        ga, gb = np.meshgrid(np.linspace(lo[a], hi[a], 60), np.linspace(lo[b], hi[b], 60))
        x = np.tile(mid, (ga.size, 1))
        x[:, a] = ga.ravel()
        x[:, b] = gb.ravel()
        grids.append((ga, gb, surface(x).reshape(ga.shape)))
    # one colour scale for every panel: a pair along which the objective hardly changes
    # looks uniform instead of showing its rounding noise on a scale of its own
    zall = np.concatenate([z.ravel() for _, _, z in grids])
    constant = _constant(zall)
    levels = np.linspace(zall.min(), zall.max(), 21)
    tags = _tags(marks)
    cs = None
    for ax, (a, b), (ga, gb, z) in zip(axs.flat, pairs, grids):
        xa, xb = ga * axes_[a].scale, gb * axes_[b].scale
        if constant:
            ax.pcolormesh(xa, xb, np.zeros_like(z), cmap="Greys", vmin=0, vmax=4, shading="auto")
            ax.text(
                0.5,
                0.5,
                f"constant to {CONSTANT_RTOL:g}:\n{float(np.mean(z)):.6g}",
                transform=ax.transAxes,
                ha="center",
                va="center",
                fontsize=9,
            )
        else:
            cs = ax.contourf(xa, xb, z, levels=levels, cmap="viridis")
            ax.set_title(f"range here {z.min():.4g} to {z.max():.4g}", fontsize=8)
        xy = np.array([[m.x[a] * axes_[a].scale, m.x[b] * axes_[b].scale] for m in marks]).reshape(-1, 2)
        for m, (px, py) in zip(marks, xy):
            ax.scatter(px, py, zorder=3, clip_on=False, **_MARKERS[m.style])
        for group in _coincident(xy):
            ax.annotate(
                ",".join(tags[i] for i in group),
                tuple(xy[group[0]]),
                fontsize=7,
                xytext=(4, 3),
                textcoords="offset points",
                color="k",
                bbox=dict(boxstyle="round,pad=0.1", fc="w", alpha=0.7, lw=0),
            )
        ax.set_xlim(lo[a] * axes_[a].scale, hi[a] * axes_[a].scale)
        ax.set_ylim(lo[b] * axes_[b].scale, hi[b] * axes_[b].scale)
        ax.set_xlabel(axes_[a].label)
        ax.set_ylabel(axes_[b].label)
    for ax in list(axs.flat)[len(pairs) :]:
        ax.axis("off")
    if cs is not None:
        fig.colorbar(cs, ax=axs, label=zlabel, shrink=0.9)
    others = "" if d == 2 else ", other variables at mid-range"
    title = f"{title}, quadratic surface{others}"
    if constant:
        title += f": {zlabel} constant to {CONSTANT_RTOL:g}"
    fig.suptitle(title, fontsize=10)
    if marks:
        fig.supxlabel("marked: " + ", ".join(f"{t} = {m.name}" for t, m in zip(tags, marks)), fontsize=8)
    return fig


def _coincident(xy: np.ndarray, rtol: float = 0.01) -> list[list[int]]:
    """Groups of points closer than ``rtol`` of the points' span (drawn with one label)."""
    if len(xy) == 0:
        return []
    span = np.ptp(xy, axis=0)
    span = np.where(span > 0, span, np.maximum(np.abs(xy).max(axis=0), 1e-300))
    groups: list[list[int]] = []
    for i, p in enumerate(xy):
        for g in groups:
            if np.all(np.abs(p - xy[g[0]]) <= rtol * span):
                g.append(i)
                break
        else:
            groups.append([i])
    return groups


def _tags(marks: Sequence[Mark]) -> list[str]:
    """Short tags for marked designs: 1, 2, ... for chosen ones, R for the reference."""
    out, k = [], 0
    for m in marks:
        if m.style == "reference":
            out.append("R")
        else:
            k += 1
            out.append(str(k))
    return out


#: Markers of the chosen designs on the trade-off figures, in the order of their names
#: (the reference design is a star).
_DESIGN_MARKERS = ("o", "s", "^", "v", "D", "P", "h", "X", "<", ">")


def _design_marker(name: str, names: Sequence[str], style: str) -> dict:
    if style == "reference":
        return dict(marker="*", s=190, edgecolor="k", linewidth=0.8)
    i = list(names).index(name) if name in names else 0
    return dict(marker=_DESIGN_MARKERS[i % len(_DESIGN_MARKERS)], s=55, edgecolor="k", linewidth=0.8)


def tradeoff_figure(
    series: Sequence[TradeoffSeries],
    xlabel: str,
    ylabel: str,
    title: str | None = None,
    limits: Sequence[tuple[str, float, str]] = (),
) -> plt.Figure:
    """One objective against another: every case's Pareto set, the chosen and reference
    designs marked.

    Each design has its own marker (colour: its case) and is named in the legend, which
    sits outside the axes: no text label on the axes, so no label hides a point or
    another label however close the designs are.

    Parameters
    ----------
    series : sequence of TradeoffSeries
    xlabel, ylabel : str
        Axis labels with units.
    title : str, optional
    limits : sequence of (axis, value, label)
        Constraint bounds on a drawn objective (``axis`` ``'x'`` or ``'y'``), drawn as
        dashed lines named in the legend.

    Returns
    -------
    Figure

    Example
    -------
    >>> fig = tradeoff_figure([TradeoffSeries("cold", np.array([[8.0, 1.9]]),
    ...                                       [("knee", 8.0, 1.9, "chosen")])], "x", "y")
    """
    fig, ax = plt.subplots(figsize=(8.5, 5), layout="constrained")
    for sr in series:
        sc = ax.scatter(
            sr.front[:, 0], sr.front[:, 1], s=7, alpha=0.45, label=f"{sr.label}: Pareto set (surrogate)"
        )
        colour = sc.get_facecolor()[0]
        names = [p[0] for p in sr.points if p[3] == "chosen"]
        for name, px, py, style in sr.points:
            ax.scatter(
                [px],
                [py],
                zorder=3,
                color=colour,
                label=f"{sr.label}: {name} (true model)",
                **_design_marker(name, names, style),
            )
    for k, (axis, value, text) in enumerate(limits):
        line = ax.axvline if axis == "x" else ax.axhline
        line(value, color="0.3", ls=("--", ":", "-.")[k % 3], lw=1, label=text)
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.02, 1.0), borderaxespad=0)
    ax.set_title(title or f"trade-off: {ylabel} against {xlabel}", fontsize=10)
    return fig


def parallel_figure(
    series: Sequence[TradeoffSeries], labels: Sequence[str], title: str = "Pareto set"
) -> plt.Figure:
    """Parallel coordinates of three or more objectives: each Pareto design a thin line,
    each chosen and reference design a thick one named in the legend (outside the axes).

    ``front`` of each series has one column per objective, and each point is
    ``(name, values, style)``; every axis is scaled from the best (0) to the worst (1) value
    of the case's Pareto set and chosen designs, with that range written under it (a
    reference design outside the range is drawn beyond 0 or 1).

    Parameters
    ----------
    series : sequence of TradeoffSeries
    labels : sequence of str
        Objectives with units.
    title : str

    Returns
    -------
    Figure

    Example
    -------
    >>> fig = parallel_figure([TradeoffSeries("c", np.eye(3), [("knee", np.ones(3) / 3, "chosen")])],
    ...                       ["a", "b", "c"])
    """
    m = len(labels)
    fig, axs = plt.subplots(
        len(series), 1, figsize=(1.9 * m + 4, 3.6 * len(series)), layout="constrained", squeeze=False
    )
    xs = np.arange(m)
    for ax, sr in zip(axs[:, 0], series):
        pts = np.array([p[1] for p in sr.points if p[2] == "chosen"]).reshape(-1, m)
        allv = np.vstack([sr.front, pts])  # the reference may lie far off: drawn beyond 0..1
        lo, hi = np.nanmin(allv, 0), np.nanmax(allv, 0)
        span = np.where(hi > lo, hi - lo, np.maximum(np.abs(hi), 1e-300))
        for row in (sr.front - lo) / span:
            ax.plot(xs, row, color="0.6", lw=0.6, alpha=0.5)
        names = [p[0] for p in sr.points if p[2] == "chosen"]
        for k, (name, values, style) in enumerate(sr.points):
            mk = _design_marker(name, names, style)
            ax.plot(
                xs,
                (np.asarray(values) - lo) / span,
                lw=2.2,
                color=f"C{k}",
                marker=mk["marker"],
                markersize=9 if style == "reference" else 6,
                markeredgecolor="k",
                label=f"{name} (true model)",
            )
        ax.set_xticks(xs, [f"{lab}\n{a:.4g} to {b:.4g}" for lab, a, b in zip(labels, lo, hi)], fontsize=8)
        ax.set_ylabel("Pareto set: best (0) to worst (1)")
        ax.grid(alpha=0.3, axis="x")
        ax.set_title(f"{title} ({sr.label}): Pareto designs thin, chosen designs thick", fontsize=10)
        ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.02, 1.0), borderaxespad=0)
    return fig
