"""Namelist text split into items by the kernel's own scanner (``fortran/src/namelist.f90``).

One reader for every deck: the kernel's decks (:class:`~ringlube.case.Case`), the calibration
files they include and the ``&study`` decks (:mod:`ringlube.study.deck`). The scanner gives
each ``name = value`` with its file and line, so every error can name file:line, group and
variable. Kernel decks take one value per variable; a caller that allows lists (``&study``)
gets one :class:`Item` per value, numbered by ``index``.

Values are the text as written (quotes removed); :func:`python_value` turns one into a
Python value the way the deck spells it (``8`` an int, ``8.0`` a float, ``.true.`` a bool,
``'x'`` a str), as f90nml did before this module replaced it.

>>> [(i.group, i.name, i.value, i.line) for i in items("&ring\\n width = 1e-3 /\\n", "d.nml")]
[('ring', 'width', '1e-3', 2)]
"""

from __future__ import annotations

import re
from typing import Any, NamedTuple

import numpy as np

from ..errors import error_for
from .kernel import _arg, _deck_text, kernel_text

__all__ = ["Item", "items", "python_value"]

_INT = re.compile(r"[+-]?\d+")
#: logicals as the kernel reads them (fortran/src/case.f90)
LOGICALS = {".true.": True, ".t.": True, "t": True, "true": True}
LOGICALS |= {".false.": False, ".f.": False, "f": False, "false": False}


class Item(NamedTuple):
    """One value of a namelist deck, as the kernel's scanner reads it.

    Attributes
    ----------
    group, name : str
        Group and variable (lower case).
    value : str
        The value as written (quotes removed, doubled quotes undone).
    line : int
        Line of the value (1-based).
    index : int
        Position of the value in its variable's list (1: the first, or a scalar).
    quoted : bool
        Whether the value was a quoted string.
    group_line : int
        Line on which the item's group opens (tells two groups of one name apart).
    file : str
        The text's name in messages (its path).

    Examples
    --------
    >>> Item("study", "samples", "64", 3, 1, False, 1, "s.nml").where
    's.nml:3'
    """

    group: str
    name: str
    value: str
    line: int
    index: int
    quoted: bool
    group_line: int
    file: str

    @property
    def where(self) -> str:
        """'file:line' of the item."""
        return f"{self.file}:{self.line}"


def _str(raw, n: int | None = None) -> str:
    b = bytes(raw)
    b = b[:n] if n is not None else b.rstrip(b" \0")
    return b.decode("utf-8", "surrogateescape")


def items(text: str, name: str, lists: bool = False) -> list[Item]:
    """The items of namelist ``text`` (named ``name`` in messages), in the order written.

    Parameters
    ----------
    text : str
        Deck text (a UTF-8 byte-order mark is skipped).
    name : str
        Name of the text in messages (its path).
    lists : bool
        Let a variable take a list of values (one item per value); else a second value is
        an error naming file:line, group and variable.

    Returns
    -------
    list of Item

    Raises
    ------
    InputError
        For text the scanner refuses (the message names file:line, and the group and
        variable where there is one).

    Examples
    --------
    >>> [i.value for i in items("&study w = 1, 2\\n 3 /", "s.nml", lists=True)]
    ['1', '2', '3']
    >>> items("&ring width = 1, 2 /", "d.nml")
    Traceback (most recent call last):
    ...
    ringlube.errors.InputError: d.nml:1: &ring width: malformed value "1 2" (one value per variable)
    """
    from .. import _kernel

    flag = 1 if lists else 0
    n, nbytes, code, message = _kernel.rl_items_count(_deck_text(text, name), _arg(name), flag)
    if code:
        raise error_for(code, kernel_text(message))
    if n == 0:
        return []
    groups, names, chars, vlen, lines, indices, quoted, glines, code, message = _kernel.rl_items(
        _arg(text), _arg(name), flag, n, nbytes
    )
    if code:
        raise error_for(code, kernel_text(message))
    raw = chars.tobytes()
    ends = np.cumsum(vlen)
    return [
        Item(
            _str(groups[i]),
            _str(names[i]),
            raw[ends[i] - vlen[i] : ends[i]].decode("utf-8", "surrogateescape"),
            int(lines[i]),
            int(indices[i]),
            bool(quoted[i]),
            int(glines[i]),
            name,
        )
        for i in range(n)
    ]


def python_value(item: Item) -> Any:
    """The value of ``item`` as a Python value, typed by how it is written: quoted -> str,
    a logical (``.true.``, ``T``, ``.f.``, as the kernel reads them) -> bool, a whole number
    -> int, else float (``d`` exponents read as ``e``).

    Parameters
    ----------
    item : Item
        One value of a deck.

    Returns
    -------
    str, bool, int or float

    Raises
    ------
    ValueError
        For unquoted text that is none of these (the caller names the item).

    Examples
    --------
    >>> [python_value(i) for i in items("&s a = 8, 8.0, 1d-3, .true., 'x' /", "s", True)]
    [8, 8.0, 0.001, True, 'x']
    """
    v = item.value
    if item.quoted:
        return v
    if _INT.fullmatch(v):
        return int(v)
    if v.lower() in LOGICALS:
        return LOGICALS[v.lower()]
    return float(v.replace("d", "e").replace("D", "e"))
