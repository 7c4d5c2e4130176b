"""ringlube: mixed-lubrication solver and design optimiser for piston compression rings.

The pipeline reads case -> run -> (sample -> fit -> optimise) -> plot:

>>> import ringlube
>>> case = ringlube.Case.from_namelist("inputs/crf450r_4000rpm_full_cold.nml")
>>> result = ringlube.run(case.with_ring(crown_offset=+60e-6))
>>> result.energy_loss, result.mixed_share, result.ring_mass  # doctest: +SKIP
"""

import os as _os
import sys as _sys


def _interrupted_at_start(kind, value, tb, _previous=_sys.excepthook):
    """The ``ringlube`` command: a Ctrl-C while it starts (importing numpy, scipy, the
    kernel) ends as one during its work, in one line and exit 130, not a traceback."""
    if issubclass(kind, KeyboardInterrupt):
        print("ringlube: interrupted", file=_sys.stderr, flush=True)
        _os._exit(130)
    _previous(kind, value, tb)


# the command's start: its script 'ringlube', or `python -m ringlube.cli` (argv[0] is '-m'
# while the package is imported)
if _os.path.basename(_sys.argv[0] if _sys.argv else "") in ("ringlube", "-m"):
    _sys.excepthook = _interrupted_at_start

from . import gas, oil  # noqa: E402
from ._version import __version__, kernel_id  # noqa: E402
from .case import GROUPS, Case  # noqa: E402
from .case_kernel import UnusedInputWarning  # noqa: E402
from .case_origins import SourceEngineDefaultWarning  # noqa: E402
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
