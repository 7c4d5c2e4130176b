"""What the cycle figures share: the crank-angle axis and a result's label."""

from __future__ import annotations

from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import matplotlib.pyplot as plt

    from .result import CycleResult

__all__ = ["crank_axis", "result_label"]

_STROKES = (("intake", 90), ("compression", 270), ("expansion", 450), ("exhaust", 630))
_CENTRES = ((0, "TDC"), (180, "BDC"), (360, "TDC\nfiring"), (540, "BDC"), (720, "TDC"))


def crank_axis(ax: plt.Axes) -> None:
    """Label a crank-angle axis 0..720 deg: TDC and BDC ticks, the four strokes named above.

    Parameters
    ----------
    ax : matplotlib Axes

    Examples
    --------
    >>> import matplotlib.pyplot as plt
    >>> fig, ax = plt.subplots()
    >>> crank_axis(ax); [float(x) for x in ax.get_xlim()]
    [0.0, 720.0]
    >>> plt.close(fig)
    """
    ax.set_xlim(0, 720)
    ax.set_xticks([c for c, _ in _CENTRES])
    ax.set_xticklabels([f"{c}\n{n}" for c, n in _CENTRES], fontsize=8)
    ax.set_xlabel("crank angle [deg]")
    for c, _ in _CENTRES[1:-1]:
        ax.axvline(c, color="0.8", lw=0.8, zorder=0)
    for name, mid in _STROKES:
        ax.text(
            mid,
            1.01,
            name,
            transform=ax.get_xaxis_transform(),
            ha="center",
            va="bottom",
            fontsize=8,
            color="0.35",
        )


def result_label(r: CycleResult, i: int) -> str:
    """A result's label in a legend: its own, else 'result i+1'.

    Parameters
    ----------
    r : CycleResult
    i : int
        The result's place among those plotted (from 0).

    Returns
    -------
    str

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> result_label(SimpleNamespace(label=""), 1)
    'result 2'
    """
    return r.label or f"result {i + 1}"
