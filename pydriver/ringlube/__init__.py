"""ringlube: mixed-lubrication solver and design optimiser for piston compression rings.

The pipeline reads case -> run -> (sample -> fit -> optimise) -> plot:

>>> import ringlube
>>> case = ringlube.Case.from_namelist("inputs/crf450r_4000rpm_full_cold.nml")
>>> result = ringlube.run(case.with_ring(crown_offset=+60e-6))
>>> result.energy_loss, result.mixed_share, result.ring_mass  # doctest: +SKIP
"""

import os as _os
import sys as _sys

# The kernel's OpenMP threads (`&numerics threads`: a distorted bore's sectors) wait for work
# asleep: with libgomp's default a thread that waits spins for a while first, and on a machine
# whose cores are taken (a study's workers) the spinning threads take the cores from the ones
# with work: two threads ran 10-16 times slower than one (docs/performance.md). libgomp reads
# the variable once, when the kernel's library loads, so it is set here, before any import of
# the kernel; a value the user set is kept.
_os.environ.setdefault("OMP_WAIT_POLICY", "PASSIVE")


def _interrupted_at_start(signum, frame):
    """The ``ringlube`` command's SIGINT handler while it starts (importing numpy, scipy, the
    kernel): a Ctrl-C ends it at once, in one line and exit 130, as during its work. Not a
    KeyboardInterrupt: raised inside a C extension's import it can come out as another error
    (numpy's 'PyCapsule_Import could not import module "datetime"', an ImportError traceback
    and exit 1). Nothing is written yet; :func:`ringlube.cli.main` puts Python's handler back
    (:func:`_started`), so that a Ctrl-C during the work stops the kernel within a step and
    removes its temporary files."""
    _os.write(2, b"ringlube: interrupted\n")
    _os._exit(130)


def _started() -> None:
    """The command has started: Python's own SIGINT handler (KeyboardInterrupt) again."""
    import signal

    try:
        if signal.getsignal(signal.SIGINT) is _interrupted_at_start:
            signal.signal(signal.SIGINT, signal.default_int_handler)
    except ValueError:  # (not the main thread: nothing was set)
        pass


def _is_the_command() -> bool:
    """Is this the ``ringlube`` command starting: its script ``ringlube`` as the interpreter
    ran it, or ``python -m ringlube.cli``? (Not a worker process a study spawned: it inherits
    the command's ``sys.argv`` but the interpreter ran other code, ``sys.orig_argv``.)"""
    argv = getattr(_sys, "orig_argv", [])
    module = argv[argv.index("-m") + 1] if "-m" in argv[:-1] else ""
    script = _sys.argv[0] if _sys.argv else ""
    return module == "ringlube.cli" or (_os.path.basename(script) == "ringlube" and script in argv)


if _is_the_command():
    import signal as _signal

    try:
        # (a command started with SIGINT ignored, in the background or a study's worker, keeps it)
        if _signal.getsignal(_signal.SIGINT) is _signal.default_int_handler:
            _signal.signal(_signal.SIGINT, _interrupted_at_start)
    except ValueError:  # (imported from another thread)
        pass

from . import gas, oil  # noqa: E402
from ._version import __version__, kernel_id  # noqa: E402
from .case import GROUPS, Case  # noqa: E402
from .case.kernel import UnusedInputWarning  # noqa: E402
from .case.origins import SourceEngineDefaultWarning  # noqa: E402
from .errors import InputError, NotConvergedError, RinglubeError  # noqa: E402
from .result import Comparison, CycleResult, compare, load  # noqa: E402
from .solve import BatchError, run, run_designs, run_many  # noqa: E402

__all__ = [
    "BatchError",
    "Case",
    "GROUPS",
    "Comparison",
    "CycleResult",
    "compare",
    "InputError",
    "NotConvergedError",
    "RinglubeError",
    "SourceEngineDefaultWarning",
    "UnusedInputWarning",
    "gas",
    "load",
    "oil",
    "run",
    "run_designs",
    "run_many",
    "__version__",
    "kernel_id",
]
