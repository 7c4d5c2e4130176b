"""ringlube: mixed-lubrication solver and design optimiser for piston compression rings.

The pipeline reads case -> run -> (sample -> fit -> optimise) -> plot:

>>> import ringlube
>>> case = ringlube.Case.from_namelist("inputs/crf450r_4000rpm_full_cold.nml")
>>> result = ringlube.run(case.with_ring(crown_offset=+60e-6))
>>> result.energy_loss, result.mixed_share, result.ring_mass  # doctest: +SKIP
"""

from . import gas
from ._version import __version__, kernel_id
from .case import GROUPS, Case
from .case_kernel import UnusedInputWarning
from .case_origins import SourceEngineDefaultWarning
from .errors import InputError, NotConvergedError, RinglubeError
from .result import Comparison, CycleResult, compare, load
from .solve import BatchError, run, run_designs, run_many

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
    "run",
    "run_designs",
    "run_many",
    "__version__",
    "kernel_id",
]
