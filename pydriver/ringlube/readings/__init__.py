"""Calibration of every reading of the open modelling choices: each film model crossed with
the contact area and the tension unit, its uncertain inputs fitted to the cold case.

What a reading is and how a point of it is scored (:mod:`ringlube.readings.reading`), the fit
of one reading and of all (:mod:`ringlube.readings.fit`), the report
(:mod:`ringlube.readings.report`) and ``ringlube readings`` (:mod:`ringlube.readings.cli`).
"""

from .fit import calibrate_readings, fit_reading
from .reading import Reading, all_readings, select_readings
from .report import write_readings

__all__ = [
    "Reading",
    "all_readings",
    "select_readings",
    "fit_reading",
    "calibrate_readings",
    "write_readings",
]
