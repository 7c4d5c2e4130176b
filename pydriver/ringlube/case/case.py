"""A ringlube case: a namelist deck you can read, change, validate and hand to the kernel.

A case reaches the kernel in memory, as deck text plus the folder its relative paths are
resolved against; the kernel parses it once with the same reader as ``ringlube-solve``.
A case read from a file keeps the file's text, so kernel messages name the real file and
line; values changed in Python travel as overrides that replace the deck's (messages about
them name ``<case NAME: changed in Python>``). A case built in Python resolves relative
paths against the working directory. The values a case shows (``case[group, name]``) are
the deck's items as the kernel's scanner reads them (:mod:`ringlube.case.items`): one
reader, no second namelist parser.
"""

from __future__ import annotations

import html
import os
import re
from pathlib import Path
from typing import Any

from ..errors import InputError, input_file
from .items import items, python_value
from .kernel import kernel_case
from .origins import _InputOrigins
from .text import _plain_number, _serialise, format_value

__all__ = ["Case", "GROUPS"]


def _groups() -> tuple[str, ...]:
    from ..tables import GROUPS as groups

    return groups


#: Namelist groups of a deck (from the kernel's input table; set at the end of the module).
GROUPS: tuple[str, ...] = ()
_PATH_VARS = {
    ("operating", "pressure_file"),
    ("ring", "profile_file"),
    ("output", "file"),
    ("calibration", "file"),
    ("bore", "distortion_file"),
}
_NAME = re.compile(r"[a-z_][a-z0-9_]*")


class Case(_InputOrigins):
    """One operating point and ring design, held as a namelist.

    Values are addressed by group and variable, ``case["ring", "width"]``; anything not
    set takes the kernel's documented default (see :meth:`value`).

    Parameters
    ----------
    groups : dict of dict, optional
        ``{group: {name: value}}`` to start from.
    name : str
        Name used in messages and as the default label of results.
    source : str or path-like, optional
        The deck this case came from (for messages).

    Examples
    --------
    >>> case = Case.from_namelist("inputs/crf450r_4000rpm_full_cold.nml")
    >>> wider = case.with_ring(width=1.2e-3)
    >>> wider["ring", "width"]
    0.0012
    """

    def __init__(
        self,
        groups: dict[str, dict[str, Any]] | None = None,
        name: str = "case",
        source: str | os.PathLike | None = None,
    ):
        self.name = name
        #: The deck this case was read from (named in error messages), if any.
        self.source = str(source) if source is not None else None
        self._nml: dict[str, dict[str, Any]] = {}  # the values set: {group: {name: value}}
        self._text: str | None = None  # the deck file's text, if read from one
        self._base: str | None = None  # folder of relative paths in _text
        self._changed: dict[tuple[str, str], Any] = {}
        for group, values in (groups or {}).items():
            self.set(group, **values)

    # construction and I/O -------------------------------------------------------------
    @classmethod
    def from_namelist(cls, path: str | os.PathLike) -> Case:
        """Read a deck; the kernel checks it first (messages name file, line and variable).

        Parameters
        ----------
        path : str or path-like
            The deck file.

        Returns
        -------
        Case
            With relative paths made absolute (relative to the deck's folder).

        Raises
        ------
        InputError
            If the file is missing, unreadable or any value is bad.

        Examples
        --------
        >>> Case.from_namelist("inputs/crf450r_4000rpm_full_cold.nml").name
        'crf450r_4000rpm_full_cold'
        """
        path = input_file(path, not_file="not a regular file (a folder or a device), not a deck")
        try:
            # bytes that are not UTF-8 travel through unchanged (surrogateescape), as in
            # ringlube-solve, which reads the deck as bytes
            text = path.read_bytes().decode("utf-8", "surrogateescape")
        except OSError as exc:
            raise InputError(f"{path}: cannot read the deck: {exc.strerror}") from None
        case = cls(name=path.stem, source=path)
        case._text = text
        case._base = str(path.resolve().parent)
        with kernel_case(case, load_trace=False, warn=False):
            pass  # the kernel's reader first: every error names file:line, group and variable
        from ..tables import INPUTS

        for item in items(text, str(path), lists=True):  # the same scanner: values as written
            value = python_value(item)
            spec = INPUTS.get((item.group, item.name))
            if spec is not None and spec.kind.endswith("_list"):  # (&bore order = 2, 4)
                value = [*case._nml.get(item.group, {}).get(item.name, [])[: item.index - 1], value]
            case._set(item.group, {item.name: value}, record=False)
        for group, var in _PATH_VARS:
            value = case.get(group, var)
            if value and not os.path.isabs(value):
                case._set(group, {var: str((path.parent / value).resolve())}, record=False)
        return case

    def to_namelist(self, path: str | os.PathLike | None = None) -> str:
        """The deck as text (relative paths absolute); also written to ``path`` if given.

        Parameters
        ----------
        path : str or path-like, optional
            File to write.

        Returns
        -------
        str
            Namelist text the kernel reads.

        Examples
        --------
        >>> print(Case({"ring": {"width": 1e-3}}).to_namelist().strip())
        &ring
            width = 0.001
        /
        """
        text = _serialise(self._nml)
        if path is not None:
            try:
                Path(path).write_text(text, encoding="utf-8", errors="surrogateescape")
            except OSError as exc:
                raise InputError(f"{path}: cannot write the deck: {exc.strerror}") from None
        return text

    # access ---------------------------------------------------------------------------
    def get(self, group: str, name: str, default: Any = None) -> Any:
        """Value of ``&group name`` as set in the deck or in Python, else ``default``.

        Examples
        --------
        >>> Case({"ring": {"width": 1e-3}}).get("ring", "tension", "unset")
        'unset'
        """
        group, name = group.lower(), name.lower()
        return self._nml.get(group, {}).get(name, default)

    def value(self, group: str, name: str) -> Any:
        """The effective value of ``&group name``: the deck's, its calibration file's or
        the kernel's default, as the kernel reads it (paths resolved).

        Raises
        ------
        InputError
            For an unknown variable or a case the kernel rejects.

        Examples
        --------
        >>> Case().value("ring", "tension_unit")
        'N'
        """
        from ..tables import INPUTS

        spec = INPUTS.get((group.lower(), name.lower()))
        if spec is None:
            raise InputError(f"&{group} {name}: unknown variable")
        return self._effective(spec)  # one kernel handle for every input, kept

    def set(self, group: str, **values: Any) -> Case:
        """Set variables of one group in place; returns the case.

        Raises
        ------
        InputError
            For a group the kernel does not know (unknown variables are reported by the
            kernel when the case is validated or run).

        Examples
        --------
        >>> Case().set("ring", width=1.2e-3)["ring", "width"]
        0.0012
        """
        return self._set(group, values, record=True)

    def _set(self, group: str, values: dict, record: bool) -> Case:
        group = str(group).lower()
        if group not in GROUPS:
            raise InputError(f"unknown namelist group &{group} (known: {', '.join(GROUPS)})")
        names = [str(n).lower() for n in values]
        twice = sorted({n for n in names if names.count(n) > 1})
        if twice:  # names are case-insensitive: 'gamma' and 'GAMMA' are one variable
            given = ", ".join(str(n) for n in values if str(n).lower() in twice)
            raise InputError(f"&{group} {twice[0]}: given twice ({given}); give it once")
        self._nml.setdefault(group, {})
        for name, value in values.items():
            name = str(name).lower()
            if not _NAME.fullmatch(name):
                raise InputError(f"&{group} {name!r}: not a variable name")
            if hasattr(value, "tolist"):  # numpy scalar -> Python scalar, array -> list
                value = value.tolist()
            if isinstance(value, (list, tuple)):  # numpy scalars in a list: Python scalars
                value = [v.tolist() if hasattr(v, "tolist") else v for v in value]
                if any(isinstance(v, (list, tuple)) for v in value):
                    raise InputError(f"&{group} {name}: a list of lists; a list input takes one flat list")
            if isinstance(value, os.PathLike):
                value = os.fspath(value)
            value = _plain_number(group, name, value)
            if (
                record
                and (group, name) in _PATH_VARS
                and isinstance(value, str)
                and value
                and not os.path.isabs(value)
                and self._text is None
            ):
                # a relative path set in Python means the working directory of now
                value = os.path.abspath(value)
            self._nml[group][name] = value
            if record:
                self._changed[group, name] = value
        return self

    def __getitem__(self, key: tuple[str, str]) -> Any:
        if not (isinstance(key, tuple) and len(key) == 2 and all(isinstance(k, str) for k in key)):
            raise KeyError(f"use case[group, name], not case[{key!r}]{_close_input(key)}")
        from ..tables import INPUTS

        if (key[0].lower(), key[1].lower()) not in INPUTS:
            raise KeyError(f"&{key[0]} {key[1]}: not an input{_close_input(key)}")
        return self.get(*key)

    def __setitem__(self, key: tuple[str, str], value: Any) -> None:
        if not (isinstance(key, tuple) and len(key) == 2):
            raise KeyError(f"use case[group, name], not case[{key!r}]")
        self.set(key[0], **{key[1]: value})

    def to_dict(self) -> dict[str, dict[str, Any]]:
        """Plain nested dict of the values set.

        Examples
        --------
        >>> Case({"ring": {"width": 1e-3}}).to_dict()
        {'ring': {'width': 0.001}}
        """
        return {g: dict(v) for g, v in self._nml.items()}

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Case) and self.to_dict() == other.to_dict()

    def __repr__(self) -> str:
        """The values set, one group a line, those changed in Python marked with '*'."""
        where = f" from {self.source}" if self.source else ""
        lines = [f"<Case {self.name!r}{where}: {self._count()} inputs set, the rest defaults>"]
        for group, values in self._nml.items():
            items = ", ".join(
                f"{n} = {format_value(v)}{'*' if (group, n) in self._changed and self._text else ''}"
                for n, v in values.items()
            )
            lines.append(f"  &{group:<10} {items}")
        if self._changed and self._text:
            lines.append("  (* changed in Python)")
        return "\n".join(lines)

    def _repr_html_(self) -> str:
        """A table of the values set (Jupyter)."""
        from ..tables import INPUTS

        where = f" from <code>{html.escape(self.source)}</code>" if self.source else ""
        rows = []
        for group, values in self._nml.items():
            for n, v in values.items():
                spec = INPUTS.get((group, n))
                unit = spec.unit if spec and spec.unit not in ("1", "(unit)") else ""
                origin = "deck" if self._text and (group, n) not in self._changed else "Python"
                rows.append(
                    f"<tr><td>&amp;{group}</td><td>{html.escape(n)}</td><td>{html.escape(format_value(v))}</td>"
                    f"<td>{html.escape(unit)}</td><td>{origin}</td></tr>"
                )
        return (
            f"<p>Case <b>{html.escape(self.name)}</b>{where}: {self._count()} inputs set, the rest defaults "
            "(<code>case.effective_inputs()</code> lists all)</p>"
            "<table><tr><th>group</th><th>variable</th><th>value</th><th>unit</th><th>from</th></tr>"
            + "".join(rows)
            + "</table>"
        )

    def _count(self) -> int:
        return sum(len(v) for v in self._nml.values())

    # variants -------------------------------------------------------------------------
    def copy(self) -> Case:
        """An independent copy (values are immutable scalars, so copying groups suffices)."""
        new = Case.__new__(Case)
        new.name, new.source = self.name, self.source
        new._text, new._base = self._text, self._base
        new._changed = dict(self._changed)
        new._nml = {group: dict(values) for group, values in self._nml.items()}
        return new

    def with_(self, group: str, **values: Any) -> Case:
        """A copy with variables of ``group`` changed (``with_<group>`` for each group, e.g.
        :meth:`with_ring`, checks the names against the kernel's table first).

        Parameters
        ----------
        group : str
            Namelist group.
        **values
            Variables and their new values.

        Examples
        --------
        >>> Case().with_("ring", width=1e-3)["ring", "width"]
        0.001
        """
        return self.copy().set(group, **values)

    def inline_calibration(self) -> Case:
        """A copy with the calibration file's values written into the case itself (and no
        calibration file), so that any calibrated variable can then be changed."""
        path = self.get("calibration", "file")
        c = self.copy()
        if not path:
            return c
        c.set("calibration", file="")
        c._nml.pop("calibration", None)
        for group, values in Case.from_namelist(path).to_dict().items():
            c.set(group, **values)
        return c

    # checking -------------------------------------------------------------------------
    def validate(self) -> int:
        """Check the case with the kernel's own reader; returns the number of crank steps.

        Raises
        ------
        InputError
            Naming the group and variable of a bad value. The gas pressure file is checked
            to exist here; its rows are checked when the case runs.

        Examples
        --------
        >>> Case().with_numerics(dpsi_deg=2.0).validate()
        360
        """
        with kernel_case(self, load_trace=False) as k:
            return k.nsteps

    # what the kernel receives ---------------------------------------------------------
    def kernel_inputs(self) -> tuple[str, str, str, str, str]:
        """(deck text, name in messages, base folder, overrides text, overrides name)."""
        label = f"<case {self.name}: changed in Python>"
        if self._text is not None:
            changed: dict[str, dict] = {}
            for (g, n), v in self._changed.items():
                changed.setdefault(g, {})[n] = v
            overrides = _serialise(changed) if changed else ""
            return self._text, str(self.source), self._base or "", overrides, label
        return self.to_namelist(), f"<case {self.name}>", os.getcwd(), "", label


def _with_group(group: str):
    """The method ``Case.with_<group>``, its docstring listing the group's variables."""
    from ..tables import INPUTS, PRESETS

    specs = [s for (g, _), s in INPUTS.items() if g == group]
    known = [s.name for s in specs]

    def method(self: Case, **values: Any) -> Case:
        import difflib

        for name in values:
            if name.lower() not in known:
                near = difflib.get_close_matches(name.lower(), known, n=1)
                hint = f"; did you mean {near[0]}?" if near else f" (known: {', '.join(known)})"
                raise InputError(f"&{group} {name}: unknown variable{hint}")
        return self.with_(group, **values)

    def row(s) -> str:
        default = s.default if s.default != "(preset)" else f"{PRESETS['default'][s.name]} (preset)"
        unit = {"1": "", "(unit)": " [see tension_unit]"}.get(s.unit, f" [{s.unit}]" if s.unit else "")
        return f"    {s.name}{unit}, default {default}: {s.description}"

    first = specs[0]
    if first.kind == "string":  # a path: made absolute when set in Python
        call = f'Case().with_{group}({first.name}="x.txt")["{group}", "{first.name}"]'
        example = f'>>> {call}.endswith("x.txt")\nTrue'
    else:
        value = _example(first)
        example = f'>>> Case().with_{group}({first.name}={value})["{group}", "{first.name}"]\n{value}'
    method.__name__ = f"with_{group}"
    method.__qualname__ = f"Case.with_{group}"
    method.__doc__ = (
        f"A copy with ``&{group}`` variables changed (names checked against the kernel's table).\n\n"
        "Parameters\n----------\n**values\n"
        + "\n".join(row(s) for s in specs)
        + f"\n\nExamples\n--------\n{example}\n"
    )
    return method


def _example(spec) -> str:
    """A value of ``spec`` as Python text (the default where there is one)."""
    from ..tables import PRESETS, typed_value

    if spec.kind == "choice":
        return repr(spec.choices[-1])
    if spec.default == "(preset)":
        return repr(PRESETS["default"][spec.name])
    return repr(typed_value(spec.kind, spec.default))


GROUPS = _groups()
for _group in GROUPS:
    setattr(Case, f"with_{_group}", _with_group(_group))
del _group


def _close_input(key: Any) -> str:
    """ "; did you mean ..." for a key near an input of the kernel's table: a (group, name)
    pair near one, or a word near a group or the name of a variable."""
    import difflib

    from ..tables import INPUTS

    if isinstance(key, tuple) and len(key) == 2:
        pairs = {f"{g}, {n}": (g, n) for g, n in INPUTS}
        near = difflib.get_close_matches(f"{key[0]}, {key[1]}".lower(), pairs, 1, 0.6)
        found = ["case['{}', '{}']".format(*pairs[m]) for m in near]
    else:
        word = str(key).lower()
        found = [f"case['{g}', name]" for g in difflib.get_close_matches(word, GROUPS, 1, 0.75)]
        found += [f"case['{g}', '{n}']" for g, n in INPUTS if n == word]
    return f"; did you mean {' or '.join(found)}?" if found else ""
