"""ringlube: mixed-lubrication solver and design optimiser for piston compression rings.

The pipeline reads case -> run -> (sample -> fit -> optimise) -> plot:

>>> import ringlube
>>> case = ringlube.Case.from_namelist("inputs/crf450r_4000rpm_full_cold.nml")
>>> result = ringlube.run(case.with_ring(crown_offset=+60e-6))
>>> result.energy_loss, result.mixed_share, result.ring_mass
"""

from .case import GROUPS, Case
from .errors import InputError, NotConvergedError, RinglubeError
from .result import CycleResult, load
from . import gas
from .solve import run, run_many

__version__ = "0.1.0"
__all__ = ["Case", "GROUPS", "CycleResult", "InputError", "NotConvergedError", "RinglubeError",
           "load", "run", "run_many", "__version__"]
