"""Design studies: sample -> run -> fit -> NSGA-II -> check (``ringlube optimise``).

:func:`run_study` runs a study deck (:mod:`ringlube.study.pipeline`). Its stages:
:mod:`~ringlube.study.runs` (sample, run), :mod:`~ringlube.study.surfaces` (fit),
:mod:`~ringlube.study.optimise` (NSGA-II on the surfaces), :mod:`~ringlube.study.check`
(the chosen designs re-simulated), :mod:`~ringlube.study.sure` (how sure the answer is),
:mod:`~ringlube.study.direct` (NSGA-II on the true model); the pymoo problems of both NSGA-IIs
are :mod:`~ringlube.study.problems`. What they use: the deck
(:mod:`~ringlube.study.table`, :mod:`~ringlube.study.deck`, :mod:`~ringlube.study.settings`,
:mod:`~ringlube.study.variables`, :mod:`~ringlube.study.constraints`), the constraints applied
to the designs (:mod:`~ringlube.study.bounds`), the study file
(:mod:`~ringlube.study.state`, :mod:`~ringlube.study.state_checks`, :mod:`~ringlube.study.h5`,
:mod:`~ringlube.study.layout`, :mod:`~ringlube.study.store`), the quadratic surfaces
(:mod:`~ringlube.study.surrogate`) and what a study writes (:mod:`~ringlube.study.format`,
:mod:`~ringlube.study.summary`, :mod:`~ringlube.study.report`, :mod:`~ringlube.study.pareto`,
:mod:`~ringlube.study.figures`, :mod:`~ringlube.study.plots`).
"""

from .deck import read_study
from .pipeline import run_study
from .settings import StudySettings
from .store import Study
from .summary import summary

__all__ = ["run_study", "read_study", "StudySettings", "Study", "summary"]
