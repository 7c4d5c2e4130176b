"""The settings of a design study: what a ``&study`` deck says, checked (the variables, their
types, defaults and ranges: the ``&study`` table, :data:`ringlube.study.table.STUDY`).

:class:`StudySettings` holds them (read by :func:`ringlube.study.deck.read_study`) and gives
the keys that decide what a resumed study keeps.
"""

from __future__ import annotations

import dataclasses
import json

import numpy as np

from .constraints import Constraint, parse_constraint
from .table import STUDY
from .variables import OUTPUTS, PER_CYCLE, split_variable

__all__ = ["StudySettings"]


@dataclasses.dataclass
class StudySettings:
    """Everything a ``&study`` deck says, checked (see :func:`~ringlube.study.deck.read_study`).

    Attributes
    ----------
    name : str
        Study name; the study file is ``OUT/NAME.h5``.
    cases, labels, weights : list
        Base decks (absolute paths), their labels and their weights in a scene.
    variables, lower, upper : list
        Design variables (``'name'`` of ``&ring`` or ``'group:name'``) and their bounds (SI).
    objectives : list of str
        Results to minimise (names of :data:`~ringlube.study.variables.OUTPUTS`).
    reference : list of float or None
        A reference design (one value per variable) compared in the report and figures.
    inputs : dict of str to str
        SHA-256 of every input file (:func:`~ringlube.study.variables.input_files`), checked on resume.

    Example
    -------
    >>> s = read_study("inputs/study_default.nml")          # doctest: +SKIP
    >>> s.variables                                           # doctest: +SKIP
    ['width', 'crown_height', 'crown_offset', 'tension']
    """

    name: str
    cases: list[str]
    labels: list[str]
    weights: list[float]
    variables: list[str]
    lower: list[float]
    upper: list[float]
    objectives: list[str]
    # defaults: the &study table (ringlube.study.table.STUDY), their one home; the direct
    # NSGA-II's default is the source study's own size
    sampler: str = STUDY["sampler"].default
    samples: int = STUDY["samples"].default
    surrogate: str = STUDY["surrogate"].default
    population: int = STUDY["population"].default
    generations: int = STUDY["generations"].default
    repeats: int = STUDY["repeats"].default
    seed: int = STUDY["seed"].default
    scene: bool = STUDY["scene"].default
    folds: int = STUDY["folds"].default
    direct_population: int = STUDY["direct_population"].default
    direct_generations: int = STUDY["direct_generations"].default
    batch: int = STUDY["batch"].default
    weighting: str = STUDY["weighting"].default
    #: cycles per second of each case (its speed_rpm / 120; with ``weighting = 'time'``)
    cycle_rates: list[float] = dataclasses.field(default_factory=list)
    #: results recorded for every design: :data:`~ringlube.study.variables.OUTPUTS` plus the
    #: objectives only some film models produce (e.g. ``oil_to_chamber`` with a starved inlet)
    outputs: list[str] = dataclasses.field(default_factory=lambda: list(OUTPUTS))
    reference: list[float] | None = None
    #: ``&study constraints``, normalised (``'oil_to_chamber <= reference'``)
    constraints: list[str] = dataclasses.field(default_factory=list)
    deck_text: str = ""
    source: str = ""
    inputs: dict[str, str] = dataclasses.field(default_factory=dict)
    units: list[str] = dataclasses.field(default_factory=list)

    @property
    def parsed_constraints(self) -> list[Constraint]:
        """The constraints as :class:`Constraint` records.

        Example
        -------
        >>> StudySettings("s", [], [], [], [], [], [], [],
        ...               constraints=["fmep <= 3"]).parsed_constraints[0].value
        3.0
        """
        return [parse_constraint(c) for c in self.constraints]

    def direct_outputs(self) -> list[str]:
        """Results the direct NSGA-II records per design: the objectives, then the
        constrained results that are not objectives, then ``liner_lift_share`` (a design that
        lifts the ring off the liner is ranked below every design that does not).

        Example
        -------
        >>> StudySettings("s", [], [], [], [], [], [], ["energy_loss"],
        ...               constraints=["fmep <= 3"]).direct_outputs()
        ['energy_loss', 'fmep', 'liner_lift_share']
        """
        return list(
            dict.fromkeys([*self.objectives, *(c.name for c in self.parsed_constraints), "liner_lift_share"])
        )

    @property
    def groups_names(self) -> list[tuple[str, str]]:
        """The variables as ``(group, name)`` pairs.

        Returns
        -------
        list of tuple of str

        Example
        -------
        >>> StudySettings("s", [], [], [], ["width", "operating:speed_rpm"], [], [],
        ...               []).groups_names
        [('ring', 'width'), ('operating', 'speed_rpm')]
        """
        return [split_variable(v) for v in self.variables]

    def key(self) -> str:
        """What must match for a study file to be resumed (not the GA or direct settings).

        Returns
        -------
        str
            JSON of the cases, labels, variables, bounds, objectives, recorded results
            (``outputs``: a constraint on a result not recorded before needs new runs),
            sampler, samples, seed.

        Example
        -------
        >>> StudySettings("s", ["a.nml"], ["a"], [1.0], ["width"], [0.0], [1.0],
        ...               ["energy_loss"]).key()[:20]
        '{"cases": ["a.nml"],'
        """
        d = dataclasses.asdict(self)
        return json.dumps(
            {
                k: d[k]
                for k in (
                    "cases",
                    "labels",
                    "variables",
                    "lower",
                    "upper",
                    "objectives",
                    "outputs",
                    "sampler",
                    "samples",
                    "seed",
                )
            }
        )

    def derived_key(self, label: str, direct: bool = False) -> str:
        """What must match for results derived from the runs of one case to be kept on resume.

        The fit and GA settings and the constraints (and the reference design when a
        constraint is bounded by it) shape every surface and front; the weights and ``scene``
        also shape the weighted scene (``label == 'scene'``); the direct NSGA-II sizes shape
        the direct comparison (``direct=True``). A stored result whose key differs is
        recomputed from the runs (which are kept).

        Parameters
        ----------
        label : str
            Case label or ``scene``.
        direct : bool
            The key of the direct NSGA-II comparison.

        Returns
        -------
        str
            JSON.

        Example
        -------
        >>> s = StudySettings("s", ["a.nml"], ["a"], [1.0], ["width"], [0.0], [1.0], ["energy_loss"])
        >>> '"weights"' in s.derived_key("scene"), '"weights"' in s.derived_key("a")
        (True, False)
        """
        names = ["surrogate", "folds", "population", "generations", "repeats", "constraints"]
        if any(c.uses_reference for c in self.parsed_constraints):
            names.append("reference")
        if label == "scene":
            names += ["weights", "scene"]
            if self.weighting != "case":
                names += ["weighting", "cycle_rates"]
        if direct:
            names += ["direct_population", "direct_generations"]
        d = dataclasses.asdict(self)
        key = {k: d[k] for k in names}
        if direct:  # what the direct NSGA-II records and ranks (checkpoints before it: redone)
            key["direct_outputs"] = self.direct_outputs()
        return json.dumps(key)

    def scene_weights(self, outputs: list[str] | None = None) -> np.ndarray:
        """The weight of each case in the scene's value of each result, (case, result), each
        column summing to 1.

        ``weighting = 'case'``: the weights, normalised, for every result. ``'time'``: the
        weights are the cases' running times; a result per cycle
        (:data:`~ringlube.study.variables.PER_CYCLE`) weighs by the cycles run, time x
        cycles per second, so that the scene's energy per cycle is the energy of all cycles
        over their number, and its friction power their energy over the time.

        Parameters
        ----------
        outputs : list of str, optional
            The results (default: ``outputs``).

        Returns
        -------
        ndarray

        Example
        -------
        >>> s = StudySettings("s", ["a", "b"], ["a", "b"], [3.0, 1.0], [], [], [], [],
        ...                   weighting="time", cycle_rates=[50.0, 16.0])
        >>> s.scene_weights(["friction_power", "energy_loss"]).round(4).tolist()
        [[0.75, 0.9036], [0.25, 0.0964]]
        """
        outputs = list(self.outputs if outputs is None else outputs)
        # each factor and each column scaled by its largest before the sum: weights near the
        # largest float (1e308) overflowed the sum to inf and made every weight 0
        w = _by_largest(self.weights)[:, None] * np.ones((1, len(outputs)))
        if self.weighting == "time":
            per_cycle = np.array([o in PER_CYCLE for o in outputs])
            w[:, per_cycle] *= _by_largest(self.cycle_rates)[:, None]
        w = w / w.max(axis=0)
        return w / w.sum(axis=0)

    def to_json(self) -> str:
        """The settings as JSON (stored in the study file).

        Returns
        -------
        str

        Example
        -------
        >>> '"name": "s"' in StudySettings("s", [], [], [], [], [], [], []).to_json()
        True
        """
        return json.dumps(dataclasses.asdict(self))


def _by_largest(values) -> np.ndarray:
    """Positive values over the largest of them (each in (0, 1]; 0 where one is below the
    largest by more than the float range, refused by :func:`~ringlube.study.deck.read_study`)."""
    v = np.asarray(values, float)
    return v / v.max()
