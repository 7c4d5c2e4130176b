"""The ``ringlube`` command.

Every user mistake ends in one line on stderr, ``ringlube: error: ...`` naming the file,
option or variable, and exit status 2 (bad input) or 1 (runtime error); a run that did not
converge exits 3; Ctrl-C exits 130.
"""

from __future__ import annotations

import os
import sys

from . import _started
from .cli_parser import _parser
from .errors import RinglubeError

__all__ = ["main"]


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
    args = None
    try:
        # Building the parser imports most of the package (scipy among it): a Ctrl-C there
        # stays with the start-up handler (one line, exit 130), since a KeyboardInterrupt
        # raised inside a C extension's import can come out as an ImportError traceback or
        # kill the interpreter at exit. Parsing writes nothing.
        args = _parser().parse_args(argv)
        _one_line_warnings()
        _started()  # a Ctrl-C from here on is a KeyboardInterrupt (ended in one line below)
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


def _one_line_warnings() -> None:
    """Source-engine-default, unused-input and unconverged-reference warnings as one line on
    stderr: ``ringlube: warning: ...`` (the kernel's message names the deck, not ringlube's
    source)."""
    import warnings

    from .case.kernel import UnusedInputWarning
    from .case.origins import SourceEngineDefaultWarning
    from .study.bounds import UnconvergedReferenceWarning

    show = warnings.showwarning
    if getattr(show, "_ringlube", False):
        return

    def one_line(message, category, filename, lineno, file=None, line=None):
        one = (SourceEngineDefaultWarning, UnusedInputWarning, UnconvergedReferenceWarning)
        if issubclass(category, one):
            print(f"ringlube: warning: {message}", file=sys.stderr)
        else:
            show(message, category, filename, lineno, file, line)

    one_line._ringlube = True
    warnings.showwarning = one_line


def _one_line(exc: BaseException) -> str:
    text = " ".join(str(exc).split("\n")).strip()
    return text or type(exc).__name__


if __name__ == "__main__":
    sys.exit(main())
