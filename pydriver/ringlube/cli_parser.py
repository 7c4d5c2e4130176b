"""The argument parser of the ``ringlube`` command: every subcommand, option and help text."""

from __future__ import annotations

import argparse

from .cli_commands import (
    _GAS_REQUIRED,
    _cmd_calibrate,
    _cmd_convergence,
    _cmd_gas,
    _cmd_optimise,
    _cmd_plot,
    _cmd_readings,
    _cmd_run,
    _cmd_show,
    _cmd_validate,
)

__all__: list[str] = []


class _Parser(argparse.ArgumentParser):
    """argparse with one-line errors (exit 2) and defaults shown in every help text."""

    def __init__(self, *args, **kwargs):
        kwargs.setdefault("formatter_class", argparse.ArgumentDefaultsHelpFormatter)
        super().__init__(*args, **kwargs)

    def error(self, message: str):  # noqa: D401 - argparse API
        self.exit(2, f"{self.prog}: error: {message} (see {self.prog} --help)\n")


def _positive_int(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"'{text}' is not a whole number") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"{value}: must be at least 1")
    return value


def _finite_float(text: str) -> float:
    import math

    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"'{text}' is not a number") from None
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"'{text}' is not a finite number")
    return value


def _parser() -> argparse.ArgumentParser:
    from . import __version__, kernel_id

    ap = _Parser(prog="ringlube", description="Piston ring mixed-lubrication solver and design optimiser.")
    ap.add_argument("--version", action="version", version=f"ringlube {__version__} (kernel {kernel_id()})")
    sub = ap.add_subparsers(dest="command", required=True, metavar="COMMAND", parser_class=_Parser)
    p = _command(
        sub,
        _cmd_run,
        "run",
        help="run one deck (same numbers as ringlube-solve)",
        description="Run one deck and write its result (HDF5).",
    )
    p.add_argument("deck", help="the case deck (namelist)")
    p.add_argument(
        "-o",
        "--output",
        help="result file (default: the deck's &output file, else result.h5 beside it, as ringlube-solve)",
    )
    p.add_argument("-q", "--quiet", action="store_true", help="print nothing but errors")
    p = _command(
        sub,
        _cmd_plot,
        "plot",
        help="friction, film and gas-pressure plots of one or more results",
        description="Friction, film and gas-pressure plots (PNG and PDF) of result files, and the "
        "inlet, liner-film and ring-pack plots of the results that have them; of a distorted bore "
        "the film/gap around the bore at chosen crank angles (polar), its crank angle x sector map "
        "and the face flow beside the end-gap flows (docs/bore.md).",
    )
    p.add_argument("results", nargs="+", help="result files (HDF5) to overlay")
    p.add_argument("-o", "--output", default=".", help="output folder")
    p.add_argument("--labels", help="comma-separated legend labels (default: file names)")
    p.add_argument(
        "--angles",
        help="comma-separated crank angles [deg] of the polar plot of a distorted bore's gap "
        "(default: 0,90,180,270,360,380,540)",
    )
    p = _command(
        sub,
        _cmd_gas,
        "gas",
        help="a gas-pressure trace for your engine, or the shipped ones",
        description="With -o FILE.csv: the single-zone trace of your own engine (bore, stroke, conrod, "
        "compression ratio required; SI units), with its inputs in the file's header and a figure "
        "beside it (PNG, PDF). The load is --imep or --peak-pressure if given (both with wall heat "
        "loss, --heat-transfer), else the fuel of the trapped charge (--manifold-pressure, "
        "--heat-fraction); --motored gives the trace without combustion (overrun: a closed throttle "
        "with the fuel cut). With --out DIR: the shipped synthetic traces (--out inputs/pressure "
        "rewrites them). Without either nothing is written. See docs/own_engine.md.",
    )
    p.add_argument(
        "names",
        nargs="*",
        default=argparse.SUPPRESS,
        help="shipped traces to write with --out (none given: all)",
    )
    p.add_argument("--out", default=argparse.SUPPRESS, help="output folder of the shipped traces")
    p.add_argument("-o", "--output", default=argparse.SUPPRESS, help="your engine's trace (CSV) to write")
    p.add_argument("--name", default=None, help="name in the trace's header (none given: the file's name)")
    p.add_argument("--no-figure", action="store_true", help="no PNG/PDF figure beside the CSV")
    p.add_argument(
        "--motored",
        action="store_true",
        default=argparse.SUPPRESS,
        help="no combustion: the motored trace (overrun with --manifold-pressure of a closed throttle)",
    )
    import dataclasses

    from .gas import HEAT_TRANSFER, OPTIONS as gas_options, GasModel

    defaults = {f.name: f.default for f in dataclasses.fields(GasModel)}
    for field, (option, help_text) in gas_options.items():
        default = defaults[field]
        if field in _GAS_REQUIRED:
            shown = "required with -o"
        elif field == "heat_fraction":
            shown = "0.75; 0.95 with --heat-transfer"
        elif field == "heat_transfer_scale":
            shown = "1"
        else:
            shown = "none" if default is None else default if isinstance(default, str) else f"{default:g}"
        kind = dict(choices=HEAT_TRANSFER, metavar="NAME") if field == "heat_transfer" else {}
        p.add_argument(
            option,
            dest=field,
            type=str if kind else _finite_float,
            default=argparse.SUPPRESS,
            **({"metavar": "X"} | kind),
            help=f"{help_text} ({shown})",
        )
    p = _command(
        sub,
        _cmd_show,
        "show",
        help="the effective inputs of a deck and where each came from",
        description="Print every input of a deck as the kernel reads it, with where its value came "
        "from (deck, calibration file, numerics preset, default), and warn if the source engine's "
        "defaults fill part of the engine geometry or ring.",
    )
    p.add_argument("deck", help="the case deck (namelist)")
    p.add_argument("--set", action="store_true", help="only the inputs the deck or its calibration file set")
    p = _command(sub, _cmd_convergence, "convergence", "speed against accuracy over numerical settings")
    p.add_argument("decks", nargs="+", help="case decks")
    p.add_argument("--out", default="docs/convergence", help="output folder")
    p.add_argument("--quick", action="store_true", help="shorter ladders (no 801/1601 nodes)")
    p.add_argument("--repeats", type=_positive_int, default=3, help="timing repeats per setting (best kept)")
    p = _command(sub, _cmd_calibrate, "calibrate", "fit the uncertain inputs to the cold Table 2 case")
    p.add_argument(
        "deck", nargs="?", default="inputs/crf450r_4000rpm_full_cold.nml", help="the cold case deck"
    )
    p.add_argument("--out", default="inputs/calibration.nml", help="calibration file written")
    p.add_argument(
        "--tension-unit",
        choices=("N", "N/m"),
        help="the reading of the ring's tension fitted: 'N' (tangential force) or 'N/m' (force per "
        "unit circumference); default: the deck's &ring tension_unit",
    )
    p.add_argument(
        "--targets",
        default=None,
        help="CSV of measured or published results (condition 'cold' is fitted: its friction, "
        "energy_loss, friction_power or fmep, and its mixed_share if given; "
        "default: inputs/targets_table2.csv, Table 2 of the study)",
    )
    p = _command(
        sub,
        _cmd_validate,
        "validate",
        help="regenerate docs/validation.md against Table 2",
        description="Regenerate docs/validation.md against the study's Table 2.",
    )
    p.add_argument("--root", default=".", help="project folder (with inputs/)")
    p.add_argument("--out", default="docs", help="output folder")
    p = _command(
        sub,
        _cmd_readings,
        "readings",
        help="calibrate every reading of the open modelling choices (cold only)",
        description="Fit every reading (film model x contact area x tension unit) to the cold "
        "Table 2 case and the published trends; write docs/readings.md.",
    )
    from .readings.cli import add_arguments as readings_arguments

    readings_arguments(p)
    p = _command(
        sub,
        _cmd_optimise,
        "optimise",
        help="DOE, quadratic surfaces and NSGA-II from a &study deck",
        description="Design study from a &study deck: sample, run, fit, NSGA-II, "
        "check; resumes an interrupted study in the same --out.",
    )
    p.add_argument("study", help="the study deck (&study)")
    p.add_argument(
        "--out",
        help="output folder (default: out/NAME, NAME from &study name); an unfinished study there is resumed",
    )
    p.add_argument(
        "--scheduler", help="address of an existing Dask scheduler (default: a LocalCluster on this machine)"
    )
    p.add_argument(
        "--workers", type=_positive_int, help="LocalCluster worker processes (default: one per core)"
    )
    p.add_argument("--serial", action="store_true", help="no Dask: run everything in this process")
    p.add_argument(
        "--restart",
        action="store_true",
        help="start afresh: a study file already in --out is replaced, none of its runs used "
        "(e.g. one made by another kernel build, which is not resumed)",
    )
    p.add_argument(
        "--direct",
        action="store_true",
        help="also NSGA-II on the true model, compared with the surrogate front",
    )
    p.add_argument(
        "-q", "--quiet", action="store_true", help="no progress bars or summary (the files are still written)"
    )
    return ap


def _command(sub, func, name: str, help: str | None = None, **kwargs) -> argparse.ArgumentParser:
    """A subcommand `name` of `sub` run by `func` (add_parser's keyword arguments: help,
    description, ...; without a description, `help` as a sentence)."""
    if help is not None:
        kwargs["help"] = help
        kwargs.setdefault("description", help[0].upper() + help[1:] + ".")
    p = sub.add_parser(name, **kwargs)
    p.set_defaults(func=func)
    return p
