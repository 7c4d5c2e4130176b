"""Namelist values as text: numbers made plain, values and groups written as a deck."""

from __future__ import annotations

import decimal
import numbers
from typing import Any

from ..errors import InputError

__all__: list[str] = []


def _plain_number(group: str, name: str, value: Any) -> Any:
    """A number of another type as a plain float (``Decimal``, ``Fraction``, a float
    subclass), and a whole float given to an integer input as an int; other values as given.

    Raises
    ------
    InputError
        For a fractional number given to an integer input (the message names it).

    Examples
    --------
    >>> import decimal
    >>> _plain_number("ring", "width", decimal.Decimal("1.1e-3"))
    0.0011
    >>> _plain_number("numerics", "nodes", 41.0)
    41
    """
    if isinstance(value, bool) or not isinstance(value, (numbers.Real, decimal.Decimal)):
        return value
    if isinstance(value, int):
        return value
    value = float(value)  # Decimal, Fraction: numbers, not strings
    from ..tables import INPUTS

    spec = INPUTS.get((group, name))
    if spec is not None and spec.kind == "integer":
        if not value.is_integer():
            raise InputError(f"&{group} {name}: {value!r} is not a whole number (an integer input)")
        value = int(value)
    return value


def format_value(value: Any) -> str:
    if isinstance(value, bool):
        return ".true." if value else ".false."
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        return repr(value) if value == value else "nan"
    if isinstance(value, (list, tuple)):
        return ", ".join(format_value(v) for v in value)
    s = str(value)
    return "'" + s.replace("'", "''") + "'"


def _serialise(groups) -> str:
    out = []
    for group, values in groups.items():
        out.append(f"&{group}")
        for name, value in values.items():
            out.append(f"    {name} = {format_value(value)}")
        out.append("/")
    return "\n".join(out) + "\n"
