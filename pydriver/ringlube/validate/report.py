"""Validation report: the shipped calibration against the study's Table 2.

``ringlube validate`` regenerates ``docs/validation.md`` and its figures from scratch:
published vs computed (cold = calibration target, hot = prediction), the calibration
re-run and compared with the shipped file, one-at-a-time sensitivity (+/-10 %) of each
compared number to each assumed input, the effect of each modelling option, the gas
trace's peak and its crank angle, the published trends, and the study's Figs 2 and 11.

The runs are :func:`ringlube.validate.compute.compute_validation`, the Markdown is
:func:`ringlube.validate.render.render_validation`; this module writes the figures and the file.
"""

from __future__ import annotations

import os
import time
from pathlib import Path

from .. import gas
from ..outputs import check_output, save_figure, write_text
from ..plot import gas_figure, plot_results, save_metadata
from .compute import ValidationData, compute_validation
from .render import render_validation

__all__ = ["validate"]


def write_figures(data: ValidationData, root: str | os.PathLike, figdir: str | os.PathLike) -> list[Path]:
    """The study's Figs 2 (gas traces) and 11 (cold against hot) into ``figdir``."""
    figdir = Path(figdir)
    files = plot_results([data.results["cold"], data.results["hot"]], figdir, stem="fig11_cold_vs_hot")
    traces = {}
    for name in ("crf450r_4000rpm_full", "crf450r_3000rpm_half"):
        traces[name] = gas.read_csv(Path(root) / "inputs" / "pressure" / f"{name}.csv")
    fig = gas_figure(traces)
    for fmt in ("png", "pdf"):
        path = figdir / f"fig2_gas_pressure.{fmt}"
        files.append(save_figure(fig, path, dpi=150, metadata=save_metadata(fmt)))
    return files


def validate(root: str | os.PathLike = ".", out: str | os.PathLike = "docs") -> Path:
    """Regenerate ``OUT/validation.md`` and ``OUT/figures/`` from the shipped decks.

    Parameters
    ----------
    root : path
        Project folder (with ``inputs/``).
    out : path
        Output folder.

    Returns
    -------
    Path
        The Markdown file written.

    Raises
    ------
    InputError
        If a shipped deck or the targets file is bad.

    Examples
    --------
    >>> validate(".", "docs")  # doctest: +SKIP
    PosixPath('docs/validation.md')
    """
    t0 = time.perf_counter()
    root, out = Path(root), Path(out)
    figdir = out / "figures"
    figdir.mkdir(parents=True, exist_ok=True)
    check_output(
        out / "validation.md",
        [root / "inputs" / "crf450r_4000rpm_full_cold.nml", root / "inputs" / "crf450r_4000rpm_full_hot.nml"],
    )
    data = compute_validation(root)
    write_figures(data, root, figdir)
    data.seconds = time.perf_counter() - t0
    return write_text(out / "validation.md", render_validation(data))
