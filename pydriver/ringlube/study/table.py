"""The ``&study`` table: one row per variable of a study deck, the one home of its type,
default, range or choices, unit and meaning (as ``fortran/src/inputs.f90`` is for the kernel's
decks).

The table drives :func:`study_values` (a ``&study`` deck read by the kernel's scanner,
:mod:`ringlube.case.items`, each value typed and range-checked, every error naming
file:line, ``&study`` and the variable), the defaults of
:class:`~ringlube.study.settings.StudySettings`, and the generated table of
docs/optimisation.md (:func:`study_markdown`, ``python -m ringlube.docgen``). Checks that
involve several variables or the base decks (one label per case, bounds against the
kernel, ...) are :func:`ringlube.study.deck.read_study`'s.

>>> STUDY["samples"].kind, STUDY["samples"].upper
('integer', 1000000)
"""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path
from typing import Any

from ..case.items import LOGICALS, Item, items
from ..errors import InputError

__all__ = ["StudyInput", "STUDY", "MAX_SAMPLES", "MAX_SEED", "study_values", "study_markdown"]

#: Most samples a study may ask for. The study file holds every sample and is rewritten at
#: each checkpoint, and a run takes about 40 ms on one core: 10**6 samples are about
#: 11 hours of runs per case on 2 cores, already far more than a quadratic surface needs.
MAX_SAMPLES = 1_000_000
#: Largest NSGA-II population and number of generations (surfaces and direct), and repeats.
MAX_POPULATION, MAX_GENERATIONS, MAX_REPEATS = 10_000, 100_000, 1000
#: Largest seed (the GA repeats use ``seed + 1000 r``, which must stay below 2**32).
MAX_SEED = 2**31 - 1


@dataclasses.dataclass(frozen=True)
class StudyInput:
    """One variable of ``&study``.

    Attributes
    ----------
    name : str
        The variable.
    kind : str
        'names' (a list of quoted strings), 'reals' (a list of numbers), 'name' (one quoted
        string), 'choice' (one of ``choices``), 'integer' or 'logical'.
    default : Any
        The value when the deck leaves it out (None: computed from other variables, see
        ``default_text``, or none at all).
    default_text : str
        The default as the docs show it.
    lower, upper : int or None
        Range of an integer (inclusive; None: unbounded).
    choices : tuple of str
        Allowed values of a choice.
    unit : str
        Unit of the values ('' for names and counts).
    doc : str
        One line.
    required : bool
        The deck must give it.
    why_upper : str
        Why ``upper`` is the limit (in the message when it is exceeded).

    Examples
    --------
    >>> STUDY["sampler"].choices
    ('sobol', 'lhs')
    """

    name: str
    kind: str
    default: Any
    default_text: str
    doc: str
    unit: str = ""
    lower: int | None = None
    upper: int | None = None
    choices: tuple[str, ...] = ()
    required: bool = False
    why_upper: str = ""

    @property
    def is_list(self) -> bool:
        """Does the variable take a list of values?"""
        return self.kind in ("names", "reals")


def _rows() -> tuple[StudyInput, ...]:
    I = StudyInput  # noqa: E741, N806 (a short name for the table)
    return (
        I(
            "name",
            "name",
            None,
            "the deck's file name",
            "study name; the study file is `OUT/NAME.h5` (a plain name)",
        ),
        I(
            "cases",
            "names",
            None,
            "(required)",
            "base decks, one per condition (relative to the study deck)",
            required=True,
        ),
        I(
            "labels",
            "names",
            None,
            "the base decks' file names",
            "one distinct plain name per case ('scene' is reserved)",
        ),
        I("weights", "reals", None, "1 per case", "weight of each case in the weighted scene (positive)"),
        I(
            "weighting",
            "choice",
            "case",
            "'case'",
            "'case': the scene is the weighted mean of every result; 'time': the weights are the "
            "cases' running times, results per cycle weigh by the cycles run (time x speed/120)",
            choices=("case", "time"),
        ),
        I(
            "variables",
            "names",
            None,
            "'width', 'crown_height', 'crown_offset', 'tension'",
            "design variables: a `&ring` name or 'group:name' of a real input",
        ),
        I(
            "lower",
            "reals",
            None,
            "the source study's ranges (ring variables only)",
            "lower bound of each variable",
            "deck's unit",
        ),
        I(
            "upper",
            "reals",
            None,
            "the source study's ranges (ring variables only)",
            "upper bound of each variable",
            "deck's unit",
        ),
        I(
            "reference",
            "reals",
            None,
            "none",
            "a reference design (one value per variable) compared in the report",
            "deck's unit",
        ),
        I(
            "objectives",
            "names",
            ("energy_loss", "mixed_share", "ring_mass"),
            "'energy_loss', 'mixed_share', 'ring_mass'",
            "results to minimise (distinct)",
        ),
        I(
            "constraints",
            "names",
            (),
            "none",
            "'NAME <= VALUE', 'NAME >= VALUE' or 'NAME <= [FACTOR *] reference', each optionally "
            "'at LABEL' (one point, or 'scene')",
        ),
        I("sampler", "choice", "sobol", "'sobol'", "design of experiments", choices=("sobol", "lhs")),
        I(
            "samples",
            "integer",
            10001,
            "10001",
            "designs run per case (at least the quadratic's terms plus `folds`)",
            lower=1,
            upper=MAX_SAMPLES,
            why_upper="the study file holds every sample; 10**6 runs are about 11 hours per case on 2 cores",
        ),
        I(
            "surrogate",
            "choice",
            "quadratic",
            "'quadratic'",
            "response surface fitted to the runs",
            choices=("quadratic",),
        ),
        I(
            "population",
            "integer",
            200,
            "200",
            "NSGA-II population on the surfaces",
            lower=2,
            upper=MAX_POPULATION,
            why_upper="NSGA-II compares every pair of the population every generation (10,000: 0.8 GB)",
        ),
        I(
            "generations",
            "integer",
            200,
            "200",
            "NSGA-II generations on the surfaces",
            lower=1,
            upper=MAX_GENERATIONS,
            why_upper="population x generations surface evaluations per repeat",
        ),
        I(
            "repeats",
            "integer",
            20,
            "20",
            "NSGA-II repeats (seeds `seed + 1000 r`), fronts merged",
            lower=1,
            upper=MAX_REPEATS,
            why_upper="every repeat is a whole NSGA-II run, its front kept in the study file",
        ),
        I("seed", "integer", 1, "1", "seed of the sampler and of NSGA-II", lower=0, upper=MAX_SEED),
        I(
            "scene",
            "logical",
            False,
            ".false.",
            "also fit and optimise the weight-averaged results of the cases",
        ),
        I("folds", "integer", 5, "5", "folds of the surfaces' cross-validation", lower=2),
        I(
            "direct_population",
            "integer",
            200,
            "200",
            "population of the direct NSGA-II on the true model (`--direct`)",
            lower=2,
            upper=MAX_POPULATION,
            why_upper="direct_population x direct_generations true-model runs per case",
        ),
        I(
            "direct_generations",
            "integer",
            200,
            "200",
            "generations of the direct NSGA-II (`--direct`)",
            lower=1,
            upper=MAX_GENERATIONS,
            why_upper="direct_population x direct_generations true-model runs per case",
        ),
        I("batch", "integer", 16, "16", "designs per parallel task", lower=1),
    )


#: The ``&study`` table by variable name, in deck order.
STUDY: dict[str, StudyInput] = {r.name: r for r in _rows()}


def _fail(it: Item, why: str):
    raise InputError(f"{it.where}: &study {it.name}: {why}")


def _one(spec: StudyInput, its: list[Item]) -> Any:
    """The Python value of the items of one variable, typed and checked by its row."""
    if not spec.is_list and len(its) > 1:
        _fail(its[1], f"takes one value, got {len(its)}")
    values = []
    for it in its:
        if spec.kind in ("names", "name", "choice"):
            if not it.quoted or not it.value.strip():
                what = "quoted names" if spec.is_list else "a quoted name"
                _fail(it, f"must be {what}, got {it.value if not it.quoted else repr(it.value)}")
            values.append(it.value.strip() if spec.kind != "name" else it.value)
        elif spec.kind == "reals":
            values.append(_real(it))
        elif spec.kind == "integer":
            values.append(_integer(spec, it))
        else:
            if it.quoted or it.value.lower() not in LOGICALS:
                _fail(it, f"must be .true. or .false., got {it.value!r}")
            values.append(LOGICALS[it.value.lower()])
    if spec.kind == "choice" and values[0] not in spec.choices:
        if len(spec.choices) == 1:
            _fail(its[0], f"must be '{spec.choices[0]}', got {values[0]!r}")
        _fail(its[0], f"must be one of {', '.join(map(repr, spec.choices))}, got {values[0]!r}")
    return values if spec.is_list else values[0]


def _real(it: Item) -> float:
    try:
        if it.quoted:
            raise ValueError
        v = float(it.value.replace("d", "e").replace("D", "e"))
    except ValueError:
        _fail(it, f"must be numbers, got {it.value!r}" if it.quoted else f"must be numbers, got {it.value}")
    if not math.isfinite(v):
        _fail(it, f"must be finite numbers, got {v}")
    return v


def _integer(spec: StudyInput, it: Item) -> int:
    try:
        if it.quoted:
            raise ValueError
        v = int(it.value)
    except ValueError:
        _fail(
            it,
            f"must be a whole number, got {it.value!r}"
            if it.quoted
            else f"must be a whole number, got {it.value}",
        )
    if spec.lower is not None and v < spec.lower:
        _fail(it, f"must be at least {spec.lower}, got {v}")
    if spec.upper is not None and v > spec.upper:
        why = f" ({spec.why_upper})" if spec.why_upper else ""
        _fail(it, f"must be at most {spec.upper:,}, got {v:,}{why}")
    return v


def study_values(path: str | Path, text: str) -> tuple[dict[str, Any], dict[str, int]]:
    """The ``&study`` group of a deck, read by the kernel's scanner and typed by :data:`STUDY`.

    Parameters
    ----------
    path : str or Path
        The deck (named in messages).
    text : str
        Its text.

    Returns
    -------
    values : dict
        The variables the deck gives (lists for list variables, else a value).
    lines : dict
        The line of each variable given.

    Raises
    ------
    InputError
        Naming file:line, ``&study`` and the variable: malformed text, another group, a
        second ``&study`` group, a variable given twice, an unknown variable, a value of the
        wrong type or outside its range.

    Examples
    --------
    >>> study_values("s.nml", "&study cases = 'a.nml', 'b.nml'\\n samples = 64 /")
    ({'cases': ['a.nml', 'b.nml'], 'samples': 64}, {'cases': 1, 'samples': 2})
    """
    its = items(text, str(path), lists=True)
    opened = sorted({i.group_line for i in its if i.group == "study"})
    for it in its:
        if it.group != "study":
            from ..tables import GROUPS

            if it.group in GROUPS and not any(i.group == "study" for i in its):
                raise InputError(
                    f"{path}: this is a case deck (&{it.group}, line {it.group_line}), not a study deck: "
                    "ringlube optimise reads one &study group (e.g. inputs/study_default.nml); "
                    "a case deck runs with `ringlube run`"
                )
            raise InputError(
                f"{it.where}: &{it.group}: not a group of a study deck (it has one &study group)"
            )
    if not opened:
        raise InputError(f"{path}: no &study group")
    if len(opened) > 1:
        raise InputError(
            f"{path}: {len(opened)} &study groups (lines {', '.join(map(str, opened))}); a study deck has one"
        )
    given: dict[str, list[Item]] = {}
    for it in its:
        if it.index == 1 and it.name in given:
            _fail(it, f"given twice (also on line {given[it.name][0].line}); keep one")
        if it.name not in STUDY:
            _fail(it, f"unknown variable (known: {', '.join(sorted(STUDY))})")
        given.setdefault(it.name, []).append(it)
    values = {name: _one(STUDY[name], group) for name, group in given.items()}
    return values, {name: group[0].line for name, group in given.items()}


def study_markdown() -> str:
    """The ``&study`` table of docs/optimisation.md (generated from :data:`STUDY`).

    Examples
    --------
    >>> study_markdown().splitlines()[0]
    '| variable | type | default | range or choices | unit | meaning |'
    """
    kinds = {
        "names": "quoted names",
        "reals": "numbers",
        "name": "quoted name",
        "choice": "choice",
        "integer": "integer",
        "logical": "logical",
    }
    lines = ["| variable | type | default | range or choices | unit | meaning |", "|---|---|---|---|---|---|"]
    for s in STUDY.values():
        if s.kind == "choice":
            rng = " \\| ".join(f"'{c}'" for c in s.choices)
        elif s.kind == "integer":
            rng = f"at least {s.lower}" if s.upper is None else f"{s.lower} .. {s.upper:,}"
        elif s.kind == "logical":
            rng = ".true. \\| .false."
        else:
            rng = ""
        lines.append(f"| `{s.name}` | {kinds[s.kind]} | {s.default_text} | {rng} | {s.unit} | {s.doc} |")
    return "\n".join(lines)
