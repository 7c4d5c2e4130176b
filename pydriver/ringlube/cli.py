"""The ``ringlube`` command.

Every user mistake ends in one line on stderr, ``ringlube: error: ...`` naming the file,
option or variable, and exit status 2 (bad input) or 1 (runtime error); a run that did not
converge exits 3; Ctrl-C exits 130.
"""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

from .errors import InputError, RinglubeError

__all__ = ["main"]


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


def _output_file(option: str, out: Path, inputs: list[Path]) -> Path:
    """Check a result file to be written: a new path or a regular file, not an input."""
    from .outputs import check_output

    return check_output(out, inputs, option)


def _output_folder(option: str, out: Path) -> Path:
    if out.exists() and not out.is_dir():
        raise InputError(f"{option} {out}: exists and is not a folder")
    return out


def _cmd_run(args: argparse.Namespace) -> int:
    from .case import Case
    from .solve import run

    case = Case.from_namelist(args.deck)
    out = (
        Path(args.output)
        if args.output
        else Path(case.get("output", "file") or Path(args.deck).with_suffix(".h5"))
    )
    inputs = [
        Path(args.deck),
        *(Path(p) for p in (case.get("operating", "pressure_file"), case.get("calibration", "file")) if p),
    ]
    _output_file("-o" if args.output else f"{args.deck}: &output file", out, inputs)
    result = run(case, output=out)
    if not args.quiet:
        from ._version import __version__

        print(result.summary(title=f"ringlube {__version__}: {args.deck}", written=str(out)))
    return 0 if result.converged else 3


def _load(path: str):
    """A result file, or one line saying what is wrong with it."""
    import h5py

    from .result import load

    p = Path(path)
    if not p.exists():
        raise InputError(f"{p}: file not found")
    if not p.is_file():
        raise InputError(f"{p}: not a file")
    if not h5py.is_hdf5(p):
        raise InputError(f"{p}: not an HDF5 result file (a deck? run it first: ringlube run {p})")
    try:
        return load(p)
    except RinglubeError:
        raise
    except (OSError, KeyError, ValueError, TypeError) as exc:
        reason = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        raise InputError(f"{p}: not a readable ringlube result ({reason})") from None


def _cmd_plot(args: argparse.Namespace) -> int:
    from .plot import plot_results

    out = _output_folder("-o", Path(args.output))
    labels = args.labels.split(",") if args.labels else []
    for label in labels:
        if not label or "/" in label or "\\" in label:
            raise InputError(
                f"--labels: '{label}' must be a non-empty name without '/' (it names the figure files)"
            )
    if len(labels) > len(args.results):
        raise InputError(f"--labels: {len(labels)} labels for {len(args.results)} result files")
    results = [_load(p) for p in args.results]
    for r, label in zip(results, labels):
        r.label = label
    for r in results:
        if "/" in r.label or "\\" in r.label:
            raise InputError(f"result label '{r.label}' contains '/'; give --labels")
    for f in plot_results(results, out, inputs=[Path(p) for p in args.results]):
        print(f"written {f}")
    return 0


def _cmd_gas(args: argparse.Namespace) -> int:
    from . import gas

    given = {f: getattr(args, f) for f in gas.OPTIONS if hasattr(args, f)}
    args.output, args.name = getattr(args, "output", None), getattr(args, "name", None)
    args.names = getattr(args, "names", [])
    if args.output is None:
        if given:
            option = gas.OPTIONS[next(iter(given))][0]
            raise InputError(f"gas: {option} describes your own engine; give -o FILE.csv, the trace to write")
        _output_folder("--out", Path(args.out))
        unknown = [n for n in args.names if n not in gas.PRESETS]
        if unknown:
            raise InputError(
                f"gas: unknown trace {', '.join(unknown)} (known: {', '.join(sorted(gas.PRESETS))}; "
                "for your own engine: ringlube gas -o FILE.csv --bore ... , see ringlube gas --help)"
            )
        gas.main(["--out", args.out, *args.names])
        return 0
    if args.names:
        raise InputError(f"gas: -o writes one trace of your own engine; drop {' '.join(args.names)}")
    missing = [gas.OPTIONS[f][0] for f in _GAS_REQUIRED if f not in given]
    if missing:
        raise InputError(f"gas: -o {args.output}: give {', '.join(missing)} (your engine's, in SI units)")
    out = Path(args.output)
    if out.suffix.lower() != ".csv":
        raise InputError(f"gas: -o {out}: the trace is a CSV file; name it *.csv")
    if out.exists() and not out.is_file():
        raise InputError(f"gas: -o {out}: exists and is not a regular file")
    if given["crank_radius"] <= 0:  # --stroke, named with its own value
        raise InputError(f"gas: --stroke: must be a positive number, not {given['crank_radius']:g}")
    given["crank_radius"] = given["crank_radius"] / 2
    try:
        model = gas.GasModel(**given)
        files = gas.write_trace(model, out, name=args.name, figures=not args.no_figure)
    except ValueError as exc:
        raise InputError(f"gas: {_gas_options(str(exc))}") from None
    psi, p = gas.read_csv(out)  # as the kernel reads it
    print(f"written {', '.join(map(str, files))}\n{out}: {gas.describe(model, psi, p)}")
    speed = f"speed_rpm = {model.speed_rpm:g}, " if model.speed_rpm else ""
    print(
        f"deck lines: &engine crank_radius = {model.crank_radius:g}, conrod_length = "
        f"{model.conrod_length:g}, bore_radius = {model.bore / 2:g} / "
        f"&operating {speed}pressure_file = '{out.name}' /"
    )
    return 0


# what `ringlube gas -o` needs: the engine's own geometry (no source-engine defaults)
_GAS_REQUIRED = ("bore", "crank_radius", "conrod_length", "compression_ratio")


def _gas_options(message: str) -> str:
    """A GasModel message with its parameter names replaced by the command's options."""
    from .gas import OPTIONS

    names, _, why = message.partition(": ")
    opts = [OPTIONS[n.strip()][0] if n.strip() in OPTIONS else n for n in names.split(",")]
    return f"{', '.join(opts)}: {why}" if why else message


def _cmd_show(args: argparse.Namespace) -> int:
    from .case import Case
    from .case_text import _format

    case = Case.from_namelist(args.deck)
    rows = case.effective_inputs()
    tension_unit = next(r.value for r in rows if r.name == "tension_unit")
    if args.set:
        rows = [r for r in rows if r.origin not in ("default",) and not r.origin.startswith("preset")]
    print(f"{args.deck}: effective inputs (from: deck, calibration file, preset, default)")
    print(f"{'group':<12}{'variable':<25}{'from':<18}value [unit]")
    for r in rows:
        unit = {"1": "", "(unit)": f"[{tension_unit}]"}.get(r.unit, f"[{r.unit}]" if r.unit else "")
        print(f"{'&' + r.group:<12}{r.name:<25}{r.origin:<18}{_format(r.value)} {unit}".rstrip())
    case.warn_source_defaults()
    return 0


def _one_line_warnings() -> None:
    """Source-engine-default warnings as one line on stderr: ``ringlube: warning: ...``."""
    import warnings

    from .case_origins import SourceEngineDefaultWarning

    show = warnings.showwarning
    if getattr(show, "_ringlube", False):
        return

    def one_line(message, category, filename, lineno, file=None, line=None):
        if issubclass(category, SourceEngineDefaultWarning):
            print(f"ringlube: warning: {message}", file=sys.stderr)
        else:
            show(message, category, filename, lineno, file, line)

    one_line._ringlube = True
    warnings.showwarning = one_line


def _cmd_convergence(args: argparse.Namespace) -> int:
    from .convergence import convergence_study, write_report

    _output_folder("--out", Path(args.out))
    command = "ringlube convergence " + " ".join(
        [*args.decks, *(["--quick"] if args.quick else []), "--out", args.out]
    )
    from .outputs import check_output

    for deck in args.decks:  # every output checked before the first (long) run
        for suffix in ("md", "csv", "png"):
            check_output(Path(args.out) / f"convergence_{Path(deck).stem}.{suffix}", args.decks, "--out")
    for deck in args.decks:
        reference, rows = convergence_study(deck, quick=args.quick, repeats=args.repeats)
        for f in write_report(deck, reference, rows, args.out, command):
            print(f"written {f}")
    return 0


def _cmd_calibrate(args: argparse.Namespace) -> int:
    from .calibrate import calibrate, cold_targets, correlation, strip_calibrated, write_calibration
    from .case import Case
    from .outputs import check_output
    from .targets import DEFAULT_TARGETS

    target_deck, _ = cold_targets(args.targets)
    case = Case.from_namelist(args.deck)
    # the calibration file the deck includes is not read by the fit (it is what is written)
    trace = case.value("operating", "pressure_file")
    inputs = [args.deck, args.targets or DEFAULT_TARGETS, target_deck, trace]
    check_output(args.out, inputs, "--out")  # before the ~300 runs, not after
    fit, fits = calibrate(args.deck, targets=args.targets)
    base = strip_calibrated(Case.from_namelist(args.deck))
    jac, corr = correlation(base, fit)
    path = write_calibration(args.out, fit, fits, jac, corr, args.deck)
    t = fit.targets
    print(
        f"chosen: {fit.values()}\n  energy {fit.energy_loss:.4f} J (target "
        f"{t['energy_loss']:g} J), mixed {fit.mixed_share:.3f} % (target {t['mixed_share']:g} %), "
        f"correlation of fitted inputs {corr:+.3f}"
    )
    print(f"written {path}")
    return 0


def _cmd_validate(args: argparse.Namespace) -> int:
    from .validate import validate

    _output_folder("--out", Path(args.out))
    print(f"written {validate(args.root, args.out)}")
    return 0


def _cmd_readings(args: argparse.Namespace) -> int:
    from .readings_cli import run_args

    return run_args(args)


def _cmd_optimise(args: argparse.Namespace) -> int:
    import signal

    from .study import run_study
    from .study_summary import summary

    def terminate(signum, frame):  # a batch system's SIGTERM: save finished runs, then stop
        raise KeyboardInterrupt(f"signal {signum}")

    if args.scheduler is not None and not args.scheduler.strip():
        raise InputError("--scheduler '': empty address (omit --scheduler for a local cluster)")
    if args.out is not None:
        _output_folder("--out", Path(args.out))
    signal.signal(signal.SIGTERM, terminate)
    args.interrupt_note = "; finished work is saved (run the same command to resume)"
    study = run_study(
        args.study,
        args.out,
        scheduler=args.scheduler,
        workers=args.workers,
        serial=args.serial,
        with_direct=args.direct,
        progress=not args.quiet,
    )
    if not args.quiet:
        print(summary(study))
    print(f"written {study.path}, report.md, Pareto CSV and figures in {study.path.parent}")
    return 0


def _parser() -> argparse.ArgumentParser:
    from . import __version__

    ap = _Parser(prog="ringlube", description="Piston ring mixed-lubrication solver and design optimiser.")
    ap.add_argument("--version", action="version", version=f"ringlube {__version__}")
    sub = ap.add_subparsers(dest="command", required=True, metavar="COMMAND", parser_class=_Parser)
    p = sub.add_parser(
        "run",
        help="run one deck (same numbers as ringlube-solve)",
        description="Run one deck and write its result (HDF5).",
    )
    p.add_argument("deck", help="the case deck (namelist)")
    p.add_argument(
        "-o", "--output", help="result file (default: the deck's &output file, else the deck's name with .h5)"
    )
    p.add_argument("-q", "--quiet", action="store_true", help="print nothing but errors")
    p.set_defaults(func=_cmd_run)
    p = sub.add_parser(
        "plot",
        help="friction, film and gas-pressure plots of one or more results",
        description="Friction, film and gas-pressure plots (PNG and PDF) of result files, and the "
        "inlet, liner-film and ring-pack plots of the results that have them.",
    )
    p.add_argument("results", nargs="+", help="result files (HDF5) to overlay")
    p.add_argument("-o", "--output", default=".", help="output folder")
    p.add_argument("--labels", help="comma-separated legend labels (default: file names)")
    p.set_defaults(func=_cmd_plot)
    p = sub.add_parser(
        "gas",
        help="a gas-pressure trace for your engine, or the shipped ones",
        description="Without -o: regenerate the shipped synthetic traces (CSV) in --out. With -o "
        "FILE.csv: the single-zone trace of your own engine (bore, stroke, conrod, compression ratio "
        "required; SI units), with its inputs in the file's header and a figure beside it (PNG, PDF). "
        "The load is --imep or --peak-pressure if given, else the fuel of the trapped charge "
        "(--manifold-pressure, --heat-fraction; 0 gives the motored trace). See docs/own_engine.md.",
    )
    p.add_argument(
        "names", nargs="*", default=argparse.SUPPRESS, help="shipped traces to write (none given: all)"
    )
    p.add_argument("--out", default="inputs/pressure", help="output folder of the shipped traces")
    p.add_argument("-o", "--output", default=argparse.SUPPRESS, help="your engine's trace (CSV) to write")
    p.add_argument(
        "--name", default=argparse.SUPPRESS, help="name in the trace's header (none given: the file's name)"
    )
    p.add_argument("--no-figure", action="store_true", help="no PNG/PDF figure beside the CSV")
    import dataclasses

    from .gas import OPTIONS as gas_options, GasModel

    defaults = {f.name: f.default for f in dataclasses.fields(GasModel)}
    for field, (option, help_text) in gas_options.items():
        default = defaults[field]
        shown = (
            "required with -o" if field in _GAS_REQUIRED else "none" if default is None else f"{default:g}"
        )
        p.add_argument(
            option,
            dest=field,
            type=_finite_float,
            default=argparse.SUPPRESS,
            metavar="X",
            help=f"{help_text} ({shown})",
        )
    p.set_defaults(func=_cmd_gas)
    p = sub.add_parser(
        "show",
        help="the effective inputs of a deck and where each came from",
        description="Print every input of a deck as the kernel reads it, with where its value came "
        "from (deck, calibration file, numerics preset, default), and warn if the source engine's "
        "defaults fill part of the engine geometry or ring.",
    )
    p.add_argument("deck", help="the case deck (namelist)")
    p.add_argument("--set", action="store_true", help="only the inputs the deck or its calibration file set")
    p.set_defaults(func=_cmd_show)
    p = sub.add_parser(
        "convergence",
        help="speed against accuracy over numerical settings",
        description="Speed against accuracy over numerical settings.",
    )
    p.add_argument("decks", nargs="+", help="case decks")
    p.add_argument("--out", default="docs/convergence", help="output folder")
    p.add_argument("--quick", action="store_true", help="shorter ladders (no 801/1601 nodes)")
    p.add_argument("--repeats", type=_positive_int, default=3, help="timing repeats per setting (best kept)")
    p.set_defaults(func=_cmd_convergence)
    p = sub.add_parser(
        "calibrate",
        help="fit the uncertain inputs to the cold Table 2 case",
        description="Fit the uncertain inputs to the cold Table 2 case.",
    )
    p.add_argument(
        "deck", nargs="?", default="inputs/crf450r_4000rpm_full_cold.nml", help="the cold case deck"
    )
    p.add_argument("--out", default="inputs/calibration.nml", help="calibration file written")
    p.add_argument(
        "--targets",
        default=None,
        help="CSV of measured or published results (condition 'cold' is fitted; "
        "default: inputs/targets_table2.csv, Table 2 of the study)",
    )
    p.set_defaults(func=_cmd_calibrate)
    p = sub.add_parser(
        "validate",
        help="regenerate docs/validation.md against Table 2",
        description="Regenerate docs/validation.md against the study's Table 2.",
    )
    p.add_argument("--root", default=".", help="project folder (with inputs/)")
    p.add_argument("--out", default="docs", help="output folder")
    p.set_defaults(func=_cmd_validate)
    p = sub.add_parser(
        "readings",
        help="calibrate every reading of the open modelling choices (cold only)",
        description="Fit every reading (film model x contact area x tension unit) to the cold "
        "Table 2 case and the published trends; write docs/readings.md.",
    )
    from .readings_cli import add_arguments as readings_arguments

    readings_arguments(p)
    p.set_defaults(func=_cmd_readings)
    p = sub.add_parser(
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
        "--direct",
        action="store_true",
        help="also NSGA-II on the true model, compared with the surrogate front",
    )
    p.add_argument(
        "-q", "--quiet", action="store_true", help="no progress bars or summary (the files are still written)"
    )
    p.set_defaults(func=_cmd_optimise)
    return ap


def main(argv: list[str] | None = None) -> int:
    """Run the ``ringlube`` command.

    Parameters
    ----------
    argv : list of str, optional
        Arguments (default: ``sys.argv[1:]``).

    Returns
    -------
    int
        Exit status: 0 success, 1 runtime error, 2 bad input, 3 not converged, 130
        interrupted.

    Example
    -------
    >>> main(["--version"])                                  # doctest: +SKIP
    ringlube 0.1.0
    """
    args = _parser().parse_args(argv)
    _one_line_warnings()
    try:
        return args.func(args)
    except RinglubeError as exc:
        print(f"ringlube: error: {_one_line(exc)}", file=sys.stderr)
        return exc.code
    except BrokenPipeError:  # the reader of our output left (`ringlube show DECK | head`)
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())  # no second error when Python flushes at exit
        return 141  # as a command ended by SIGPIPE
    except OSError as exc:  # the file system said no (permissions, disk full, ...)
        where = f"{exc.filename}: " if getattr(exc, "filename", None) else ""
        print(f"ringlube: error: {where}{exc.strerror or exc}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print(f"ringlube: interrupted{getattr(args, 'interrupt_note', '')}", file=sys.stderr)
        return 130


def _one_line(exc: BaseException) -> str:
    text = " ".join(str(exc).split("\n")).strip()
    return text or type(exc).__name__


if __name__ == "__main__":
    sys.exit(main())
