"""The settings of a design study: the ``&study`` deck, read and checked.

:func:`read_study` reads a study deck into a :class:`StudySettings` and checks every value
(each error names the file, ``&study`` and the variable), checks each design variable
against every base deck with the kernel's own reader, and fingerprints the content of
every input file (base decks, the calibration files they include, their pressure traces)
so that a study is never resumed on changed inputs.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import math
import os
from pathlib import Path
from typing import Any

import numpy as np

from .case import Case
from .errors import InputError

__all__ = [
    "StudySettings",
    "read_study",
    "DESIGN_RANGES",
    "MAX_SAMPLES",
    "OUTPUTS",
    "output_units",
    "variable_unit",
    "effective",
    "split_variable",
    "input_files",
    "display",
    "Constraint",
    "parse_constraint",
]

#: Default bounds (SI) of the four ring design variables of the source study (SPEC 11/12),
#: used only when the deck gives neither ``lower`` nor ``upper``. The tension range is in
#: the unit set by ``&ring tension_unit`` of the base decks.
DESIGN_RANGES = {
    "width": (0.54e-3, 1.34e-3),
    "crown_height": (6e-6, 13e-6),
    "crown_offset": (-54e-6, 67e-6),
    "tension": (8.0, 26.0),
}
#: Most samples a study may ask for. The study file holds every sample and is rewritten at
#: each checkpoint, and a run takes about 40 ms on one core: 10**6 samples are about
#: 11 hours of runs per case on 2 cores, already far more than a quadratic surface needs.
MAX_SAMPLES = 1_000_000
#: Largest seed (the GA repeats use ``seed + 1000 r``, which must stay below 2**32).
MAX_SEED = 2**31 - 1
#: Study variables given without a group belong to this group.
DEFAULT_GROUP = "ring"
_SAMPLERS = ("sobol", "lhs")
_SURROGATES = ("quadratic",)
_INT_KEYS = {
    "samples": 1,
    "population": 1,
    "generations": 1,
    "repeats": 1,
    "seed": 0,
    "folds": 2,
    "direct_population": 1,
    "direct_generations": 1,
    "batch": 1,
}


# --- facts owned by the kernel (one place each, to be redirected at merge) -----------


def _output_units() -> dict[str, str]:
    """Every design quantity a study records for every design, with its unit (the kernel's
    result table: scalars marked as objectives that every film model produces)."""
    from .tables import SCALARS

    return {k: v.unit for k, v in SCALARS.items() if v.objective and not v.requires}


def _effective(case: Case, group: str, name: str) -> Any:
    """Value the kernel uses for ``&group name``: the deck's, its calibration file's, or the
    kernel's default."""
    return case.value(group, name)


def _input_unit(case: Case, group: str, name: str) -> str:
    """Unit of the input ``&group name`` (from the kernel's input table; the tension's is
    the case's ``tension_unit``)."""
    from .tables import INPUTS

    spec = INPUTS.get((group, name))
    if spec is None:
        return ""
    if spec.unit == "(unit)":
        return str(_effective(case, "ring", "tension_unit"))
    return "" if spec.unit == "1" else spec.unit


def _is_unknown_variable(group: str, name: str) -> bool:
    """Is ``&group name`` missing from the kernel's input table?"""
    from .tables import INPUTS

    return (group, name) not in INPUTS


def _is_whole_number(group: str, name: str) -> bool:
    """Is ``&group name`` an integer input of the kernel's table?"""
    from .tables import INPUTS

    spec = INPUTS.get((group, name))
    return spec is not None and spec.kind == "integer"


def _model_units() -> dict[str, str]:
    """Every design quantity a study may record, with its unit: the objective results of the
    kernel's table, including those only some film models produce (``oil_to_chamber``)."""
    from .tables import SCALARS

    return {k: v.unit for k, v in SCALARS.items() if v.objective}


def _produces(case: Case, requires: str) -> bool:
    """Does a run of ``case`` produce results that need ``requires`` ('jfo', 'starved', 'gas')?"""
    if requires == "jfo":
        return case.value("physics", "cavitation") == "jfo"
    if requires == "starved":
        return case.value("physics", "inlet") == "starved"
    if requires == "gas":
        return case.value("physics", "ring_pack") == "gas"
    return True


def output_units() -> dict[str, str]:
    """Scalar results a study may record for a design, with their units.

    The objective results first (:data:`OUTPUTS`, then those only some film models
    produce), then every other scalar of the kernel's result table (a constraint may name
    any of them, e.g. ``friction_power``).

    Returns
    -------
    dict of str to str
        Result name -> unit (SI, ``%`` for shares, ``g`` for the ring mass).

    Example
    -------
    >>> output_units()["energy_loss"], output_units()["fmep"]
    ('J', 'kPa')
    """
    from .tables import SCALARS

    return {**_model_units(), **{k: v.unit for k, v in SCALARS.items()}}


@dataclasses.dataclass(frozen=True)
class Constraint:
    """One ``&study constraints`` entry: ``NAME <= VALUE``, ``NAME >= VALUE`` or
    ``NAME <= reference`` (the reference design's true-model value on the same case).

    Attributes
    ----------
    name : str
        A scalar result (:func:`output_units`).
    sense : str
        ``'<='`` or ``'>='``.
    value : float or None
        The bound in the result's unit, or None for ``reference``.

    Example
    -------
    >>> c = parse_constraint("oil_to_chamber <= reference")
    >>> c.uses_reference, c.violation(3.0, 2.0)
    (True, 0.5)
    """

    name: str
    sense: str
    value: float | None

    @property
    def uses_reference(self) -> bool:
        """Is the bound the reference design's value?"""
        return self.value is None

    def __str__(self) -> str:
        rhs = "reference" if self.value is None else f"{self.value:g}"
        return f"{self.name} {self.sense} {rhs}"

    def violation(self, y, bound: float):
        """pymoo's inequality ``g <= 0``: ``(y - bound) / scale`` for ``<=`` (negated for
        ``>=``), scaled by ``|bound|`` (1 if the bound is 0) so constraints of different
        units weigh alike.

        Parameters
        ----------
        y : float or ndarray
            The result.
        bound : float
            The bound (:attr:`value`, or the reference's value).

        Returns
        -------
        float or ndarray
            <= 0 where satisfied.

        Example
        -------
        >>> parse_constraint("min_film >= 1e-6").violation(0.5e-6, 1e-6)
        0.5
        """
        scale = abs(bound) if bound != 0 else 1.0
        g = (np.asarray(y, float) - bound) / scale
        g = g if self.sense == "<=" else -g
        return float(g) if np.ndim(g) == 0 else g


def parse_constraint(text: str) -> Constraint:
    """Parse ``'NAME <= VALUE'``, ``'NAME >= VALUE'``, ``'NAME <= reference'``.

    Parameters
    ----------
    text : str
        One entry of ``&study constraints``; VALUE in the result's unit
        (:func:`output_units`).

    Returns
    -------
    Constraint

    Raises
    ------
    ValueError
        Saying what is wrong (the caller names file, group and variable).

    Example
    -------
    >>> str(parse_constraint(" fmep<=10 "))
    'fmep <= 10'
    """
    import re

    m = re.fullmatch(r"\s*([A-Za-z_]\w*)\s*(<=|>=)\s*(\S+)\s*", str(text))
    if not m:
        raise ValueError(f"'{text}' is not 'NAME <= VALUE', 'NAME >= VALUE' or 'NAME <= reference'")
    name, sense, rhs = m.group(1).lower(), m.group(2), m.group(3)
    units = output_units()
    if name not in units:
        raise ValueError(f"'{text}': unknown result '{name}' (known: {', '.join(units)})")
    if rhs.lower() == "reference":
        return Constraint(name, sense, None)
    try:
        value = float(rhs.lower().replace("d", "e"))
    except ValueError:
        raise ValueError(f"'{text}': '{rhs}' is neither a number nor 'reference'") from None
    if not math.isfinite(value):
        raise ValueError(f"'{text}': the bound must be a finite number")
    return Constraint(name, sense, value)


#: Names of the scalar results a study records for every design (in this order).
OUTPUTS = tuple(_output_units())


def effective(case: Case, group: str, name: str) -> Any:
    """The value the kernel uses for ``&group name`` of ``case``.

    Parameters
    ----------
    case : Case
        A case read from a deck.
    group, name : str
        Namelist group and variable.

    Returns
    -------
    object
        The deck's value, else its calibration file's, else the kernel's default (``None``
        where not known).

    Example
    -------
    >>> effective(Case({"ring": {"width": 1e-3}}), "ring", "width")
    0.001
    """
    return _effective(case, group, name)


def variable_unit(case: Case, variable: str) -> str:
    """Unit of a study variable (``'tension'`` follows ``&ring tension_unit``).

    Parameters
    ----------
    case : Case
        A base case of the study.
    variable : str
        ``'name'`` (a ``&ring`` variable) or ``'group:name'``.

    Returns
    -------
    str
        The unit, or ``""`` if not known.

    Example
    -------
    >>> variable_unit(Case({"ring": {"tension_unit": "N/m"}}), "tension")
    'N/m'
    """
    return _input_unit(case, *split_variable(variable))


def split_variable(variable: str) -> tuple[str, str]:
    """``'group:name'`` or ``'name'`` (a ``&ring`` variable) as ``(group, name)``, lower case.

    Parameters
    ----------
    variable : str
        A study variable.

    Returns
    -------
    tuple of str
        Group and variable name.

    Example
    -------
    >>> split_variable("operating:speed_rpm"), split_variable("Width")
    (('operating', 'speed_rpm'), ('ring', 'width'))
    """
    group, _, name = str(variable).strip().lower().rpartition(":")
    return (group.strip() or DEFAULT_GROUP), name.strip()


def display(variable: str, unit: str, lower: float, upper: float) -> tuple[str, float]:
    """How a variable is shown: label with unit, and the factor from SI to that unit.

    Lengths in metres are shown in µm or mm, whichever suits the range.

    Parameters
    ----------
    variable : str
        Study variable.
    unit : str
        Its SI unit (:func:`variable_unit`).
    lower, upper : float
        Its range.

    Returns
    -------
    label : str
    scale : float

    Example
    -------
    >>> display("crown_height", "m", 6e-6, 13e-6)
    ('crown height [µm]', 1000000.0)
    >>> display("tension", "N/m", 8, 26)
    ('tension [N/m]', 1.0)
    """
    _, name = split_variable(variable)
    label = name.replace("_", " ")
    if unit == "m":
        span = max(abs(lower), abs(upper))
        if span < 1e-4:
            return f"{label} [µm]", 1e6
        if span < 1e-1:
            return f"{label} [mm]", 1e3
    return (f"{label} [{unit}]" if unit else label), 1.0


def input_files(case: Case, deck: str | os.PathLike) -> list[Path]:
    """The files a base deck reads: itself, its calibration file and its pressure trace.

    Parameters
    ----------
    case : Case
        The case read from ``deck``.
    deck : path
        The deck's path.

    Returns
    -------
    list of Path
        Absolute paths, without duplicates.

    Example
    -------
    >>> [p.name for p in input_files(Case({}), "a.nml")]
    ['a.nml']
    """
    files = [Path(deck).resolve()]
    cal = case.get("calibration", "file")
    if cal:
        files.append(Path(cal).resolve())
    trace = _effective(case, "operating", "pressure_file")
    if trace:
        files.append(Path(trace).resolve())
    return list(dict.fromkeys(files))


def _fingerprint(files: list[Path]) -> dict[str, str]:
    out = {}
    for p in files:
        try:
            out[str(p)] = hashlib.sha256(p.read_bytes()).hexdigest()
        except OSError as exc:
            raise InputError(f"{p}: cannot read ({exc.strerror or exc})") from None
    return out


@dataclasses.dataclass
class StudySettings:
    """Everything a ``&study`` deck says, checked (see :func:`read_study`).

    Attributes
    ----------
    name : str
        Study name; the study file is ``OUT/NAME.h5``.
    cases, labels, weights : list
        Base decks (absolute paths), their labels and their weights in a scene.
    variables, lower, upper : list
        Design variables (``'name'`` of ``&ring`` or ``'group:name'``) and their bounds (SI).
    objectives : list of str
        Results to minimise (names of :data:`OUTPUTS`).
    reference : list of float or None
        A reference design (one value per variable) compared in the report and figures.
    inputs : dict of str to str
        SHA-256 of every input file (:func:`input_files`), checked on resume.

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
    sampler: str = "sobol"
    samples: int = 10001
    surrogate: str = "quadratic"
    population: int = 200
    generations: int = 200
    repeats: int = 20
    seed: int = 1
    scene: bool = False
    folds: int = 5
    direct_population: int = 200  # the study's own NSGA-II size (affordable since issue 11)
    direct_generations: int = 200
    batch: int = 16
    #: results recorded for every design: :data:`OUTPUTS` plus the objectives only some
    #: film models produce (e.g. ``oil_to_chamber`` with a starved inlet)
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
        if direct:
            names += ["direct_population", "direct_generations"]
        d = dataclasses.asdict(self)
        key = {k: d[k] for k in names}
        if direct:  # what the direct NSGA-II records and ranks (checkpoints before it: redone)
            key["direct_outputs"] = self.direct_outputs()
        return json.dumps(key)

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


def _as_list(v) -> list:
    return list(v) if isinstance(v, (list, tuple)) else [v]


class _Checker:
    def __init__(self, path: Path):
        self.path = path

    def bad(self, var: str, why: str):
        raise InputError(f"{self.path}: &study {var}: {why}")

    def integer(self, var: str, v: Any, lo: int, hi: int | None = None, why: str = "") -> int:
        if isinstance(v, bool) or not isinstance(v, int):
            self.bad(var, f"must be a whole number, got {v!r}")
        if v < lo:
            self.bad(var, f"must be at least {lo}, got {v}")
        if hi is not None and v > hi:
            self.bad(var, f"must be at most {hi:,}, got {v:,}" + (f" ({why})" if why else ""))
        return v

    def reals(self, var: str, values: list) -> list[float]:
        out = []
        for v in values:
            if isinstance(v, bool) or not isinstance(v, (int, float)):
                self.bad(var, f"must be numbers, got {v!r}")
            if not math.isfinite(v):
                self.bad(var, f"must be finite numbers, got {v}")
            out.append(float(v))
        return out

    def words(self, var: str, values: list) -> list[str]:
        for v in values:
            if not isinstance(v, str) or not v.strip():
                self.bad(var, f"must be quoted names, got {v!r}")
        return [v.strip() for v in values]

    def plain_name(self, var: str, v: str, what: str) -> None:
        if not v or any(ch in v for ch in "/\\") or v.startswith(".") or v.strip() != v:
            self.bad(
                var,
                f"'{v}' must be a plain name (no '/', '\\', leading '.', leading or "
                f"trailing spaces): it names {what}",
            )


def read_study(path: str | os.PathLike) -> StudySettings:
    """Read and check a ``&study`` deck.

    Relative case paths are relative to the deck's folder. Each base deck is checked by
    the kernel, each design variable is checked to exist in every base deck (and its
    bounds to be accepted there), and the content of every input file is fingerprinted.

    Parameters
    ----------
    path : path
        The study deck.

    Returns
    -------
    StudySettings

    Raises
    ------
    InputError
        Naming the file, ``&study`` and the variable (or the base deck and its variable).

    Example
    -------
    >>> s = read_study("inputs/study_default.nml")     # doctest: +SKIP
    >>> s.samples, s.labels                             # doctest: +SKIP
    (1025, ['cold', 'hot'])
    """
    path = Path(path)
    if not path.is_file():
        raise InputError(f"{path}: file not found" if not path.exists() else f"{path}: not a file")
    nml = _parse(path)
    if "study" not in nml:
        raise InputError(f"{path}: no &study group")
    if not isinstance(nml["study"], dict):
        raise InputError(f"{path}: {len(nml['study'])} &study groups; a study deck has one")
    s = dict(nml["study"])
    chk = _Checker(path)
    twice = _given_twice(path.read_text(errors="replace"))
    if twice:
        chk.bad(twice, "given twice; keep one")
    known = {f.name for f in dataclasses.fields(StudySettings)} - {"deck_text", "source", "inputs", "units"}
    for k in s:
        if k not in known:
            chk.bad(k, f"unknown variable (known: {', '.join(sorted(known))})")

    if "cases" not in s:
        chk.bad("cases", "required (one or more base decks)")
    cases = [str((path.parent / c).resolve()) for c in chk.words("cases", _as_list(s["cases"]))]
    labels = chk.words("labels", _as_list(s.get("labels", [Path(c).stem for c in cases])))
    weights = chk.reals("weights", _as_list(s.get("weights", [1.0] * len(cases))))
    variables = chk.words("variables", _as_list(s.get("variables", list(DESIGN_RANGES))))
    objectives = chk.words(
        "objectives", _as_list(s.get("objectives", ["energy_loss", "mixed_share", "ring_mass"]))
    )
    ints = {k: chk.integer(k, s[k], lo) for k, lo in _INT_KEYS.items() if k in s}
    for k in ("sampler", "surrogate"):
        if k in s:
            chk.words(k, [s[k]])
    if "scene" in s and not isinstance(s["scene"], bool):
        chk.bad("scene", f"must be .true. or .false., got {s['scene']!r}")

    name = s.get("name", path.stem)
    if not isinstance(name, str):
        chk.bad("name", f"must be a quoted name, got {name!r}")
    chk.plain_name("name", name, "the study file")
    for label in labels:
        chk.plain_name("labels", label, "a group of the study file and its figures")
    if len(labels) != len(cases) or len(set(labels)) != len(labels):
        chk.bad("labels", f"one distinct label per case ({len(cases)} cases)")
    if "scene" in labels:
        chk.bad("labels", "'scene' is reserved for the weighted scene")
    if len(weights) != len(cases) or any(w <= 0 for w in weights):
        chk.bad("weights", f"one positive weight per case ({len(cases)} cases)")

    pairs = []
    for v in variables:
        group, name_ = split_variable(v)
        if not name_ or ":" in name_:
            chk.bad("variables", f"'{v}' is not 'name' or 'group:name'")
        if _is_whole_number(group, name_):
            chk.bad(
                "variables",
                f"'{v}' is a whole number (&{group} {name_}); a study samples real values: "
                "vary it with one base deck per value instead",
            )
        pairs.append((group, name_))
    if len(set(pairs)) != len(pairs):
        chk.bad("variables", "a variable is given twice")
    lower, upper = _bounds(chk, s, variables, pairs)
    if any(lo >= hi for lo, hi in zip(lower, upper)):
        chk.bad("upper", "each upper bound must exceed its lower bound")
    reference = None
    if "reference" in s:
        reference = chk.reals("reference", _as_list(s["reference"]))
        if len(reference) != len(variables):
            chk.bad("reference", f"one value per variable ({len(variables)})")

    constraints = []
    for text in chk.words("constraints", _as_list(s.get("constraints", []))):
        try:
            c = parse_constraint(text)
        except ValueError as exc:
            chk.bad("constraints", str(exc))
        if c.uses_reference and reference is None:
            chk.bad("constraints", f"'{text}' is bounded by the reference design: give &study reference")
        constraints.append(str(c))
    if len(set(constraints)) != len(constraints):
        chk.bad("constraints", "a constraint is given twice")

    units = _model_units()
    for o in objectives:
        if o not in units:
            chk.bad("objectives", f"unknown objective '{o}' (known: {', '.join(units)})")
    if not objectives or len(set(objectives)) != len(objectives):
        chk.bad("objectives", "one or more distinct objectives")
    sampler = s.get("sampler", "sobol")
    if sampler not in _SAMPLERS:
        chk.bad("sampler", f"must be one of {', '.join(map(repr, _SAMPLERS))}, got {sampler!r}")
    surrogate = s.get("surrogate", "quadratic")
    if surrogate not in _SURROGATES:
        chk.bad("surrogate", f"must be 'quadratic', got {surrogate!r}")
    if "samples" in ints:
        chk.integer(
            "samples",
            ints["samples"],
            1,
            MAX_SAMPLES,
            "the study file holds every sample; 10**6 runs are about 11 hours per case on 2 cores",
        )
    if "seed" in ints:
        chk.integer("seed", ints["seed"], 0, MAX_SEED)

    st = StudySettings(
        name=name,
        cases=cases,
        labels=labels,
        weights=weights,
        variables=variables,
        lower=lower,
        upper=upper,
        objectives=objectives,
        sampler=sampler,
        surrogate=surrogate,
        reference=reference,
        constraints=constraints,
        **({"scene": s["scene"]} if "scene" in s else {}),
        **ints,
        deck_text=path.read_text(errors="replace"),
        source=str(path),
    )
    nterms = 1 + 2 * len(variables) + len(variables) * (len(variables) - 1) // 2
    if st.samples < nterms + st.folds:
        chk.bad(
            "samples",
            f"need at least {nterms + st.folds} for a quadratic in "
            f"{len(variables)} variables with {st.folds}-fold cross-validation",
        )
    st.inputs, st.units = _check_cases(chk, st, pairs)
    from .tables import SCALARS

    for var, o in [("objectives", o) for o in objectives] + [
        ("constraints", c.name) for c in st.parsed_constraints
    ]:
        req = SCALARS[o].requires if o in SCALARS else ""
        if req and o not in st.outputs:
            need = {"jfo": "cavitation = 'jfo'", "starved": "inlet = 'starved'", "gas": "ring_pack = 'gas'"}[
                req
            ]
            for deck in cases:
                if not _produces(Case.from_namelist(deck), req):
                    chk.bad(var, f"'{o}' needs &physics {need} in every base deck ({deck} has not)")
        if o not in st.outputs:
            st.outputs.append(o)  # constrained results are recorded (and fitted) too
    return st


def _parse(path: Path):
    """The namelist file read by f90nml, or one line saying why not."""
    import contextlib
    import io

    import f90nml

    try:
        with contextlib.redirect_stdout(io.StringIO()):  # f90nml prints its state on some errors
            return f90nml.read(path)
    except Exception as exc:  # f90nml raises several types for bad syntax
        lines = str(exc).strip().splitlines()
        why = lines[0] if lines else f"{type(exc).__name__} (an unterminated string or a stray character?)"
        raise InputError(f"{path}: cannot parse namelist: {why}") from None


def _given_twice(text: str) -> str:
    """The first variable assigned twice in the ``&study`` group of ``text`` ('' if none).

    Strings and ``!`` comments are skipped; ``name(i) =`` counts per index.

    Example
    -------
    >>> _given_twice("&study samples = 16, samples = 32 /")
    'samples'
    >>> _given_twice("&study name = 'a=b', lower(1) = 1, lower(2) = 2 /")
    ''
    """
    import re

    code = re.sub(r"'(?:[^']|'')*'|\"(?:[^\"]|\"\")*\"|![^\n]*", " ", text)
    group = re.search(r"&study\b(.*?)(?:/|&end\b|$)", code, flags=re.IGNORECASE | re.DOTALL)
    seen = set()
    for m in re.finditer(r"([A-Za-z_]\w*)\s*(\([^)]*\))?\s*=", group.group(1) if group else ""):
        key = (m.group(1).lower(), (m.group(2) or "").replace(" ", ""))
        if key in seen:
            return m.group(1).lower()
        seen.add(key)
    return ""


def _bounds(
    chk: _Checker, s: dict, variables: list[str], pairs: list[tuple[str, str]]
) -> tuple[list[float], list[float]]:
    given = [k for k in ("lower", "upper") if k in s]
    if len(given) == 1:
        chk.bad(
            "lower" if "lower" not in s else "upper",
            f"required when '{given[0]}' is given (one bound per variable)",
        )
    if given:
        lower = chk.reals("lower", _as_list(s["lower"]))
        upper = chk.reals("upper", _as_list(s["upper"]))
        if not (len(lower) == len(upper) == len(variables)):
            chk.bad("lower", f"one lower and one upper bound per variable ({len(variables)})")
        return lower, upper
    missing = [v for v, (g, n) in zip(variables, pairs) if g != DEFAULT_GROUP or n not in DESIGN_RANGES]
    if missing:
        chk.bad(
            "lower",
            f"required: default ranges exist only for the ring variables "
            f"{', '.join(DESIGN_RANGES)}, not for {', '.join(missing)}",
        )
    return ([DESIGN_RANGES[n][0] for _, n in pairs], [DESIGN_RANGES[n][1] for _, n in pairs])


def _check_cases(
    chk: _Checker, st: StudySettings, pairs: list[tuple[str, str]]
) -> tuple[dict[str, str], list[str]]:
    """Kernel checks of every base deck, variable and bound; input fingerprints; units."""
    files: list[Path] = []
    units_seen: dict[str, dict[str, str]] = {}
    for label, deck in zip(st.labels, st.cases):
        case = Case.from_namelist(deck)  # the kernel checks the deck itself
        files += input_files(case, deck)
        for v, (group, name), lo, hi in zip(st.variables, pairs, st.lower, st.upper):
            try:
                case.with_(group, **{name: lo})
            except InputError as exc:
                chk.bad("variables", f"'{v}': {exc}")
            for which, value in (("lower", lo), ("upper", hi)):
                try:
                    case.with_(group, **{name: value}).validate()
                except InputError as exc:
                    msg = str(exc)
                    if _is_unknown_variable(group, name):
                        chk.bad("variables", f"'{v}' is not a variable of &{group} (base deck {deck})")
                    chk.bad(which, f"{v} = {value:g} is rejected by base deck '{label}': {msg}")
            units_seen.setdefault(v, {})[label] = _input_unit(case, group, name)
    units = []
    for v, per_case in units_seen.items():
        if len(set(per_case.values())) > 1:
            chk.bad(
                "variables",
                f"'{v}' has different units in the base decks "
                f"({', '.join(f'{k}: {u}' for k, u in per_case.items())}); "
                "one value cannot mean both",
            )
        units.append(next(iter(per_case.values())))
    return _fingerprint(list(dict.fromkeys(files))), units
