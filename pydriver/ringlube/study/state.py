"""The state of a design study as typed records.

Per case (base deck label, or ``scene``) a :class:`CaseState`: the true-model :class:`Runs`,
the fitted :class:`~ringlube.study.surrogate.QuadraticSurface` of each result, the GA repeats, the
merged :class:`Front`, and the records of the true-model checks
(:mod:`ringlube.study.state_checks`: the chosen and reference designs re-simulated, how sure
the answer is, the direct NSGA-II and its checkpoints). Each record writes itself into an
HDF5 group (``to_h5(group, s)``: into an empty group, every matrix labelled with the
columns' names and units from the study settings ``s``) and reads itself back
(``from_h5(group)``) beside its fields;
:mod:`ringlube.study.layout` composes them into a case of the study file and
:class:`~ringlube.study.store.Study` holds them.
"""

from __future__ import annotations

import dataclasses

import h5py
import numpy as np

from .h5 import put, put_strings, strings
from .settings import StudySettings
from .state_checks import Checked, Direct, DirectGeneration, Dominating, Sure
from .surrogate import QuadraticSurface
from .variables import OUTPUTS, output_units

__all__ = ["CaseState", "Runs", "Front"]


@dataclasses.dataclass
class Runs:
    """True-model runs of every sample on one case.

    Attributes
    ----------
    outputs : ndarray, shape (n, len(OUTPUTS))
        Every scalar result (:data:`~ringlube.study.variables.OUTPUTS`); NaN until run or
        when the run failed.
    done, converged, failed : ndarray of bool, shape (n,)
        Run (or failed), converged, failed with an error (an invalid design).
    errors : list of str
        The error message of each failed run ("" otherwise).
    wall_s : float
        Wall time spent on these runs, over every session of the study.

    Example
    -------
    >>> r = Runs.empty(3)
    >>> r.done.any(), r.usable().sum()
    (np.False_, np.int64(0))
    """

    outputs: np.ndarray
    done: np.ndarray
    converged: np.ndarray
    failed: np.ndarray
    errors: list[str]
    wall_s: float = 0.0

    @classmethod
    def empty(cls, n: int, k: int = len(OUTPUTS)) -> Runs:
        """Runs of ``n`` samples, none done.

        Parameters
        ----------
        n : int
            Number of samples.
        k : int
            Number of results recorded per sample (the study's outputs).

        Returns
        -------
        Runs

        Example
        -------
        >>> Runs.empty(2).outputs.shape[0]
        2
        """
        return cls(
            np.full((n, k), np.nan),
            np.zeros(n, bool),
            np.zeros(n, bool),
            np.zeros(n, bool),
            [""] * n,
        )

    def usable(self) -> np.ndarray:
        """Samples that ran, converged and did not fail (those the surfaces are fitted to).

        Returns
        -------
        ndarray of bool

        Example
        -------
        >>> Runs.empty(2).usable().tolist()
        [False, False]
        """
        return self.done & self.converged & ~self.failed

    def to_h5(self, group: h5py.Group, s: StudySettings) -> None:
        """Write the runs into the empty ``group`` (e.g. ``/cases/LABEL/runs``), every
        matrix labelled (``columns``, ``units``).

        Example
        -------
        >>> s = StudySettings("s", ["a.nml"], ["c"], [1.0], ["width"], [0.0], [1.0],
        ...                   ["energy_loss"], units=["m"])
        >>> with h5py.File("x.h5", "w", driver="core", backing_store=False) as f:
        ...     Runs.empty(2).to_h5(f.create_group("runs"), s)
        ...     Runs.from_h5(f["runs"]).done.tolist()
        [False, False]
        """
        units = output_units()
        put(group, "outputs", self.outputs, list(s.outputs), [units[o] for o in s.outputs])
        for k in ("done", "converged", "failed"):
            group.create_dataset(k, data=getattr(self, k))
        put_strings(group, "errors", self.errors)
        group.attrs["wall_s"] = self.wall_s

    @classmethod
    def from_h5(cls, group: h5py.Group) -> Runs:
        """The runs :meth:`to_h5` wrote into ``group`` (e.g. ``/cases/cold/runs``)."""
        return cls(
            group["outputs"][()],
            group["done"][()].astype(bool),
            group["converged"][()].astype(bool),
            group["failed"][()].astype(bool),
            strings(group["errors"]),
            float(group.attrs["wall_s"]),
        )


@dataclasses.dataclass
class Front:
    """The merged non-dominated set of the GA repeats on the surfaces.

    Attributes
    ----------
    x : ndarray, shape (k, d)
        Designs.
    f : ndarray, shape (k, len(objectives))
        Their objectives as the surfaces predict them.
    hv, hv_repeats, hv_ratio_mean, hv_ratio_min : float or ndarray
        Hypervolume of the merged set and of each repeat, and the repeats' ratios to it.
    ref, lo : ndarray
        Reference point and ideal corner of the normalised hypervolume.

    Example
    -------
    >>> Front(np.zeros((1, 2)), np.zeros((1, 2)), 1.0, np.ones(1), 1.0, 1.0,
    ...       np.ones(2), np.zeros(2)).x.shape
    (1, 2)
    """

    x: np.ndarray
    f: np.ndarray
    hv: float
    hv_repeats: np.ndarray
    hv_ratio_mean: float
    hv_ratio_min: float
    ref: np.ndarray
    lo: np.ndarray

    def to_h5(self, group: h5py.Group, s: StudySettings) -> None:
        """Write the front into the empty ``group`` (e.g. ``/cases/LABEL/front``), every
        matrix labelled (``columns``, ``units``).

        Example
        -------
        >>> s = StudySettings("s", ["a.nml"], ["c"], [1.0], ["width"], [0.0], [1.0],
        ...                   ["energy_loss"], units=["m"])
        >>> with h5py.File("x.h5", "w", driver="core", backing_store=False) as f:
        ...     Front(np.zeros((1, 1)), np.zeros((1, 1)), 1.0, np.ones(1), 1.0, 1.0, np.ones(1),
        ...           np.zeros(1)).to_h5(f.create_group("front"), s)
        ...     Front.from_h5(f["front"]).hv
        1.0
        """
        units = output_units()
        obj_units = [units[o] for o in s.objectives]
        put(group, "x", self.x, s.variables, s.units)
        put(group, "f", self.f, s.objectives, obj_units)
        put(group, "hv_repeats", self.hv_repeats)
        put(group, "ref", self.ref, s.objectives, obj_units)
        put(group, "lo", self.lo, s.objectives, obj_units)
        for k in ("hv", "hv_ratio_mean", "hv_ratio_min"):
            group.attrs[k] = getattr(self, k)

    @classmethod
    def from_h5(cls, group: h5py.Group) -> Front:
        """The front :meth:`to_h5` wrote into ``group`` (e.g. ``/cases/cold/front``)."""
        return cls(
            group["x"][()],
            group["f"][()],
            float(group.attrs["hv"]),
            group["hv_repeats"][()],
            float(group.attrs["hv_ratio_mean"]),
            float(group.attrs["hv_ratio_min"]),
            group["ref"][()],
            group["lo"][()],
        )


@dataclasses.dataclass
class CaseState:
    """Everything a study computed for one case (or the weighted scene).

    Example
    -------
    >>> CaseState(Runs.empty(4)).front is None
    True
    """

    runs: Runs
    surfaces: dict[str, QuadraticSurface] = dataclasses.field(default_factory=dict)
    repeats: dict[int, tuple[np.ndarray, np.ndarray]] = dataclasses.field(default_factory=dict)
    front: Front | None = None
    #: the front's designs re-simulated to choose from (study_check.candidate_designs)
    candidates: Checked | None = None
    chosen: Checked | None = None
    reference: Checked | None = None
    #: the good samples that dominate a chosen design by the true model (check.dominating_samples)
    dominating: Dominating | None = None
    direct: Direct | None = None
    direct_generations: list[DirectGeneration] = dataclasses.field(default_factory=list)
    sure: Sure | None = None
