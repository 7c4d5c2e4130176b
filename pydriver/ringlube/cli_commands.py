"""The subcommands of the ``ringlube`` command: one ``_cmd_NAME(args)`` each, returning the
exit status (the parser is :mod:`ringlube.cli_parser`, the command :mod:`ringlube.cli`)."""

from __future__ import annotations

import argparse
from pathlib import Path

from .errors import InputError, RinglubeError, input_file

__all__: list[str] = []


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

    if args.output is not None and not args.output.strip():
        raise InputError("-o: the output file name is empty")
    case = Case.from_namelist(args.deck)
    # without -o, the kernel's own choice: the deck's &output file, else its default
    # 'result.h5', relative to the deck's folder (as ringlube-solve does)
    out = Path(args.output) if args.output is not None else Path(case.value("output", "file"))
    inputs = [
        Path(args.deck),
        *(
            Path(p)
            for p in (
                case.get("operating", "pressure_file"),
                case.get("calibration", "file"),
                case.get("ring", "profile_file"),
            )
            if p
        ),
    ]
    _output_file("-o" if args.output is not None else f"{args.deck}: &output file", out, inputs)
    from . import _kernel

    # a line on the terminal says where a run of more than a few seconds is (not with -q)
    _kernel.rl_progress(0 if args.quiet else 1)
    result = run(case, output=out)
    if not args.quiet:
        from ._version import __version__

        print(result.summary(title=f"ringlube {__version__}: {args.deck}", written=str(out)))
    if not result.converged:  # as ringlube-solve: on stderr, also with -q
        import sys

        print(
            "ringlube run: warning: the run did not converge; result written with converged = 0",
            file=sys.stderr,
        )
    return 0 if result.converged else 3


def _load(path: str):
    """A result file, or one line saying what is wrong with it."""
    import h5py

    from .result import load

    p = input_file(path)
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
    angles = None
    if args.angles is not None:
        from .plot_bore import crank_angles

        angles = crank_angles(args.angles)
    results = [_load(p) for p in args.results]
    for r, label in zip(results, labels):
        r.label = label
    for r in results:
        if "/" in r.label or "\\" in r.label:
            raise InputError(f"result label '{r.label}' contains '/'; give --labels")
    for f in plot_results(results, out, inputs=[Path(p) for p in args.results], angles=angles):
        print(f"written {f}")
    return 0


def _cmd_gas(args: argparse.Namespace) -> int:
    from . import gas
    from .gas import range_problem

    given = {f: getattr(args, f) for f in gas.OPTIONS if hasattr(args, f)}
    output, folder = getattr(args, "output", None), getattr(args, "out", None)
    names, motored = getattr(args, "names", []), getattr(args, "motored", False)
    if output is None:
        if given or motored:
            option = gas.OPTIONS[next(iter(given))][0] if given else "--motored"
            raise InputError(f"gas: {option} describes your own engine; give -o FILE.csv, the trace to write")
        unknown = [n for n in names if n not in gas.PRESETS]
        if unknown:
            raise InputError(
                f"gas: unknown trace {', '.join(unknown)} (known: {', '.join(sorted(gas.PRESETS))}; "
                "for your own engine: ringlube gas -o FILE.csv --bore ... , see ringlube gas --help)"
            )
        if folder is None:  # never rewrite the shipped traces unasked
            raise InputError(
                "gas: nothing written: give -o FILE.csv with your engine (--bore, --stroke, --conrod, "
                "--compression-ratio) for its trace, or --out DIR for the shipped traces "
                f"({', '.join(sorted(gas.PRESETS))}; --out inputs/pressure rewrites them)"
            )
        _output_folder("--out", Path(folder))
        for line in gas.write_presets(folder, names):
            print(line)
        return 0
    if folder is not None:
        raise InputError("gas: --out writes the shipped traces, -o your engine's; give one of them")
    if names:
        raise InputError(f"gas: -o writes one trace of your own engine; drop {' '.join(names)}")
    if not output.strip():
        raise InputError("gas: -o: the output file name is empty")
    missing = [gas.OPTIONS[f][0] for f in _GAS_REQUIRED if f not in given]
    if missing:
        raise InputError(f"gas: -o {output}: give {', '.join(missing)} (your engine's, in SI units)")
    out = Path(output)
    if out.suffix.lower() != ".csv":
        raise InputError(f"gas: -o {out}: the trace is a CSV file; name it *.csv")
    if motored:
        burning = [gas.OPTIONS[f][0] for f in gas.COMBUSTION_OPTIONS if f in given]
        if burning:
            raise InputError(f"gas: --motored: a motored trace has no combustion; drop {', '.join(burning)}")
        given["heat_fraction"] = 0.0
    why = range_problem("crank_radius", given["crank_radius"], factor=2.0)
    if why:  # --stroke, named with its own value and range
        raise InputError(f"gas: --stroke: {why}")
    given["crank_radius"] = given["crank_radius"] / 2
    try:
        model = gas.GasModel(**given)
        files, psi, p = gas.write_trace(model, out, name=args.name, figures=not args.no_figure, option="-o")
    except ValueError as exc:
        raise InputError(f"gas: {_gas_options(str(exc))}") from None
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
    parts = [n.strip() for n in names.split(",")]
    if not why or not all(n in OPTIONS for n in parts):
        return message
    return f"{', '.join(OPTIONS[n][0] for n in parts)}: {why}"


def _cmd_show(args: argparse.Namespace) -> int:
    from .case import Case
    from .case.text import format_value

    case = Case.from_namelist(args.deck)
    rows = case.effective_inputs()
    tension_unit = next(r.value for r in rows if r.name == "tension_unit")
    if args.set:
        rows = [r for r in rows if r.origin not in ("default",) and not r.origin.startswith("preset")]
    print(f"{args.deck}: effective inputs (from: deck, calibration file, preset, default)")
    print(f"{'group':<12}{'variable':<25}{'from':<18}value [unit]")
    for r in rows:
        unit = {"1": "", "(unit)": f"[{tension_unit}]"}.get(r.unit, f"[{r.unit}]" if r.unit else "")
        group = f"{'&' + r.group:<11} "  # a blank after the longest, '&calibration'
        print(f"{group}{r.name:<25}{r.origin:<18}{format_value(r.value)} {unit}".rstrip())
    case.validate()  # its warnings: source-engine defaults, inputs the case does not use
    return 0


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
    from .calibrate import (
        calibrate,
        cold_targets,
        correlation,
        strip_calibrated,
        write_calibration,
    )
    from .case import Case
    from .outputs import check_output
    from .targets import DEFAULT_TARGETS

    target_deck, _ = cold_targets(args.targets)
    case = Case.from_namelist(args.deck)
    # the calibration file the deck includes is not read by the fit (it is what is written)
    trace = case.value("operating", "pressure_file")
    inputs = [args.deck, args.targets or DEFAULT_TARGETS, target_deck, trace]
    check_output(args.out, inputs, "--out")  # before the ~300 runs, not after
    fit, fits = calibrate(args.deck, targets=args.targets, tension_unit=args.tension_unit)
    base = strip_calibrated(Case.from_namelist(args.deck))
    if args.tension_unit:
        base = base.with_ring(tension_unit=args.tension_unit)
    jac, corr = correlation(base, fit)
    command = f"ringlube calibrate {args.deck}"
    if args.tension_unit:
        command += f" --tension-unit {args.tension_unit}"
    if args.targets:
        command += f" --targets {args.targets}"
    if args.out != "inputs/calibration.nml":
        command += f" --out {args.out}"
    path = write_calibration(args.out, fit, fits, jac, corr, args.deck, command)
    shown = {"energy_loss": ("energy", ".4f", "J"), "mixed_share": ("mixed", ".3f", "%")}
    shown |= {"friction_power": ("friction power", ".4f", "W"), "fmep": ("FMEP", ".4f", "kPa")}
    reached = [
        f"{shown[q][0]} {fit.value_of(q):{shown[q][1]}} {shown[q][2]} (target {v:g} {shown[q][2]})"
        for q, v in fit.targets.items()
    ]
    tail = f"correlation of fitted inputs {corr:+.3f}" if len(fit.fitted) > 1 else "one fitted input"
    print(f"chosen: {fit.values()}\n  {', '.join(reached)}, {tail}")
    print(f"written {path}")
    return 0


def _cmd_validate(args: argparse.Namespace) -> int:
    from .validate import validate

    _output_folder("--out", Path(args.out))
    print(f"written {validate(args.root, args.out)}")
    return 0


def _cmd_readings(args: argparse.Namespace) -> int:
    from .readings.cli import run_args

    return run_args(args)


def _cmd_optimise(args: argparse.Namespace) -> int:
    import functools
    import signal

    from .executor import Executor, check_where
    from .study import run_study, summary

    def terminate(signum, frame):  # a batch system's SIGTERM: save finished runs, then stop
        raise KeyboardInterrupt(f"signal {signum}")

    check_where(args.scheduler, args.serial)
    if args.out is not None:
        _output_folder("--out", Path(args.out))
    signal.signal(signal.SIGTERM, terminate)
    args.interrupt_note = "; finished work is saved (run the same command to resume)"
    # the executor made once the deck and study file are checked (a Dask cluster starts then)
    where = functools.partial(Executor, scheduler=args.scheduler, workers=args.workers, serial=args.serial)
    study = run_study(
        args.study,
        args.out,
        executor=where,
        with_direct=args.direct,
        progress=not args.quiet,
        restart=args.restart,
    )
    if not args.quiet:
        print(summary(study))
    print(f"written {study.path}, report.md, Pareto CSV and figures in {study.path.parent}")
    return 0
