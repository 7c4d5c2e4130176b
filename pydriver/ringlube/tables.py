"""The kernel's tables, read from the compiled kernel: the one home of every input's
default, range, unit and description, of the numerics presets, and of the names, units
and descriptions of every result.

Nothing here is written by hand: each table is the tab-separated text that the kernel
exports (``fortran/src/inputs.f90`` and ``fortran/src/results.f90``).

>>> from ringlube.tables import INPUTS, SCALARS
>>> INPUTS["ring", "width"].unit
'm'
>>> SCALARS["energy_loss"].unit
'J'
"""

from __future__ import annotations

import dataclasses
from functools import cache

__all__ = [
    "InputSpec",
    "FieldSpec",
    "INPUTS",
    "PRESETS",
    "SERIES",
    "INT_SERIES",
    "SCALARS",
    "FLAG_BITS",
    "FLAGS",
    "LINER",
    "SECTORS",
    "ModelSpec",
    "MODELS",
    "MarginSpec",
    "MARGINS",
    "GROUPS",
    "table_text",
]


@dataclasses.dataclass(frozen=True)
class InputSpec:
    """One input variable of the kernel's table.

    Attributes
    ----------
    group, name : str
        Namelist group and variable.
    kind : str
        'real', 'integer', 'logical', 'string', 'choice', or 'real_list' / 'integer_list'
        (a list of values: ``&bore amplitude = 10e-6, 5e-6``).
    default : str
        Default as deck text ('(preset)': set by the numerics preset 'default').
    lower, upper : float
        Plausible range of a number (inclusive).
    unit : str
        Unit of the value in a deck ('1' dimensionless; '(unit)' for the tension, see
        ``tension_unit``).
    choices : tuple of str
        Allowed values of a choice.
    description : str
        One line.

    Examples
    --------
    >>> INPUTS["numerics", "nodes"].kind, INPUTS["ring", "tension_unit"].choices
    ('integer', ('N', 'N/m'))
    """

    group: str
    name: str
    kind: str
    default: str
    lower: float
    upper: float
    unit: str
    choices: tuple[str, ...]
    description: str

    @property
    def default_value(self):
        """The default as a Python value (None where a preset sets it)."""
        if self.default == "(preset)":
            return PRESETS["default"].get(self.name)
        return typed_value(self.kind, self.default)


@dataclasses.dataclass(frozen=True)
class FieldSpec:
    """One result quantity: ``short`` name (Python, studies), ``stored`` name (HDF5),
    ``unit``, ``kind`` ('real'; 'integer', a count, or 'logical', 1 or 0: whole numbers,
    stored as integers), ``long_name`` and ``requires`` ('' always produced, 'jfo' only by
    the mass-conserving film, 'starved' only with a starved inlet, 'gas' only with the ring
    pack), ``objective`` (a design quantity a study records for every design and may
    optimise) and ``optimisable`` (a study may optimise it: the objectives, and results it
    records when a study names them, e.g. ``friction_power``).

    Examples
    --------
    >>> SERIES["h0"].stored, SCALARS["oil_to_chamber"].requires, SCALARS["converged"].kind
    ('h0_m', 'starved', 'logical')
    """

    short: str
    stored: str
    unit: str
    kind: str
    long_name: str
    requires: str = ""
    objective: bool = False
    optimisable: bool = False

    def value(self, x: float):
        """A stored number as this quantity's Python value: bool for 'logical', int for
        'integer', float for 'real'.

        >>> SCALARS["converged"].value(1.0), SCALARS["cycles_run"].value(3.0)
        (True, 3)
        """
        if self.kind == "logical":
            return bool(x)
        return int(x) if self.kind == "integer" else float(x)


@dataclasses.dataclass(frozen=True)
class ModelSpec:
    """An optional model: the results whose ``requires`` is ``name`` exist when the input
    ``&group variable`` is ``value``.

    Examples
    --------
    >>> m = MODELS["starved"]
    >>> m.group, m.variable, m.value
    ('physics', 'inlet', 'starved')
    """

    name: str
    group: str
    variable: str
    value: str


def table_text(which: str) -> str:
    """The kernel's table ``which`` as tab-separated text (header line first).

    Parameters
    ----------
    which : str
        'inputs', 'presets', 'series', 'int_series', 'scalars', 'flags', 'liner', 'sectors' or
        'models'.

    Returns
    -------
    str
        '' for an unknown table.

    Examples
    --------
    >>> table_text("flags").splitlines()[0].split()
    ['bit', 'name', 'description']
    """
    from . import _kernel

    text, n = _kernel.rl_table(which)
    return bytes(text[:n]).decode() if isinstance(text, bytes) else str(text)[:n]


def _rows(which: str) -> list[list[str]]:
    lines = table_text(which).splitlines()
    return [line.split("\t") for line in lines[1:] if line]


def typed_value(kind: str, text: str):
    """A value of the kernel's tables as Python: ``kind`` 'real', 'integer', 'logical' (a
    list of them with ``_list``), else the text."""
    if kind.endswith("_list"):
        return [typed_value(kind[: -len("_list")], t) for t in text.replace(",", " ").split()]
    if kind == "real":
        return float(text.replace("d", "e").replace("D", "e"))
    if kind == "integer":
        return int(text)
    if kind == "logical":
        return text.strip(".").lower().startswith("t")
    return text


@cache
def _load():
    inputs = {}
    for g, n, kind, default, lo, hi, unit, choices, desc in _rows("inputs"):
        inputs[g, n] = InputSpec(
            g, n, kind, default, float(lo), float(hi), unit, tuple(c for c in choices.split("|") if c), desc
        )
    presets: dict[str, dict] = {}
    for preset, name, value in _rows("presets"):
        kind = inputs["numerics", name].kind
        presets.setdefault(preset, {})[name] = typed_value(kind, value)

    def fields(which):
        return {r[0]: FieldSpec(*r[:6], r[6] == "1", r[7] == "1") for r in _rows(which)}

    flags = {int(b): desc for b, _, desc in _rows("flags")}
    return (
        inputs,
        presets,
        fields("series"),
        fields("int_series"),
        fields("scalars"),
        flags,
        fields("liner"),
        fields("sectors"),
    )


INPUTS: dict[tuple[str, str], InputSpec]
PRESETS: dict[str, dict]
SERIES: dict[str, FieldSpec]
INT_SERIES: dict[str, FieldSpec]
SCALARS: dict[str, FieldSpec]
FLAG_BITS: dict[int, str]
LINER: dict[str, FieldSpec]
#: the series per crank step and sector of a distorted bore (crank angle x sector)
SECTORS: dict[str, FieldSpec]
INPUTS, PRESETS, SERIES, INT_SERIES, SCALARS, FLAG_BITS, LINER, SECTORS = _load()
#: the bit of each ``/cycle/flags`` condition by its name in the kernel's table, e.g.
#: ``FLAGS["h0_ceiling"]`` (lift-off)
FLAGS: dict[str, int] = {name: int(b) for b, name, _ in _rows("flags")}
#: the optional models by the name results give in ``requires``: which input selects each
MODELS: dict[str, ModelSpec] = {r[0]: ModelSpec(*r) for r in _rows("models")}


@dataclasses.dataclass(frozen=True)
class MarginSpec:
    """A branch-risk margin's threshold and why (docs/model.md, "Branch risk"): a run whose
    |margin| is below it is warned of, and a study marks the design.

    Examples
    --------
    >>> MARGINS["lift_margin"].threshold
    0.01
    """

    name: str
    threshold: float
    reason: str


#: the branch-risk margins (results ``lift_margin``, ``seal_margin``) by name
MARGINS: dict[str, MarginSpec] = {r[0]: MarginSpec(r[0], float(r[1]), r[2]) for r in _rows("margins")}

#: Namelist groups of a deck, in table order.
GROUPS: tuple[str, ...] = tuple(dict.fromkeys(g for g, _ in INPUTS))


def _num(x: float) -> str:
    return f"{x:g}"


def inputs_markdown() -> str:
    """The input table of docs/model.md (generated from the kernel's table)."""
    lines = [
        "| group | variable | default | range or choices | unit | meaning |",
        "|---|---|---|---|---|---|",
    ]
    for (g, n), s in INPUTS.items():
        if s.kind in ("real", "integer"):
            rng = f"{_num(s.lower)} .. {_num(s.upper)}"
        elif s.kind == "choice":
            rng = " \\| ".join(f"'{c}'" for c in s.choices)
        elif s.kind == "logical":
            rng = ".true. \\| .false."
        else:
            rng = "text"
        default = s.default
        if default == "(preset)":
            default = f"{PRESETS['default'][n]} (preset 'default')"
        elif s.kind in ("string", "choice"):
            default = f"'{default}'"
        unit = {"1": "-", "(unit)": "see tension_unit", "": ""}.get(s.unit, s.unit)
        lines.append(f"| `&{g}` | `{n}` | {default} | {rng} | {unit} | {s.description.replace('|', '/')} |")
    lines += [
        "",
        "Numerics presets (`&numerics preset`; values given explicitly override them):",
        "",
        "| preset | " + " | ".join(next(iter(PRESETS.values()))) + " |",
        "|---|" + "---|" * len(next(iter(PRESETS.values()))),
    ]
    for name, values in PRESETS.items():
        lines.append(
            f"| '{name}' | "
            + " | ".join(_num(v) if isinstance(v, float) else str(v) for v in values.values())
            + " |"
        )
    return "\n".join(lines)


def results_markdown() -> str:
    """The result table of docs/model.md (generated from the kernel's tables)."""
    note = {"": "", **{m.name: f" (`{m.variable} = '{m.value}'` only)" for m in MODELS.values()}}
    lines = ["| where | HDF5 name | Python name | unit | meaning |", "|---|---|---|---|---|"]

    def row(where: str, s: FieldSpec, python: str) -> None:
        lines.append(f"| {where} | `{s.stored}` | `{python}` | {s.unit} | {s.long_name}{note[s.requires]} |")

    for s in SCALARS.values():
        row("root attribute", s, s.short)
    for s in [*SERIES.values(), *INT_SERIES.values()]:
        row("`/cycle`", s, s.short)
    for s in SECTORS.values():
        row("`/cycle` (crank angle x sector)", s, s.short)
    for s in LINER.values():
        row("`/liner`", s, f"liner['{s.short}']")
    lines += [
        "",
        "Every input of the case is also a root attribute `group.name` (e.g. `ring.width`): its "
        "effective value (deck, calibration file, preset or default; `Case.value(group, name)`) in "
        "the unit of the [input table](#inputs), logicals as 0/1, choices and paths as text.",
        "",
        "A distorted bore's run also has a root attribute `conformability_<k>` for each order k of "
        "its distortion: A_k over its conformability limit (`conformability_by_order[k]` in Python; "
        "`conformability` is the largest).",
    ]
    lines += ["", "Bits of `/cycle/flags`: " + "; ".join(f"{b}: {d}" for b, d in FLAG_BITS.items()) + "."]
    return "\n".join(lines)
