"""Calibration of every reading of the open modelling choices.

The command ``ringlube readings``: fit every reading on the cold case and write
docs/readings.md (the score in :mod:`ringlube.readings`, the optimiser in
:mod:`ringlube.readings.fit`, the report in :mod:`ringlube.readings.report`).

    ringlube readings [--out docs/readings.md] [--readings ID ...] [--evals 60] [--quick]
"""

from __future__ import annotations

import time

from ..errors import InputError
from ..outputs import check_output
from .fit import calibrate_readings
from .reading import EVALS, all_readings, select_readings
from .report import write_readings

__all__ = ["add_arguments", "run_args", "main"]


def add_arguments(ap) -> None:
    """The options of ``ringlube readings`` (shared with the ``ringlube`` command).

    Parameters
    ----------
    ap : argparse.ArgumentParser

    Examples
    --------
    >>> import argparse
    >>> ap = argparse.ArgumentParser(); add_arguments(ap)
    >>> ap.parse_args(["--quick"]).quick
    True
    """
    ap.add_argument("--out", default="docs/readings.md", help="Markdown file written")
    ap.add_argument(
        "--readings",
        nargs="+",
        metavar="ID",
        help="fit only these readings (ids like 'jfo-starved/lumped/N/m'; shell wildcards allowed)",
    )
    ap.add_argument(
        "--evals", type=int, default=EVALS, help="most points per reading the optimiser evaluates"
    )
    ap.add_argument("--workers", type=int, default=2, help="worker processes")
    ap.add_argument("--relax", type=int, default=2, help="re-fit the best N readings with relaxed bounds")
    ap.add_argument(
        "--quick",
        action="store_true",
        help="coarse numerics, at most 10 points, no relaxed re-fit: a smoke test",
    )
    ap.add_argument("--list", action="store_true", help="list the reading ids and stop")


def run_args(args) -> int:
    """Run ``ringlube readings`` with parsed arguments.

    Parameters
    ----------
    args : argparse.Namespace
        From a parser given :func:`add_arguments`.

    Returns
    -------
    int
        Exit status.

    Raises
    ------
    InputError
        For an unknown reading or a bad number.

    Examples
    --------
    >>> import argparse
    >>> ap = argparse.ArgumentParser(); add_arguments(ap)
    >>> run_args(ap.parse_args(["--list"]))  # doctest: +ELLIPSIS
    swift-stieber/lumped/N/m
    ...
    0
    """
    if args.list:
        print("\n".join(r.id for r in all_readings()))
        return 0
    if args.evals < 1 or args.workers < 1 or args.relax < 0:
        raise InputError("--evals and --workers must be at least 1, --relax at least 0")
    readings = select_readings(args.readings)
    check_output(args.out, option="--out")  # before hours of fits, not after
    budget = min(args.evals, 10) if args.quick else args.evals
    relax = 0 if args.quick else args.relax
    t0 = time.perf_counter()
    out = calibrate_readings(readings, budget=budget, quick=args.quick, workers=args.workers, relax=relax)
    cmd = "ringlube readings"
    if args.readings:
        cmd += " --readings " + " ".join(args.readings)
    if args.quick:
        cmd += " --quick"
    elif args.evals != EVALS:
        cmd += f" --evals {args.evals}"
    if args.relax != 2 and not args.quick:
        cmd += f" --relax {args.relax}"
    if args.workers != 2:
        cmd += f" --workers {args.workers}"
    print(f"written {write_readings(out, args.out, cmd, time.perf_counter() - t0)}")
    return 0


def main(argv: list[str] | None = None) -> int:
    """``ringlube readings``: fit every reading and write the report.

    Parameters
    ----------
    argv : list of str, optional

    Returns
    -------
    int

    Examples
    --------
    >>> main(["--out", "docs/readings.md"])  # doctest: +SKIP
    0
    """
    import argparse
    import sys

    ap = argparse.ArgumentParser(prog="ringlube readings", description=__doc__.splitlines()[0])
    add_arguments(ap)
    args = ap.parse_args(argv)
    try:
        return run_args(args)
    except InputError as exc:
        print(f"ringlube readings: error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":  # pragma: no cover
    raise SystemExit(main())
