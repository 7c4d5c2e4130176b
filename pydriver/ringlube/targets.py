"""Measured or published results to calibrate against and validate with, read from a CSV
file (the shipped one is Table 2 of the source study, ``inputs/targets_table2.csv``).

Columns: ``condition, deck, quantity, value, unit``; ``#`` lines are comments. ``deck`` is
relative to the file's folder; ``quantity`` is a scalar result (``ringlube.tables.SCALARS``)
and ``unit`` must be its unit.

>>> from ringlube.targets import read_targets, DEFAULT_TARGETS
>>> t = read_targets(DEFAULT_TARGETS)
>>> t["cold"].values["energy_loss"]
1.92
"""

from __future__ import annotations

import csv
import dataclasses
import math
import os
from pathlib import Path

from .errors import InputError
from .tables import SCALARS

__all__ = ["Condition", "read_targets", "DEFAULT_TARGETS"]


#: Results that cannot be negative (a negative target is a typing mistake).
_NON_NEGATIVE = frozenset(
    {"energy_loss", "mixed_share", "ring_mass", "min_film", "max_friction", "friction_power", "fmep"}
)


def _default() -> Path:
    from .examples import examples_dir

    return examples_dir() / "targets_table2.csv"


@dataclasses.dataclass
class Condition:
    """The targets of one condition: its deck and {quantity: value} in the result's unit.

    Examples
    --------
    >>> read_targets(DEFAULT_TARGETS)["hot"].values["mixed_share"]
    12.5
    """

    name: str
    deck: Path
    values: dict[str, float]


def read_targets(path: str | os.PathLike) -> dict[str, Condition]:
    """Read a targets file.

    Parameters
    ----------
    path : str or path-like

    Returns
    -------
    dict of str to Condition
        By condition name, in file order.

    Raises
    ------
    InputError
        Naming the file and line of a missing column, an unknown quantity, a wrong unit, a
        value that is not a finite number, a negative energy, share, mass, film or
        friction, a quantity given twice for one condition, a condition with two decks, or
        text that is not UTF-8 (a leading byte-order mark is accepted).

    Examples
    --------
    >>> sorted(read_targets(DEFAULT_TARGETS))
    ['cold', 'hot']
    """
    path = Path(path)
    if not path.is_file():
        raise InputError(f"{path}: targets file not found")
    out: dict[str, Condition] = {}
    try:  # utf-8-sig: a byte-order mark (as spreadsheets write) is not part of the header
        text = path.read_text(encoding="utf-8-sig")
    except UnicodeDecodeError as exc:
        line = path.read_bytes()[: exc.start].count(b"\n") + 1
        raise InputError(
            f"{path}:{line}: not UTF-8 text (byte 0x{exc.object[exc.start]:02x}); save the file as UTF-8"
        ) from None
    lines = text.splitlines(keepends=True)
    rows = [(n, line) for n, line in enumerate(lines, 1) if line.strip() and not line.startswith("#")]
    reader = csv.DictReader([line for _, line in rows])
    need = {"condition", "deck", "quantity", "value", "unit"}
    if not need <= set(reader.fieldnames or ()):
        raise InputError(f"{path}: header must name the columns {', '.join(sorted(need))}")
    for (lineno, _), row in zip(rows[1:], reader):
        where = f"{path}:{lineno}"
        q = (row["quantity"] or "").strip()
        if q not in SCALARS:
            raise InputError(f"{where}: unknown quantity '{q}' (known: {', '.join(SCALARS)})")
        unit = (row["unit"] or "").strip()
        if unit != SCALARS[q].unit:
            raise InputError(f"{where}: {q} is in {SCALARS[q].unit}, not '{unit}'")
        try:
            value = float(row["value"])
        except (TypeError, ValueError):
            value = math.nan
        if not math.isfinite(value):
            raise InputError(f"{where}: value '{row['value']}' is not a finite number")
        name = (row["condition"] or "").strip()
        deck = (path.parent / (row["deck"] or "").strip()).resolve()
        if value < 0 and q in _NON_NEGATIVE:
            raise InputError(f"{where}: {q} = {value:g}: must not be negative")
        cond = out.setdefault(name, Condition(name, deck, {}))
        if cond.deck != deck:
            raise InputError(f"{where}: condition '{name}' already uses the deck {cond.deck}")
        if q in cond.values:
            raise InputError(f"{where}: condition '{name}' gives {q} twice; keep one row")
        cond.values[q] = value
    return out


DEFAULT_TARGETS = _default()
