"""Synthetic in-cylinder gas-pressure traces for any engine.

The single-zone model (volume, Wiebe heat release, closed cycle, wall heat, the shipped
presets) is :mod:`ringlube.gas.model`; trace files, figures and the ``ringlube gas`` command
are :mod:`ringlube.gas.traces`. Their public names are all here: ``ringlube.gas.GasModel``,
``ringlube.gas.trace``, ``ringlube.gas.read_csv``, ...
"""

from .model import (
    CRF450R,
    HEAT_TRANSFER,
    LIMITS,
    PRESETS,
    R_AIR,
    GasModel,
    burn_angles,
    heat_released,
    heat_transfer_coefficient,
    imep,
    limits,
    load_solution,
    range_problem,
    trace,
    wall_heat,
)
from .traces import (
    COMBUSTION_OPTIONS,
    OPTIONS,
    check_trace,
    command,
    describe,
    figure,
    header,
    main,
    read_csv,
    write_csv,
    write_presets,
    write_trace,
)

__all__ = [
    "GasModel",
    "PRESETS",
    "CRF450R",
    "R_AIR",
    "LIMITS",
    "HEAT_TRANSFER",
    "limits",
    "range_problem",
    "trace",
    "imep",
    "heat_released",
    "heat_transfer_coefficient",
    "load_solution",
    "wall_heat",
    "burn_angles",
    "OPTIONS",
    "COMBUSTION_OPTIONS",
    "describe",
    "check_trace",
    "header",
    "command",
    "write_csv",
    "write_trace",
    "write_presets",
    "read_csv",
    "figure",
    "main",
]
