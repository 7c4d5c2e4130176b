"""Calibration of the uncertain inputs (``ringlube calibrate``).

The one calibrator, which fits bounded inputs to targets (:mod:`ringlube.calibrate.calibrator`,
also that of ``ringlube readings``), and the calibration of the shipped decks against the
cold Table 2 case with it (:mod:`ringlube.calibrate.cold`).
"""

from .calibrator import METHODS, Param, calibrate_inputs, start_design
from .cold import (
    BOUNDS,
    DISCRETE,
    FITTED,
    FRICTION,
    GOAL,
    NOMINAL,
    PARAMS,
    Fit,
    apply,
    calibrate,
    choose,
    cold_targets,
    correlation,
    strip_calibrated,
    write_calibration,
)

__all__ = [
    "FITTED",
    "GOAL",
    "FRICTION",
    "BOUNDS",
    "NOMINAL",
    "PARAMS",
    "DISCRETE",
    "Fit",
    "calibrate",
    "write_calibration",
    "cold_targets",
    "apply",
    "choose",
    "correlation",
    "strip_calibrated",
    "Param",
    "start_design",
    "calibrate_inputs",
    "METHODS",
]
