"""The state of a design study as typed records.

Per case (base deck label, or ``scene``) a :class:`CaseState`: the true-model :class:`Runs`,
the fitted :class:`Surface` of each result, the GA repeats, the merged :class:`Front`, the
chosen and reference designs re-simulated (:class:`Checked`), how sure the answer is
(:class:`Sure`) and the :class:`Direct` comparison with its checkpoints
(:class:`DirectGeneration`). :class:`~ringlube.study_store.Study` holds them and
:mod:`ringlube.study_layout` stores them.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from .study_variables import OUTPUTS

__all__ = [
    "CaseState",
    "Runs",
    "Surface",
    "Front",
    "Checked",
    "Direct",
    "DirectGeneration",
    "Sure",
]


@dataclasses.dataclass
class Runs:
    """True-model runs of every sample on one case.

    Attributes
    ----------
    outputs : ndarray, shape (n, len(OUTPUTS))
        Every scalar result (:data:`~ringlube.study_variables.OUTPUTS`); NaN until run or
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


@dataclasses.dataclass
class Surface:
    """A fitted quadratic surface of one result (coefficients over the scaled variables).

    Attributes
    ----------
    coef : ndarray
        Coefficients of :func:`~ringlube.surrogate.quadratic_features`.
    r2, r2_adj, cv_rmse, cv_rel : float
        Goodness of fit; k-fold cross-validated RMSE (result's unit) and relative to mean |y|.
    n : int
        Samples fitted.

    Example
    -------
    >>> Surface(np.zeros(3), 1.0, 1.0, 0.0, 0.0, 10).n
    10
    """

    coef: np.ndarray
    r2: float
    r2_adj: float
    cv_rmse: float
    cv_rel: float
    n: int


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


@dataclasses.dataclass
class DirectGeneration:
    """One generation of the direct NSGA-II, as evaluated (its checkpoint).

    Attributes
    ----------
    x : ndarray, shape (k, d)
        The designs pymoo asked for.
    f : ndarray, shape (k, len(direct_outputs))
        Their true objectives, then the constrained results that are not objectives
        (:meth:`~ringlube.study_settings.StudySettings.direct_outputs`; NaN where the run
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


@dataclasses.dataclass
class CaseState:
    """Everything a study computed for one case (or the weighted scene).

    Example
    -------
    >>> CaseState(Runs.empty(4)).front is None
    True
    """

    runs: Runs
    surfaces: dict[str, Surface] = dataclasses.field(default_factory=dict)
    repeats: dict[int, tuple[np.ndarray, np.ndarray]] = dataclasses.field(default_factory=dict)
    front: Front | None = None
    chosen: Checked | None = None
    reference: Checked | None = None
    direct: Direct | None = None
    direct_generations: list[DirectGeneration] = dataclasses.field(default_factory=list)
    sure: Sure | None = None
