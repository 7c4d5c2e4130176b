"""The design variables of a study and the kernel's facts about them and the results.

Default ranges of the ring variables, ``'group:name'`` variables, the value and unit the kernel
uses for an input, the scalar results a study may record (with their units), how a variable
is shown, and the input files of a base deck with their fingerprints.
"""

from __future__ import annotations

import hashlib
import os
from pathlib import Path
from typing import Any

from ..case import Case
from ..errors import InputError

__all__ = [
    "result_display",
    "DESIGN_RANGES",
    "OUTPUTS",
    "PER_CYCLE",
    "output_units",
    "variable_unit",
    "effective",
    "split_variable",
    "input_files",
    "display",
]

#: Default bounds (SI) of the four ring design variables of the source study,
#: used only when the deck gives neither ``lower`` nor ``upper``. The tension range is in
#: the unit set by ``&ring tension_unit`` of the base decks.
DESIGN_RANGES = {
    "width": (0.54e-3, 1.34e-3),
    "crown_height": (6e-6, 13e-6),
    "crown_offset": (-54e-6, 67e-6),
    "tension": (8.0, 26.0),
}
#: The results that are amounts per cycle (energy, gas and oil per cycle, events per cycle, and
#: FMEP, the work per cycle over the swept volume): with ``&study weighting = 'time'`` the
#: scene weighs them by the cycles each case runs; every other result (a rate such as friction
#: power or blowby, a share of the cycle's time) by its running time.
PER_CYCLE = frozenset(
    {"energy_loss", "fmep", "fmep_bar", "oil_to_chamber", "blowby_mass", "blowback_mass", "flutter_events"}
)
#: Study variables given without a group belong to this group.
DEFAULT_GROUP = "ring"


# --- facts owned by the kernel (one place each, to be redirected at merge) -----------


def _output_units() -> dict[str, str]:
    """Every design quantity a study records for every design, with its unit (the kernel's
    result table: scalars marked as objectives that every film model produces)."""
    from ..tables import SCALARS

    return {k: v.unit for k, v in SCALARS.items() if v.objective and not v.requires}


def _effective(case: Case, group: str, name: str) -> Any:
    """Value the kernel uses for ``&group name``: the deck's, its calibration file's, or the
    kernel's default."""
    return case.value(group, name)


def _input_unit(case: Case, group: str, name: str) -> str:
    """Unit of the input ``&group name`` (from the kernel's input table; the tension's is
    the case's ``tension_unit``)."""
    from ..tables import INPUTS

    spec = INPUTS.get((group, name))
    if spec is None:
        return ""
    if spec.unit == "(unit)":
        return str(_effective(case, "ring", "tension_unit"))
    return "" if spec.unit == "1" else spec.unit


def _is_unknown_variable(group: str, name: str) -> bool:
    """Is ``&group name`` missing from the kernel's input table?"""
    from ..tables import INPUTS

    return (group, name) not in INPUTS


def _is_whole_number(group: str, name: str) -> bool:
    """Is ``&group name`` an integer input of the kernel's table?"""
    from ..tables import INPUTS

    spec = INPUTS.get((group, name))
    return spec is not None and spec.kind == "integer"


def _text_input(group: str, name: str) -> str:
    """What ``&group name`` takes when it is not a number (``"text"``, ``"one of 'a', 'b'"``,
    ``".true. or .false."``, ``"a list of values"``), else ``""``."""
    from ..tables import INPUTS

    spec = INPUTS.get((group, name))
    if spec is None or spec.kind in ("real", "integer"):
        return ""
    if spec.kind == "choice":
        return "one of " + ", ".join(f"'{c}'" for c in spec.choices)
    if spec.kind.endswith("_list"):
        return "a list of values"
    return ".true. or .false." if spec.kind == "logical" else "text"


def _model_units() -> dict[str, str]:
    """Every design quantity a study may optimise, with its unit: the objective results of the
    kernel's table, including those only some film models produce (``oil_to_chamber``), and
    those it records when a study names them (``friction_power``, ``fmep``)."""
    from ..tables import SCALARS

    return {k: v.unit for k, v in SCALARS.items() if v.optimisable}


def _produces(case: Case, requires: str) -> bool:
    """Does a run of ``case`` produce results that need ``requires`` (a model of the kernel's
    table, :data:`ringlube.tables.MODELS`; '' always)?"""
    from ..tables import MODELS

    m = MODELS.get(requires)
    return m is None or case.value(m.group, m.variable) == m.value


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
    from ..tables import SCALARS

    return {**_model_units(), **{k: v.unit for k, v in SCALARS.items()}}


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
    """The files a base deck reads: itself, its calibration file, its pressure trace, its face
    profile (``profile = 'table'``) and its bore's distortion file (``bore = 'distorted'``).

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
    used = {
        ("ring", "profile_file"): _effective(case, "ring", "profile") == "table",
        ("bore", "distortion_file"): _effective(case, "physics", "bore") == "distorted",
    }
    for (group, name), read in used.items():
        f = case.get(group, name) if read else None
        if f:
            files.append(Path(f).resolve())
    return list(dict.fromkeys(files))


def _fingerprint(files: list[Path]) -> dict[str, str]:
    out = {}
    for p in files:
        try:
            out[str(p)] = hashlib.sha256(p.read_bytes()).hexdigest()
        except OSError as exc:
            raise InputError(f"{p}: cannot read ({exc.strerror or exc})") from None
    return out


def result_display(name: str) -> tuple[str, float]:
    """Unit a result is shown in and the factor from its stored unit: lengths (stored in
    metres, e.g. ``min_film``) in µm, every other result in its own unit.

    Parameters
    ----------
    name : str
        A result (:func:`~ringlube.study.variables.output_units`).

    Returns
    -------
    unit : str
    scale : float

    Example
    -------
    >>> result_display("min_film"), result_display("energy_loss")
    (('µm', 1000000.0), ('J', 1.0))
    """
    unit = output_units()[name]
    return ("µm", 1e6) if unit == "m" else (unit, 1.0)
