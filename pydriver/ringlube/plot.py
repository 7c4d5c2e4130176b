"""Cycle plots in the style of the source study (friction and film over the cycle)."""

from __future__ import annotations

import os
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

import matplotlib

matplotlib.use("Agg")  # files only; no display needed
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from .errors import InputError  # noqa: E402
from .outputs import check_output, save_figure  # noqa: E402
from .plot_axes import crank_axis, result_label  # noqa: E402

if TYPE_CHECKING:
    from .result import CycleResult

__all__ = [
    "friction_figure",
    "film_figure",
    "gas_figure",
    "liner_figure",
    "overlay_figure",
    "plot_results",
    "save_metadata",
    "supply_figure",
]

# no creation date in the files, so that regenerated figures differ only when their data do
_METADATA = {"png": {"Software": None}, "pdf": {"CreationDate": None, "Producer": None}}


def save_metadata(fmt: str) -> dict:
    """savefig metadata without timestamps for the given format.

    Parameters
    ----------
    fmt : str
        'png' or 'pdf' (others: no metadata).

    Returns
    -------
    dict

    Examples
    --------
    >>> save_metadata("pdf")
    {'CreationDate': None, 'Producer': None}
    """
    return _METADATA.get(fmt, {})


def friction_figure(results: Sequence[CycleResult]) -> plt.Figure:
    """Friction over the cycle with its viscous and boundary parts (study Figs 3, 5, 11b).

    Parameters
    ----------
    results : sequence of CycleResult
        Overlaid, in order.

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> import ringlube
    >>> r = ringlube.run(ringlube.Case().with_numerics(preset="fast"))
    >>> len(friction_figure([r]).axes) >= 1
    True
    """
    fig, ax = plt.subplots(figsize=(8, 4.2), layout="constrained")
    for i, r in enumerate(results):
        (line,) = ax.plot(
            r.crank_angle_deg,
            r.friction,
            lw=1.4,
            label=f"{result_label(r, i)}: total ({r.energy_loss:.3f} J/cycle)",
        )
        for part, y, ls in (("viscous", r.viscous_friction, "--"), ("boundary", r.boundary_friction, ":")):
            ax.plot(
                r.crank_angle_deg,
                y,
                lw=0.9,
                ls=ls,
                color=line.get_color(),
                label=f"{result_label(r, i)}: {part}",
            )
    ax.axhline(0, color="k", lw=0.6)
    ax.set_ylabel("friction on the ring [N]\n(positive: towards the crankcase)")
    ax.set_title(
        "Friction on the ring, positive towards the crankcase (it opposes the ring's motion:\n"
        "positive on upstrokes, negative on downstrokes)",
        fontsize=9,
    )
    crank_axis(ax)
    ax.legend(fontsize=7, ncol=1 if len(results) == 1 else 2, loc="lower left")
    return fig


def film_figure(results: Sequence[CycleResult]) -> plt.Figure:
    """Minimum film thickness over the cycle with the lambda = 4 threshold (Figs 6, 8, 11a).

    Parameters
    ----------
    results : sequence of CycleResult
        Overlaid, in order.

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> import ringlube
    >>> r = ringlube.run(ringlube.Case().with_numerics(preset="fast"))
    >>> len(film_figure([r]).axes) >= 1
    True
    """
    fig, ax = plt.subplots(figsize=(8, 4.2), layout="constrained")
    for i, r in enumerate(results):
        ax.plot(
            r.crank_angle_deg,
            r.lambda_min * r.sigma * 1e6,
            lw=1.4,
            label=f"{result_label(r, i)} (mixed {r.mixed_share:.1f} % of the cycle)",
        )
    sigmas = sorted({r.sigma for r in results})
    for s in sigmas:
        ax.axhline(4 * s * 1e6, color="tab:red", lw=1, ls="--")
        ax.text(
            5,
            4 * s * 1e6,
            f" $\\lambda$ = 4 ({4 * s * 1e6:.2f} $\\mu$m): mixed/boundary below",
            color="tab:red",
            fontsize=8,
            va="bottom",
        )
    ax.set_ylabel(r"minimum film thickness [$\mu$m]")
    ax.set_ylim(bottom=0)
    crank_axis(ax)
    ax.legend(fontsize=8, loc="upper right")
    return fig


def overlay_figure(results: Sequence[CycleResult], labels: Sequence[str] | None = None) -> plt.Figure:
    """Several results over one cycle, one colour each (``ringlube.compare(...).figure()``):
    friction (positive towards the crankcase), friction power and film thickness h0.

    Parameters
    ----------
    results : sequence of CycleResult
    labels : sequence of str, optional
        One per result (default: their labels).

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> import ringlube
    >>> r = ringlube.run(ringlube.Case().with_numerics(preset="fast"))
    >>> len(overlay_figure([r, r], ["a", "b"]).axes)
    3
    """
    labels = [result_label(r, i) for i, r in enumerate(results)] if labels is None else list(labels)
    fig, axes = plt.subplots(3, 1, figsize=(8, 8), sharex=True, layout="constrained")
    for r, name in zip(results, labels):
        (line,) = axes[0].plot(r.crank_angle_deg, r.friction, lw=1.2, label=name)
        axes[1].plot(
            r.crank_angle_deg,
            r.power_loss,
            lw=1.2,
            color=line.get_color(),
            label=f"{name}: {r.scalars.get('friction_power', np.nan):.1f} W mean",
        )
        axes[2].plot(r.crank_angle_deg, r.h0 * 1e6, lw=1.2, color=line.get_color(), label=name)
    axes[0].axhline(0, color="k", lw=0.6)
    axes[0].set_ylabel("friction [N]\n(+ towards the crankcase)")
    axes[1].set_ylabel("friction power [W]")
    axes[2].set_ylabel(r"film thickness $h_0$ [$\mu$m]")
    axes[2].set_yscale("log")  # a ring that lifts off (h0_ceiling) beside microns
    for ax in axes:
        crank_axis(ax)
        ax.legend(fontsize=7, loc="upper right")
    for ax in axes[:-1]:
        ax.set_xlabel("")
    return fig


def supply_figure(results: Sequence[CycleResult]) -> plt.Figure:
    """Inlet fill and wetted width over the cycle (mass-conserving film).

    Parameters
    ----------
    results : sequence of CycleResult
        Overlaid, in order.

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> import ringlube
    >>> r = ringlube.run(ringlube.Case().with_numerics(preset="fast"))
    >>> len(supply_figure([r]).axes) >= 1
    True
    """
    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(8, 6), sharex=True, layout="constrained")
    for i, r in enumerate(results):
        if "inlet_fill" not in r.series:
            continue
        ax1.plot(r.crank_angle_deg, r.inlet_fill, lw=1.2, label=result_label(r, i))
        ax2.plot(r.crank_angle_deg, r.wetted_width * 1e3, lw=1.2, label=result_label(r, i))
    ax1.set_ylabel("inlet fill theta_in [-]")
    ax1.set_ylim(-0.05, 1.05)
    ax2.set_ylabel("wetted (full-film) width [mm]")
    ax2.set_ylim(bottom=0)
    crank_axis(ax2)
    if ax1.lines:
        ax1.legend(fontsize=8, loc="lower right")
    return fig


def ring_pack_figure(results: Sequence[CycleResult]) -> plt.Figure:
    """The gas around the ring over the cycle (``ring_pack = 'gas'``): chamber p1,
    groove p2 and land p3 pressures, the ring's lift in its groove and the flows through the
    two end gaps (the second ring's is the blowby).

    Parameters
    ----------
    results : sequence of CycleResult
        Overlaid, in order (results without the ring pack are left out).

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> import ringlube
    >>> r = ringlube.run(ringlube.Case().with_physics(ring_pack="gas").with_numerics(preset="fast"))
    >>> len(ring_pack_figure([r]).axes)
    3
    """
    fig, (ax1, ax2, ax3) = plt.subplots(3, 1, figsize=(8, 8), sharex=True, layout="constrained")
    for i, r in enumerate(results):
        if "groove_pressure" not in r.series:
            continue
        tag = result_label(r, i)
        (line,) = ax1.plot(r.crank_angle_deg, r.gas_pressure / 1e5, lw=1.0, label=f"{tag} p1 chamber")
        for part, p, ls in (("p2 groove", r.groove_pressure, "--"), ("p3 land", r.land_pressure, ":")):
            ax1.plot(r.crank_angle_deg, p / 1e5, lw=1.2, ls=ls, color=line.get_color(), label=f"{tag} {part}")
        # one colour per result in every panel, the line style tells the quantity
        c = line.get_color()
        ax2.plot(r.crank_angle_deg, r.ring_lift * 1e6, lw=1.2, color=c, label=tag)
        ax3.plot(
            r.crank_angle_deg, r.top_gap_flow * 1e3, lw=1.0, color=c, label=f"{tag} top gap (chamber to land)"
        )
        ax3.plot(
            r.crank_angle_deg,
            r.second_gap_flow * 1e3,
            lw=1.2,
            ls="--",
            color=c,
            label=f"{tag} second gap (blowby)",
        )
    ax1.set_ylabel("gas pressure [bar abs]")
    ax1.set_yscale("log")
    ax2.set_ylabel("ring lift above the lower flank [um]")
    ax3.set_ylabel("gas flow [g/s], + towards crankcase")
    crank_axis(ax3)
    for ax in (ax1, ax3):
        if ax.lines:
            ax.legend(fontsize=7, loc="upper right")
    return fig


def liner_figure(results: Sequence[CycleResult]) -> plt.Figure:
    """The oil film on the liner along the stroke at the end of the reported cycle (crank
    angle 720 deg, firing TDC: the ring at the top of its travel), starved inlet.

    Parameters
    ----------
    results : sequence of CycleResult
        Overlaid, in order.

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> import ringlube
    >>> r = ringlube.run(ringlube.Case().with_numerics(preset="fast"))
    >>> len(liner_figure([r]).axes) >= 1
    True
    """
    fig, ax = plt.subplots(figsize=(8, 4.2), layout="constrained")
    for i, r in enumerate(results):
        if not r.liner:
            continue
        ax.plot(
            r.liner["liner_position"] * 1e3,
            r.liner["liner_oil_film"] * 1e6,
            lw=1.2,
            label=f"{result_label(r, i)} ({r.oil_to_chamber:.3g} mm$^3$ per cycle to the chamber)",
        )
    ax.set_xlabel("liner position from the top ring at TDC [mm] (towards the crankcase)")
    ax.set_ylabel(r"oil film on the liner [$\mu$m]")
    ax.set_title(
        "Oil film on the liner at the end of the cycle (crank angle 720 deg, TDC: the ring at\n"
        "the top of its travel; the film left by the exhaust upstroke and the lower rings)",
        fontsize=9,
    )
    ax.set_ylim(bottom=0)
    if ax.lines:
        ax.legend(fontsize=8, loc="upper right")
    return fig


def plot_results(
    results: Sequence[CycleResult],
    outdir: str | os.PathLike,
    formats: Sequence[str] = ("png", "pdf"),
    stem: str = "",
    inputs: Sequence[str | os.PathLike] = (),
    angles: Sequence[float] | None = None,
) -> list[Path]:
    """Write the friction and film figures for one or several (overlaid) results, and for
    results of the mass-conserving film the inlet fill and wetted width, with a starved
    inlet the liner oil film, with the ring pack its pressures, lift and gas flows, with a
    distorted bore the gap around the bore, its map and the face flow
    (:mod:`ringlube.plot_bore`, of those results only), and the gas pressure each run used
    (its trace times ``pressure_scale``).

    Parameters
    ----------
    results : sequence of CycleResult
    outdir : path
        Created if missing.
    formats : sequence of str
        File formats.
    stem : str
        File name stem (default: the labels joined).
    inputs : sequence of path
        Files that must not be overwritten (the result files plotted); every figure is
        checked by :func:`ringlube.outputs.check_output` (no symbolic link, no folder, no
        input) before any is written, and written atomically.
    angles : sequence of float, optional
        Crank angles [deg] of the polar plot of a distorted bore's gap (default
        :data:`ringlube.plot_bore.POLAR_ANGLES`); refused when no result has a distorted bore.

    Returns
    -------
    list of Path

    Examples
    --------
    >>> import ringlube, tempfile
    >>> r = ringlube.run(ringlube.Case(name="r").with_numerics(preset="fast"))
    >>> [p.name for p in plot_results([r], tempfile.mkdtemp(), formats=("png",))]
    ['r_friction.png', 'r_film.png', 'r_gas.png']
    """
    outdir = Path(outdir)
    stem = stem or ("_vs_".join(r.label for r in results if r.label) or "result")
    files = []
    kinds = [("friction", friction_figure), ("film", film_figure)]
    if any("inlet_fill" in r.series for r in results):
        kinds.append(("supply", supply_figure))
    if any(r.liner for r in results):
        kinds.append(("liner", liner_figure))
    if any("groove_pressure" in r.series for r in results):
        kinds.append(("ring_pack", ring_pack_figure))
    kinds += _bore_kinds(results, angles)
    kinds.append(("gas", _gas_of_results))
    outdir.mkdir(parents=True, exist_ok=True)
    for kind, _ in kinds:  # every name checked before the first figure is written
        for fmt in formats:
            check_output(outdir / f"{stem}_{kind}.{fmt}", inputs)
    for kind, make in kinds:
        fig = make(results)
        for fmt in formats:
            path = outdir / f"{stem}_{kind}.{fmt}"
            files.append(save_figure(fig, path, inputs, dpi=150, metadata=_METADATA[fmt]))
        plt.close(fig)
    return files


def _bore_kinds(results: Sequence[CycleResult], angles: Sequence[float] | None) -> list:
    """The figures of the results with a distorted bore (drawn of those only): the gap around
    the bore at ``angles``, its map and the face flow; none without such a result (then
    ``angles`` is refused)."""
    import copy

    from . import plot_bore as pb

    # (copies labelled as in the other figures: "result 2" is the second result in each)
    bores = [copy.copy(r) for r in results if r.distorted]
    for r, i in zip(bores, [i for i, r in enumerate(results) if r.distorted]):
        r.label = result_label(r, i)
    if not bores:
        if angles is not None:
            raise InputError(
                "--angles: no result has a distorted bore (the polar plot of the gap needs a run "
                "with &physics bore = 'distorted')"
            )
        return []
    polar = pb.POLAR_ANGLES if angles is None else pb.crank_angles(angles)
    return [
        ("bore_polar", lambda _: pb.bore_polar_figure(bores, polar)),
        ("bore_map", lambda _: pb.bore_map_figure(bores)),
        ("bore_flow", lambda _: pb.face_flow_figure(bores)),
    ]


def _gas_of_results(results: Sequence[CycleResult]) -> plt.Figure:
    """The gas pressure of each result over its cycle (:func:`gas_figure`)."""
    return gas_figure(
        {result_label(r, i): (r.crank_angle_deg, r.gas_pressure) for i, r in enumerate(results)}
    )


def gas_figure(traces: dict[str, tuple[np.ndarray, np.ndarray]]) -> plt.Figure:
    """In-cylinder gas pressure over the cycle (study Fig 2).

    Parameters
    ----------
    traces : dict of str to (ndarray, ndarray)
        Label -> (crank angle deg, pressure Pa).

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> import numpy as np
    >>> psi = np.linspace(0, 720, 5)
    >>> gas_figure({"flat": (psi, np.full(5, 1e5))}).axes[0].get_ylabel()
    'gas pressure [bar abs]'
    """
    fig, ax = plt.subplots(figsize=(8, 4.2), layout="constrained")
    for label, (psi, p) in traces.items():
        i = int(np.argmax(p))
        ax.plot(psi, p / 1e5, lw=1.4, label=f"{label} (peak {p[i] / 1e5:.1f} bar at {psi[i]:.1f} deg)")
    ax.set_ylabel("gas pressure [bar abs]")
    ax.set_ylim(bottom=0)
    crank_axis(ax)
    ax.legend(fontsize=8)
    return fig
