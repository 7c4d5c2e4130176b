"""Figures of a distorted bore (``&physics bore = 'distorted'``): the film/gap around the bore
at chosen crank angles (polar), a crank angle x sector map of the gap, and the gas through the
ring's face beside the end-gap flows of the ring pack. ``ringlube plot`` draws them for every
result that has a distorted bore; a round bore's result is refused with a message."""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from typing import TYPE_CHECKING

import matplotlib

matplotlib.use("Agg")  # files only; no display needed
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.colors import LogNorm  # noqa: E402

from .errors import InputError  # noqa: E402
from .plot_axes import crank_axis, result_label  # noqa: E402
from .tables import FLAGS  # noqa: E402

if TYPE_CHECKING:
    from .result import CycleResult

__all__ = ["POLAR_ANGLES", "bore_polar_figure", "bore_map_figure", "face_flow_figure", "crank_angles"]

#: the crank angles of the polar plot by default [deg]: intake TDC, mid-intake, BDC,
#: mid-compression, firing TDC, just after it (the peak gas load), BDC of expansion
POLAR_ANGLES = (0.0, 90.0, 180.0, 270.0, 360.0, 380.0, 540.0)

# the stroke a crank angle lies in (0 = TDC at the start of intake)
_STROKE_NAMES = ("intake", "compression", "expansion", "exhaust")


def _distorted(results: Sequence[CycleResult], what: str) -> list[tuple[int, CycleResult]]:
    """The results with their index (one result: itself); an :class:`InputError` naming the
    first that is no result or has a round bore."""
    from .result import CycleResult

    results = [results] if isinstance(results, CycleResult) else list(results)
    if not results:
        raise InputError(f"{what}: no result given")
    for i, r in enumerate(results):
        if not isinstance(r, CycleResult):
            raise InputError(
                f"{what}: result {i + 1} is a {type(r).__name__}, not a result "
                "(ringlube.run(case), or ringlube.load(path) of a result file)"
            )
        if not getattr(r, "distorted", False):
            raise InputError(
                f"{what}: '{result_label(r, i)}' has a round bore (no sectors); it needs a run with "
                "&physics bore = 'distorted' and a &bore group (docs/bore.md)"
            )
    return list(enumerate(results))


def crank_angles(text: str | Sequence[float]) -> tuple[float, ...]:
    """Crank angles of the polar plot from ``'0,90,380'`` (or numbers): each in 0 .. 720 deg.

    Parameters
    ----------
    text : str, float or sequence of float

    Returns
    -------
    tuple of float

    Raises
    ------
    InputError
        An empty list, a value that is not a number or outside 0 .. 720.

    Examples
    --------
    >>> crank_angles("0, 90,380")
    (0.0, 90.0, 380.0)
    >>> crank_angles("0,800")
    Traceback (most recent call last):
    ...
    ringlube.errors.InputError: --angles: 800 deg is outside the cycle (0 .. 720 deg)
    """
    if isinstance(text, str):
        items = text.replace(",", " ").split()
    elif hasattr(text, "tolist"):  # a numpy array or scalar
        items = list(np.ravel(text).tolist())
    elif isinstance(text, Iterable):  # a list, a tuple, a range, a generator
        items = list(text)
    else:  # one angle
        items = [text]
    if not items:
        raise InputError("--angles: no crank angle given (e.g. --angles 0,90,180,270,360,380,540)")
    out = []
    for t in items:
        try:
            a = float(t)
        except (TypeError, ValueError):
            raise InputError(f"--angles: '{t}' is not a crank angle in deg") from None
        if not (0.0 <= a <= 720.0):
            raise InputError(f"--angles: {a:g} deg is outside the cycle (0 .. 720 deg)")
        out.append(a)
    return tuple(out)


def _step(r: CycleResult, angle: float) -> int:
    """The crank step nearest ``angle`` (deg, on the periodic cycle)."""
    d = np.abs((r.crank_angle_deg - angle + 360.0) % 720.0 - 360.0)
    return int(np.argmin(d))


def _stroke(angle: float) -> str:
    a = angle % 720.0
    if a in (0.0, 360.0):
        return "TDC, firing" if a == 360.0 else "TDC"
    if a in (180.0, 540.0):
        return "BDC"
    return _STROKE_NAMES[int(a // 180.0) % 4]


def _ring_outline(r: CycleResult, k: int) -> tuple[np.ndarray, np.ndarray]:
    """The gap h0_j [um] of step k as a closed outline around the bore: each sector its own
    film, constant over its arc (theta_j +- pi / M)."""
    h = r.sector_h0[k] * 1e6
    m = len(h)
    half = np.pi / m
    arc = np.linspace(-half, half, 9)
    theta = np.concatenate([np.deg2rad(t) + arc for t in r.sector_angle_deg])
    return np.append(theta, theta[0] + 2 * np.pi), np.append(np.repeat(h, len(arc)), h[0])


def bore_polar_figure(results: Sequence[CycleResult], angles: Sequence[float] = POLAR_ANGLES) -> plt.Figure:
    """The ring's film/gap h0_j around the bore at chosen crank angles, one polar panel each
    (radius: h0 on a log scale, every result overlaid; each sector constant over its arc, a
    dot at its centre). A light gap is where the outline bulges out to tens of microns; the
    dashed circle is 4 sigma (below it the film is mixed/boundary). A panel whose ring is
    pushed off the liner (held at back_clearance, flag 2) says "radial collapse".

    Parameters
    ----------
    results : sequence of CycleResult
        Distorted-bore results.
    angles : sequence of float
        Crank angles [deg] (0 = TDC at the start of intake, 360 = firing TDC); the nearest
        crank step is drawn.

    Returns
    -------
    matplotlib.figure.Figure

    Raises
    ------
    InputError
        A result with a round bore.

    Examples
    --------
    >>> import ringlube
    >>> case = ringlube.Case().with_physics(bore="distorted", cavitation="jfo")
    >>> case = case.with_("bore", order=[4], amplitude=[10e-6], sectors=8).with_numerics(preset="fast")
    >>> r = ringlube.run(case)
    >>> len(bore_polar_figure([r], angles=[90, 380]).axes)
    2
    >>> bore_polar_figure([ringlube.run(ringlube.Case().with_numerics(preset="fast"))])
    Traceback (most recent call last):
    ...
    ringlube.errors.InputError: polar plot of the gap: 'case' has a round bore (no sectors); ...
    """
    rs = _distorted(results, "polar plot of the gap")
    angles = crank_angles(angles)
    ncols = min(4, len(angles))
    nrows = -(-len(angles) // ncols)
    fig, axes = plt.subplots(
        nrows,
        ncols,
        figsize=(3.1 * ncols, 3.2 * nrows + 0.9),
        subplot_kw={"projection": "polar"},
        squeeze=False,
        layout="constrained",
    )
    steps = [[_step(r, a) for a in angles] for _, r in rs]
    h = np.concatenate([r.sector_h0[s].ravel() for (_, r), s in zip(rs, steps)]) * 1e6
    lo, hi = 10 ** np.floor(np.log10(h.min() / 1.2)), 10 ** np.ceil(np.log10(h.max() * 1.2))
    sigmas = sorted({r.sigma for _, r in rs})
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for n, (ax, a) in enumerate(zip(axes.flat, angles)):
        for (i, r), s in zip(rs, steps):
            k = s[n]
            theta, gap = _ring_outline(r, k)
            c = colours[i % len(colours)]
            ax.plot(theta, gap, lw=1.2, color=c, label=result_label(r, i))
            ax.plot(np.deg2rad(r.sector_angle_deg), r.sector_h0[k] * 1e6, "o", ms=2.5, color=c)
        full = np.linspace(0, 2 * np.pi, 181)
        for sg in sigmas:
            ax.plot(full, np.full_like(full, 4 * sg * 1e6), "--", color="tab:red", lw=0.8)
        ax.set_rscale("log")
        ax.set_rlim(lo, hi)
        ax.set_rlabel_position(100)
        ax.tick_params(labelsize=7)
        drawn = rs[0][1].crank_angle_deg[steps[0][n]]
        same = abs((drawn - a + 360.0) % 720.0 - 360.0) < 1e-9
        shown = f"{a:g} deg" if same else f"{a:g} deg (step at {drawn:g})"
        collapsed = any(r.flags[s[n]] & FLAGS["h0_ceiling"] for (_, r), s in zip(rs, steps))
        ax.set_title(f"{shown}: {_stroke(a)}" + (" (radial collapse)" if collapsed else ""), fontsize=9)
    for ax in list(axes.flat)[len(angles) :]:
        ax.set_visible(False)
    handles = [axes.flat[0].lines[2 * j] for j in range(len(rs))]
    handles.append(axes.flat[0].lines[2 * len(rs)])
    names = [result_label(r, i) for i, r in rs] + [r"4 $\sigma$: mixed/boundary inside"]
    fig.legend(handles, names, loc="outside lower center", ncol=min(4, len(names)), fontsize=8)
    fig.suptitle(
        r"Film/gap $h_0$ of each sector around the bore [$\mu$m, log radius] at chosen crank angles"
        "\n(angle around the bore from the distortion's phase reference; a light gap bulges out)",
        fontsize=9,
    )
    return fig


def bore_map_figure(results: Sequence[CycleResult]) -> plt.Figure:
    """The film/gap h0 of every sector over the cycle: crank angle x angle around the bore,
    colour on a log scale (one panel per result, one colour scale for all). Light gaps are
    the bright bands along the cycle, a radial collapse (the ring held at back_clearance) a
    bright column across every sector.

    Parameters
    ----------
    results : sequence of CycleResult
        Distorted-bore results.

    Returns
    -------
    matplotlib.figure.Figure

    Raises
    ------
    InputError
        A result with a round bore.

    Examples
    --------
    >>> import ringlube
    >>> case = ringlube.Case().with_physics(bore="distorted", cavitation="jfo")
    >>> case = case.with_("bore", order=[4], amplitude=[10e-6], sectors=8).with_numerics(preset="fast")
    >>> r = ringlube.run(case)
    >>> bore_map_figure([r]).axes[0].get_ylabel()
    'angle around the bore [deg]'
    """
    rs = _distorted(results, "map of the gap")
    fig, axes = plt.subplots(
        len(rs), 1, figsize=(8, 1.0 + 2.8 * len(rs)), squeeze=False, sharex=True, layout="constrained"
    )
    h = np.concatenate([r.sector_h0.ravel() for _, r in rs]) * 1e6
    norm = LogNorm(vmin=h.min(), vmax=h.max())
    mesh = None
    for ax, (i, r) in zip(axes[:, 0], rs):
        psi = r.crank_angle_deg
        m = r.sector_h0.shape[1]
        step = psi[1] - psi[0] if len(psi) > 1 else 720.0
        x_edges = np.append(psi - step / 2, psi[-1] + step / 2)
        y_edges = (np.arange(m + 1) - 0.5) * 360.0 / m
        mesh = ax.pcolormesh(x_edges, y_edges, r.sector_h0.T * 1e6, norm=norm, cmap="viridis", shading="flat")
        ax.set_ylabel("angle around the bore [deg]")
        ax.set_yticks(np.arange(0, 361, 90))
        ax.set_ylim(y_edges[0], y_edges[-1])
        ax.set_title(
            f"{result_label(r, i)}: {m} sectors; light gaps {r.light_gap_share:.1f} % of sector-steps, "
            f"conformability {r.conformability:.2f}",
            fontsize=9,
            pad=14,
        )
        crank_axis(ax)
    for ax in axes[:-1, 0]:
        ax.set_xlabel("")
    bar = fig.colorbar(mesh, ax=axes[:, 0], shrink=0.9)
    bar.set_label(r"film/gap $h_0$ [$\mu$m] (log)")
    return fig


def face_flow_figure(results: Sequence[CycleResult]) -> plt.Figure:
    """The gas through the ring's face over the cycle beside the end-gap flows of the ring
    pack (top gap: chamber to land, second gap: the blowby), and the sectors' smallest and
    largest film/gap (when the faces open).

    Parameters
    ----------
    results : sequence of CycleResult
        Distorted-bore results (the end gaps where the run had the ring pack).

    Returns
    -------
    matplotlib.figure.Figure

    Raises
    ------
    InputError
        A result with a round bore.

    Examples
    --------
    >>> import ringlube
    >>> case = ringlube.Case().with_physics(bore="distorted", cavitation="jfo")
    >>> case = case.with_("bore", order=[4], amplitude=[10e-6], sectors=8).with_numerics(preset="fast")
    >>> r = ringlube.run(case)
    >>> len(face_flow_figure([r]).axes)
    2
    """
    rs = _distorted(results, "face flow figure")
    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(8, 6.5), sharex=True, layout="constrained")
    for i, r in rs:
        tag = result_label(r, i)
        (line,) = ax1.plot(
            r.crank_angle_deg,
            r.face_flow * 1e3,
            lw=1.4,
            label=f"{tag} face ({r.face_leakage:.3g} mg/cycle towards the crankcase)",
        )
        c = line.get_color()
        if "top_gap_flow" in r.series:
            top = r.top_gap_flow * 1e3
            ax1.plot(r.crank_angle_deg, top, lw=1.0, ls="--", color=c, label=f"{tag} top gap")
            ax1.plot(
                r.crank_angle_deg,
                r.second_gap_flow * 1e3,
                lw=1.0,
                ls=":",
                color=c,
                label=f"{tag} second gap (blowby {r.blowby_mass:.3g} mg/cycle)",
            )
        gap = r.sector_h0 * 1e6
        ax2.fill_between(r.crank_angle_deg, gap.min(axis=1), gap.max(axis=1), color=c, alpha=0.25, lw=0)
        ax2.plot(r.crank_angle_deg, gap.max(axis=1), lw=1.0, color=c, label=f"{tag} largest (the open side)")
        ax2.plot(r.crank_angle_deg, gap.min(axis=1), lw=1.0, ls="--", color=c, label=f"{tag} smallest")
    ax1.axhline(0, color="k", lw=0.6)
    ax1.set_ylabel("gas flow [g/s]\n(+ towards the crankcase)")
    ax1.set_title(
        "Gas through the ring's face (where its film leaves a path) beside the end gaps", fontsize=9, pad=14
    )
    ax2.set_yscale("log")
    ax2.set_ylabel(r"film/gap $h_0$ of the sectors [$\mu$m]")
    for ax in (ax1, ax2):
        crank_axis(ax)
        ax.legend(fontsize=7, loc="upper right")
    ax1.set_xlabel("")
    return fig
