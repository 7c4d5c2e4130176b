"""The records of a study's true-model checks, each written and read beside its fields
(``to_h5``/``from_h5`` as in :mod:`ringlube.study.state`).

The designs chosen on the surrogate front and the reference re-simulated (:class:`Checked`),
the study's own samples that dominate a chosen design by the true model (:class:`Dominating`),
how sure the answer is (:class:`Sure`), and the direct NSGA-II on the true model
(:class:`Direct`) with its per-generation checkpoints (:class:`DirectGeneration`). They are
part of a case's :class:`~ringlube.study.state.CaseState`; :mod:`ringlube.study.layout`
places them in the study file (``chosen``, ``reference``, ``dominating``, ``sure``, ``direct``,
``direct_generations/gK``).
"""

from __future__ import annotations

import dataclasses

import h5py
import numpy as np

from .h5 import put, put_strings, strings, text
from .settings import StudySettings
from .variables import output_units

__all__ = ["Checked", "Dominating", "Sure", "Direct", "DirectGeneration"]


@dataclasses.dataclass
class Checked:
    """Designs re-simulated with the true model, beside the surfaces' predictions.

    Attributes
    ----------
    names : list of str
        What each design is (``min energy_loss``, ``knee``, ``reference``).
    x : ndarray, shape (k, d)
        The designs.
    f_true, f_surrogate : ndarray, shape (k, len(OUTPUTS))
        Every result from the true model (NaN if it failed) and from the surfaces.
    converged : ndarray of bool
        Whether each true-model run converged.
    errors : list of str
        Error of each failed run ("" otherwise).
    points : dict of str to ndarray, optional
        The true results at each operating point (case label -> shape (k, len(OUTPUTS))):
        the scene's designs, and the chosen designs of a case re-run at the other points, so
        that every point's constraints can be checked (None: not run there).

    Example
    -------
    >>> c = Checked(["knee"], np.zeros((1, 1)), np.ones((1, 5)), np.ones((1, 5)) * 1.5,
    ...             np.ones(1, bool), [""])
    >>> float(c.rel_error[0, 0])
    0.5
    """

    names: list[str]
    x: np.ndarray
    f_true: np.ndarray
    f_surrogate: np.ndarray
    converged: np.ndarray
    errors: list[str]
    points: dict[str, np.ndarray] | None = None

    def rows(self, rows: list[int]) -> Checked:
        """The designs ``rows`` alone (with their results at every point).

        Example
        -------
        >>> Checked(["a", "b"], np.zeros((2, 1)), np.ones((2, 5)), np.ones((2, 5)), np.ones(2, bool),
        ...         ["", ""]).rows([1]).names
        ['b']
        """
        return Checked(
            [self.names[i] for i in rows],
            np.asarray(self.x)[rows],
            np.atleast_2d(self.f_true)[rows],
            np.atleast_2d(self.f_surrogate)[rows],
            np.asarray(self.converged, bool)[rows],
            [self.errors[i] for i in rows],
            None if self.points is None else {p: np.atleast_2d(v)[rows] for p, v in self.points.items()},
        )

    @property
    def rel_error(self) -> np.ndarray:
        """Surrogate error relative to the true model, ``(surrogate - true) / |true|``.

        Returns
        -------
        ndarray

        Example
        -------
        >>> Checked([], np.zeros((0, 1)), np.ones((0, 5)), np.ones((0, 5)), np.ones(0, bool),
        ...         []).rel_error.shape
        (0, 5)
        """
        with np.errstate(divide="ignore", invalid="ignore"):
            return (self.f_surrogate - self.f_true) / np.abs(self.f_true)

    def to_h5(self, group: h5py.Group, s: StudySettings) -> None:
        """Write the designs, their results and :attr:`rel_error` into the empty ``group``
        (e.g. ``/cases/LABEL/chosen`` or ``reference``), every matrix labelled (``columns``,
        ``units``).

        Example
        -------
        >>> s = StudySettings("s", ["a.nml"], ["c"], [1.0], ["width"], [0.0], [1.0],
        ...                   ["energy_loss"], units=["m"])
        >>> with h5py.File("x.h5", "w", driver="core", backing_store=False) as f:
        ...     n = len(s.outputs)
        ...     Checked(["knee"], np.zeros((1, 1)), np.ones((1, n)), np.ones((1, n)), np.ones(1, bool),
        ...             [""]).to_h5(f.create_group("chosen"), s)
        ...     Checked.from_h5(f["chosen"]).names
        ['knee']
        """
        units = output_units()
        out_units = [units[o] for o in s.outputs]
        put_strings(group, "names", self.names)
        put(group, "x", self.x, s.variables, s.units)
        put(group, "f_true", self.f_true, list(s.outputs), out_units)
        put(group, "f_surrogate", self.f_surrogate, list(s.outputs), out_units)
        put(group, "rel_error", self.rel_error, list(s.outputs), ["1"] * len(s.outputs))
        group.create_dataset("converged", data=self.converged)
        put_strings(group, "errors", self.errors)
        for point, values in (self.points or {}).items():
            put(group, f"points/{point}", values, list(s.outputs), out_units)

    @classmethod
    def from_h5(cls, group: h5py.Group) -> Checked:
        """The re-simulated designs :meth:`to_h5` wrote into ``group`` (e.g. ``/cases/cold/chosen``)."""
        return cls(
            strings(group["names"]),
            group["x"][()],
            group["f_true"][()],
            group["f_surrogate"][()],
            group["converged"][()].astype(bool),
            strings(group["errors"]),
            {p: v[()] for p, v in group["points"].items()} if "points" in group else None,
        )


@dataclasses.dataclass
class Dominating:
    """The good samples of a case (true-model runs of the design of experiments: converged,
    on the liner, within the constraints) that dominate one of its chosen designs by the true
    model: no worse in every objective and better in at least one, a difference below ``rtol``
    of the larger magnitude counting as a tie
    (:func:`~ringlube.study.check.dominating_samples`). No rows: none does.

    Attributes
    ----------
    chosen : list of str
        The chosen design each row dominates (designs chosen twice, e.g. ``min energy_loss``
        and ``knee`` at one design, named together: ``min energy_loss, knee``).
    sample : ndarray of int
        The dominating sample of each row: its row of ``samples/x`` and ``runs/outputs``.
    x : ndarray, shape (k, d)
        The samples' designs.
    f : ndarray, shape (k, len(objectives))
        The samples' objectives (true model).
    compared : int
        Good samples the chosen designs were compared with.
    rtol : float
        The relative tolerance of a tie.
    not_compared : list of str
        Chosen designs whose own objectives are not all numbers (a failed re-simulation): not
        compared.

    Example
    -------
    >>> d = Dominating(["knee"], np.array([7]), np.zeros((1, 1)), np.ones((1, 2)), 60, 1e-3, [])
    >>> d.rows_of("knee").tolist(), d.rows_of("min energy_loss").tolist()
    ([0], [])
    """

    chosen: list[str]
    sample: np.ndarray
    x: np.ndarray
    f: np.ndarray
    compared: int
    rtol: float
    not_compared: list[str] = dataclasses.field(default_factory=list)

    def rows_of(self, chosen: str) -> np.ndarray:
        """The rows that dominate the chosen design(s) named ``chosen``.

        Parameters
        ----------
        chosen : str

        Returns
        -------
        ndarray of int

        Example
        -------
        >>> Dominating([], np.zeros(0, int), np.zeros((0, 1)), np.zeros((0, 1)), 0, 1e-3).rows_of("knee")
        array([], dtype=int64)
        """
        return np.array([i for i, c in enumerate(self.chosen) if c == chosen], int)

    def to_h5(self, group: h5py.Group, s: StudySettings) -> None:
        """Write the dominating samples into the empty ``group`` (``/cases/LABEL/dominating``),
        every matrix labelled; ``compared`` and ``rtol`` as attributes.

        Example
        -------
        >>> s = StudySettings("s", ["a.nml"], ["c"], [1.0], ["width"], [0.0], [1.0],
        ...                   ["energy_loss"], units=["m"])
        >>> with h5py.File("x.h5", "w", driver="core", backing_store=False) as f:
        ...     Dominating(["knee"], np.array([7]), np.zeros((1, 1)), np.ones((1, 1)), 60, 1e-3,
        ...                []).to_h5(f.create_group("dominating"), s)
        ...     d = Dominating.from_h5(f["dominating"])
        ...     d.chosen, d.sample.tolist(), d.compared, d.rtol
        (['knee'], [7], 60, 0.001)
        """
        units = output_units()
        put_strings(group, "chosen", self.chosen)
        group.create_dataset("sample", data=np.asarray(self.sample, np.int64))
        put(group, "x", np.asarray(self.x).reshape(len(self.sample), len(s.variables)), s.variables, s.units)
        put(
            group,
            "f",
            np.asarray(self.f).reshape(len(self.sample), len(s.objectives)),
            s.objectives,
            [units[o] for o in s.objectives],
        )
        put_strings(group, "not_compared", self.not_compared)
        group.attrs["compared"] = int(self.compared)
        group.attrs["rtol"] = float(self.rtol)

    @classmethod
    def from_h5(cls, group: h5py.Group) -> Dominating:
        """The dominating samples :meth:`to_h5` wrote into ``group`` (``/cases/cold/dominating``)."""
        return cls(
            strings(group["chosen"]),
            group["sample"][()].astype(int),
            group["x"][()],
            group["f"][()],
            int(group.attrs["compared"]),
            float(group.attrs["rtol"]),
            strings(group["not_compared"]),
        )


@dataclasses.dataclass
class Direct:
    """NSGA-II on the true model and its comparison with the surrogate front.

    Attributes
    ----------
    x, f : ndarray
        The direct front (true objectives).
    runs, failed, unconverged, lifted : int
        True-model runs made, how many of them failed, did not converge, or converged with
        the ring lifted off the liner at some crank steps (never in the front).
    wall_s : float
        Wall time.
    hv_direct, hv_surrogate, igd_surrogate_to_direct, igd_direct_to_surrogate : float
        Hypervolumes (common reference) and IGDs in normalised objectives.

    Example
    -------
    >>> Direct(np.zeros((1, 1)), np.zeros((1, 1)), 8, 0.1, 0.5, 0.5, 0.0, 0.0).failed
    0
    """

    x: np.ndarray
    f: np.ndarray
    runs: int
    wall_s: float
    hv_direct: float
    hv_surrogate: float
    igd_surrogate_to_direct: float
    igd_direct_to_surrogate: float
    failed: int = 0
    unconverged: int = 0
    lifted: int = 0

    def to_h5(self, group: h5py.Group, s: StudySettings) -> None:
        """Write the direct front and its figures into the empty ``group`` (e.g.
        ``/cases/LABEL/direct``), every matrix labelled.

        The ``key`` attribute (the direct settings) is written by :mod:`ringlube.study.layout`.

        Example
        -------
        >>> s = StudySettings("s", ["a.nml"], ["c"], [1.0], ["width"], [0.0], [1.0],
        ...                   ["energy_loss"], units=["m"])
        >>> with h5py.File("x.h5", "w", driver="core", backing_store=False) as f:
        ...     Direct(np.zeros((1, 1)), np.zeros((1, 1)), 8, 0.1, 0.5, 0.5, 0.0,
        ...            0.0).to_h5(f.create_group("direct"), s)
        ...     int(Direct.from_h5(f["direct"]).runs)
        8
        """
        units = output_units()
        put(group, "x", self.x, s.variables, s.units)
        put(group, "f", self.f, s.objectives, [units[o] for o in s.objectives])
        for fld in dataclasses.fields(self):
            if fld.name not in ("x", "f"):
                group.attrs[fld.name] = getattr(self, fld.name)

    @classmethod
    def from_h5(cls, group: h5py.Group) -> Direct:
        """The direct comparison :meth:`to_h5` wrote into ``group`` (e.g.
        ``/cases/cold/direct``); attributes it lacks take their defaults."""
        kw = {
            fld.name: group.attrs.get(fld.name, fld.default)
            for fld in dataclasses.fields(cls)
            if fld.name not in ("x", "f")
        }
        return cls(group["x"][()], group["f"][()], **kw)


@dataclasses.dataclass
class DirectGeneration:
    """One generation of the direct NSGA-II, as evaluated (its checkpoint).

    Attributes
    ----------
    x : ndarray, shape (k, d)
        The designs pymoo asked for.
    f : ndarray, shape (k, len(direct_outputs))
        Their true objectives, then the constrained results that are not objectives
        (:meth:`~ringlube.study.settings.StudySettings.direct_outputs`; NaN where the run
        failed).
    converged, failed : ndarray of bool, shape (k,)
        Whether each run converged, and whether the kernel rejected the design.
    wall_s : float
        Wall time of the generation's runs.

    Example
    -------
    >>> DirectGeneration(np.zeros((2, 1)), np.ones((2, 1)), np.ones(2, bool),
    ...                  np.zeros(2, bool), 0.1).x.shape
    (2, 1)
    """

    x: np.ndarray
    f: np.ndarray
    converged: np.ndarray
    failed: np.ndarray
    wall_s: float = 0.0

    def to_h5(self, group: h5py.Group, s: StudySettings) -> None:
        """Write the generation into the empty ``group`` (e.g.
        ``/cases/LABEL/direct_generations/gK``), every matrix labelled (``columns``, ``units``).

        The ``key`` attribute (the direct settings) is written by :mod:`ringlube.study.layout`.

        Example
        -------
        >>> s = StudySettings("s", ["a.nml"], ["c"], [1.0], ["width"], [0.0], [1.0],
        ...                   ["energy_loss"], units=["m"])
        >>> with h5py.File("x.h5", "w", driver="core", backing_store=False) as f:
        ...     DirectGeneration(np.zeros((2, 1)), np.ones((2, 4)), np.ones(2, bool),
        ...                      np.zeros(2, bool), 0.1).to_h5(f.create_group("g0"), s)
        ...     DirectGeneration.from_h5(f["g0"]).wall_s
        0.1
        """
        units = output_units()
        group.attrs["wall_s"] = self.wall_s
        put(group, "x", self.x, s.variables, s.units)
        put(group, "f", self.f, s.direct_outputs(), [units[o] for o in s.direct_outputs()])
        group.create_dataset("converged", data=self.converged)
        group.create_dataset("failed", data=self.failed)

    @classmethod
    def from_h5(cls, group: h5py.Group) -> DirectGeneration:
        """The generation :meth:`to_h5` wrote into ``group`` (e.g. ``/cases/cold/direct_generations/g0``)."""
        return cls(
            group["x"][()],
            group["f"][()],
            group["converged"][()].astype(bool),
            group["failed"][()].astype(bool),
            float(group.attrs["wall_s"]),
        )


@dataclasses.dataclass
class Sure:
    """How sure the chosen designs are: extra true-model runs of them (and the reference).

    Attributes
    ----------
    names : list of str
        The designs (the chosen ones, then ``reference``).
    x : ndarray, shape (k, d)
    nominal : ndarray, shape (k, len(outputs))
        Their results as re-simulated (the study's preset, nominal inputs).
    preset : str
        The ``&numerics preset`` of the base decks.
    accurate : ndarray, shape (k, len(outputs))
        The same designs at preset ``'accurate'``.
    inputs : list of str
        Uncertain inputs varied one at a time (``group:name``).
    factors : list of float
        Each input is multiplied and divided by its factor.
    low, high : ndarray, shape (len(inputs), k, len(outputs))
        Results with the input divided / multiplied by its factor.

    Example
    -------
    >>> Sure(["knee"], np.zeros((1, 1)), np.ones((1, 2)), "fast", np.ones((1, 2)), [], [],
    ...      np.zeros((0, 1, 2)), np.zeros((0, 1, 2))).preset
    'fast'
    """

    names: list[str]
    x: np.ndarray
    nominal: np.ndarray
    preset: str
    accurate: np.ndarray
    inputs: list[str]
    factors: list[float]
    low: np.ndarray
    high: np.ndarray

    def to_h5(self, group: h5py.Group, s: StudySettings) -> None:
        """Write the extra runs into the empty ``group`` (e.g. ``/cases/LABEL/sure``), every
        matrix labelled (``columns``, ``units``).

        Example
        -------
        >>> s = StudySettings("s", ["a.nml"], ["c"], [1.0], ["width"], [0.0], [1.0],
        ...                   ["energy_loss"], units=["m"])
        >>> with h5py.File("x.h5", "w", driver="core", backing_store=False) as f:
        ...     n = len(s.outputs)
        ...     Sure(["knee"], np.zeros((1, 1)), np.ones((1, n)), "fast", np.ones((1, n)), [], [],
        ...          np.zeros((0, 1, n)), np.zeros((0, 1, n))).to_h5(f.create_group("sure"), s)
        ...     Sure.from_h5(f["sure"]).preset
        'fast'
        """
        units = output_units()
        out_units = [units[o] for o in s.outputs]
        put_strings(group, "names", self.names)
        put_strings(group, "inputs", self.inputs)
        put(group, "x", self.x, s.variables, s.units)
        put(group, "nominal", self.nominal, list(s.outputs), out_units)
        put(group, "accurate", self.accurate, list(s.outputs), out_units)
        put(group, "factors", np.asarray(self.factors, float), self.inputs)
        put(group, "low", self.low, list(s.outputs), out_units)
        put(group, "high", self.high, list(s.outputs), out_units)
        group.attrs["preset"] = self.preset

    @classmethod
    def from_h5(cls, group: h5py.Group) -> Sure:
        """The extra runs :meth:`to_h5` wrote into ``group`` (e.g. ``/cases/cold/sure``)."""
        return cls(
            strings(group["names"]),
            group["x"][()],
            group["nominal"][()],
            text(group.attrs["preset"]),
            group["accurate"][()],
            strings(group["inputs"]),
            [float(v) for v in group["factors"][()]],
            group["low"][()],
            group["high"][()],
        )
