"""A ringlube case: a namelist deck you can read, change, validate and hand to the kernel.

A case reaches the kernel in memory, as deck text plus the folder its relative paths are
resolved against; the kernel parses it once with the same reader as ``ringlube-solve``.
A case read from a file keeps the file's text, so kernel messages name the real file and
line; values changed in Python travel as overrides that replace the deck's (messages about
them name ``<case NAME: changed in Python>``). A case built in Python resolves relative
paths against the working directory.
"""

from __future__ import annotations

import contextlib
import numbers
import os
import re
from collections.abc import Iterator
from pathlib import Path
from typing import Any, NamedTuple

import f90nml

from .errors import InputError, error_for

__all__ = ["Case", "GROUPS", "KernelCase", "kernel_case"]


def _groups() -> tuple[str, ...]:
    from .tables import GROUPS as groups

    return groups


#: Namelist groups of a deck (from the kernel's input table; set at the end of the module).
GROUPS: tuple[str, ...] = ()

_PATH_VARS = {("operating", "pressure_file"), ("output", "file"), ("calibration", "file")}
_NAME = re.compile(r"[a-z_][a-z0-9_]*")


class Case:
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
        self._nml = f90nml.Namelist()
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
        path = Path(path)
        if not path.exists():
            raise InputError(f"{path}: file not found")
        if not path.is_file():
            raise InputError(f"{path}: not a regular file (a folder or a device), not a deck")
        try:
            # bytes that are not UTF-8 travel through unchanged (surrogateescape), as in
            # ringlube-solve, which reads the deck as bytes
            text = path.read_bytes().decode("utf-8", "surrogateescape")
        except OSError as exc:
            raise InputError(f"{path}: cannot read the deck: {exc.strerror}") from None
        case = cls(name=path.stem, source=path)
        case._text = text
        case._base = str(path.resolve().parent)
        with kernel_case(case, load_trace=False):
            pass  # the kernel's reader first: it rejects what f90nml would reinterpret
        try:
            nml = f90nml.reads(text.removeprefix("\ufeff"))  # a byte-order mark is not the deck
        except Exception as exc:  # f90nml raises several types for bad syntax
            raise InputError(f"{path}: cannot parse namelist: {exc}") from exc
        for group, values in nml.items():
            case._set(group, dict(values), record=False)
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
        from . import _kernel
        from .tables import INPUTS, _value

        spec = INPUTS.get((group.lower(), name.lower()))
        if spec is None:
            raise InputError(f"&{group} {name}: unknown variable")
        with kernel_case(self, load_trace=False) as k:
            handle = k.handle
            text, code, message = _kernel.rl_get(handle, spec.group.encode(), spec.name.encode())
        if code:
            raise error_for(code, _text(message))
        return _value(spec.kind, _text(text))

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
        if group not in self._nml:
            self._nml[group] = f90nml.Namelist()
        for name, value in values.items():
            name = str(name).lower()
            if not _NAME.fullmatch(name):
                raise InputError(f"&{group} {name!r}: not a variable name")
            if hasattr(value, "item"):  # numpy scalar -> Python scalar
                value = value.item()
            if isinstance(value, os.PathLike):
                value = os.fspath(value)
            if isinstance(value, numbers.Real) and not isinstance(value, (bool, int)):
                value = float(value)  # Decimal, Fraction: numbers, not strings
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
        return f"Case({self.name!r}, {self.to_dict()!r})"

    # variants -------------------------------------------------------------------------
    def copy(self) -> Case:
        """An independent copy (values are immutable scalars, so copying groups suffices)."""
        new = Case.__new__(Case)
        new.name, new.source = self.name, self.source
        new._text, new._base = self._text, self._base
        new._changed = dict(self._changed)
        new._nml = f90nml.Namelist()
        for group, values in self._nml.items():
            new._nml[group] = f90nml.Namelist(values)
        return new

    def with_(self, group: str, **values: Any) -> Case:
        """A copy with variables of ``group`` changed."""
        return self.copy().set(group, **values)

    def with_ring(self, **values: Any) -> Case:
        """A copy with ``&ring`` variables changed."""
        return self.with_("ring", **values)

    def with_operating(self, **values: Any) -> Case:
        """A copy with ``&operating`` variables changed."""
        return self.with_("operating", **values)

    def with_numerics(self, **values: Any) -> Case:
        """A copy with ``&numerics`` variables changed."""
        return self.with_("numerics", **values)

    def with_physics(self, **values: Any) -> Case:
        """A copy with ``&physics`` variables changed."""
        return self.with_("physics", **values)

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


def _format(value: Any) -> str:
    if isinstance(value, bool):
        return ".true." if value else ".false."
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        return repr(value) if value == value else "nan"
    if isinstance(value, (list, tuple)):
        return ", ".join(_format(v) for v in value)
    s = str(value)
    return "'" + s.replace("'", "''") + "'"


def _serialise(groups) -> str:
    out = []
    for group, values in groups.items():
        out.append(f"&{group}")
        for name, value in values.items():
            out.append(f"    {name} = {_format(value)}")
        out.append("/")
    return "\n".join(out) + "\n"


def _text(message) -> str:
    if isinstance(message, bytes):
        message = message.decode("utf-8", errors="replace")
    return str(message).rstrip("\0 ").strip()


def _arg(s: str) -> bytes:
    """A string argument for the f2py layer (UTF-8 bytes; f2py would refuse non-ASCII;
    bytes of a path that are not UTF-8 go through unchanged)."""
    return s.encode("utf-8", "surrogateescape")


class KernelCase(NamedTuple):
    """A case parsed by the kernel: its handle, crank steps and liner cells of a run.

    Examples
    --------
    >>> KernelCase(1, 720, 0).nsteps
    720
    """

    handle: int
    nsteps: int
    nliner: int


@contextlib.contextmanager
def kernel_case(case: Case, load_trace: bool = True) -> Iterator[KernelCase]:
    """Context manager: the case parsed by the kernel (a :class:`KernelCase`).

    Parameters
    ----------
    case : Case
    load_trace : bool
        Read the gas-pressure file (else only check it exists).

    Examples
    --------
    >>> with kernel_case(Case().with_numerics(dpsi_deg=2.0)) as k:
    ...     k.nsteps
    360

    Raises
    ------
    InputError
        If the kernel rejects the case (its message names file, line, group, variable).
    """
    from . import _kernel

    text, name, base, overrides, overrides_name = case.kernel_inputs()
    if base and not base.endswith("/"):
        base += "/"
    handle, nsteps, nliner, code, message = _kernel.rl_open(
        _arg(text), _arg(name), _arg(base), _arg(overrides), _arg(overrides_name), 1 if load_trace else 0
    )
    if code:
        raise error_for(code, _text(message))
    try:
        yield KernelCase(int(handle), int(nsteps), int(nliner))
    finally:
        _kernel.rl_close(handle)


GROUPS = _groups()
