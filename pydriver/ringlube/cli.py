"""The ``ringlube`` command."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from .errors import RinglubeError

__all__ = ["main"]


def _cmd_run(args: argparse.Namespace) -> int:
    from .case import Case
    from .solve import run

    case = Case.from_namelist(args.deck)
    result = run(case)
    out = Path(args.output) if args.output else Path(
        case.get("output", "file") or Path(args.deck).with_suffix(".h5"))
    result.to_hdf5(out)
    print(f"{args.deck}: {result.summary()}\nwritten {out}")
    return 0 if result.converged else 3


def _cmd_plot(args: argparse.Namespace) -> int:
    from .plot import plot_results
    from .result import load

    results = [load(p) for p in args.results]
    if args.labels:
        for r, label in zip(results, args.labels.split(",")):
            r.label = label
    for f in plot_results(results, args.output):
        print(f"written {f}")
    return 0


def _cmd_gas(args: argparse.Namespace) -> int:
    from . import gas

    gas.main(["--out", args.out, *args.names])
    return 0


def _cmd_convergence(args: argparse.Namespace) -> int:
    from .convergence import convergence_study, write_report

    command = "ringlube convergence " + " ".join(
        [*args.decks, *(["--quick"] if args.quick else []), "--out", args.out])
    for deck in args.decks:
        reference, rows = convergence_study(deck, quick=args.quick, repeats=args.repeats)
        for f in write_report(deck, reference, rows, args.out, command):
            print(f"written {f}")
    return 0


def _cmd_calibrate(args: argparse.Namespace) -> int:
    from .calibrate import calibrate, correlation, strip_calibrated, write_calibration
    from .case import Case

    fit, fits = calibrate(args.deck)
    base = strip_calibrated(Case.from_namelist(args.deck))
    jac, corr = correlation(base, fit)
    path = write_calibration(args.out, fit, fits, jac, corr, args.deck)
    print(f"chosen: {fit.values()}\n  energy {fit.energy_loss:.4f} J (target 1.92), mixed "
          f"{fit.mixed_share:.3f} % (target 8.47), correlation of fitted inputs {corr:+.3f}")
    print(f"written {path}")
    return 0


def _cmd_validate(args: argparse.Namespace) -> int:
    from .validate import validate

    print(f"written {validate(args.root, args.out)}")
    return 0


def _cmd_optimise(args: argparse.Namespace) -> int:
    import signal

    from .study import run_study
    from .study_report import summary

    def terminate(signum, frame):  # a batch system's SIGTERM: save finished runs, then stop
        raise KeyboardInterrupt(f"signal {signum}")

    signal.signal(signal.SIGTERM, terminate)

    study = run_study(args.study, args.out, scheduler=args.scheduler, workers=args.workers,
                      serial=args.serial, with_direct=args.direct)
    print(summary(study))
    print(f"written {study.path} and figures in {study.path.parent}")
    return 0


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="ringlube", description="Piston ring mixed-lubrication "
                                 "solver and design optimiser.")
    sub = ap.add_subparsers(dest="command", required=True)
    p = sub.add_parser("run", help="run one deck (same numbers as ringlube-solve)")
    p.add_argument("deck")
    p.add_argument("-o", "--output", help="result file (default: the deck's &output file)")
    p.set_defaults(func=_cmd_run)
    p = sub.add_parser("plot", help="friction and film plots of one or more results")
    p.add_argument("results", nargs="+")
    p.add_argument("-o", "--output", default=".", help="output folder")
    p.add_argument("--labels", help="comma-separated legend labels")
    p.set_defaults(func=_cmd_plot)
    p = sub.add_parser("gas", help="regenerate the synthetic gas-pressure traces")
    p.add_argument("--out", default="inputs/pressure")
    p.add_argument("names", nargs="*")
    p.set_defaults(func=_cmd_gas)
    p = sub.add_parser("convergence", help="speed against accuracy over numerical settings")
    p.add_argument("decks", nargs="+")
    p.add_argument("--out", default="out/convergence", help="output folder")
    p.add_argument("--quick", action="store_true", help="shorter ladders (no 801/1601 nodes)")
    p.add_argument("--repeats", type=int, default=3, help="timing repeats per setting (best kept)")
    p.set_defaults(func=_cmd_convergence)
    p = sub.add_parser("calibrate", help="fit the uncertain inputs to the cold Table 2 case")
    p.add_argument("deck", nargs="?", default="inputs/crf450r_4000rpm_full_cold.nml")
    p.add_argument("--out", default="inputs/calibration.nml")
    p.set_defaults(func=_cmd_calibrate)
    p = sub.add_parser("validate", help="regenerate docs/validation.md against the study's Table 2")
    p.add_argument("--root", default=".", help="project folder (with inputs/)")
    p.add_argument("--out", default="docs", help="output folder")
    p.set_defaults(func=_cmd_validate)
    p = sub.add_parser("optimise", help="DOE, quadratic surfaces and NSGA-II from a &study deck")
    p.add_argument("study")
    p.add_argument("--out", help="output folder (default out/NAME); an existing study there is resumed")
    p.add_argument("--scheduler", help="address of an existing Dask scheduler (default: LocalCluster)")
    p.add_argument("--workers", type=int, help="LocalCluster workers (default: one per core)")
    p.add_argument("--serial", action="store_true", help="no Dask: run everything in this process")
    p.add_argument("--direct", action="store_true", help="also NSGA-II on the true model, and compare")
    p.set_defaults(func=_cmd_optimise)
    args = ap.parse_args(argv)
    try:
        return args.func(args)
    except RinglubeError as exc:
        print(f"ringlube: error: {exc}", file=sys.stderr)
        return exc.code
    except KeyboardInterrupt:
        print("ringlube: interrupted; finished work is saved (run the same command to resume)",
              file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
