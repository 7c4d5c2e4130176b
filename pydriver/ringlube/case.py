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
import decimal
import html
import numbers
import os
import re
import warnings
from collections.abc import Iterator
from pathlib import Path
from typing import Any, NamedTuple

import f90nml

from .errors import InputError, error_for

__all__ = [
    "Case",
    "EffectiveInput",
    "GROUPS",
    "KernelCase",
    "SOURCE_ENGINE_INPUTS",
    "SourceEngineDefaultWarning",
    "kernel_case",
]


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
    from .tables import INPUTS

    spec = INPUTS.get((group, name))
    if spec is not None and spec.kind == "integer":
        if not value.is_integer():
            raise InputError(f"&{group} {name}: {value!r} is not a whole number (an integer input)")
        value = int(value)
    return value


def _groups() -> tuple[str, ...]:
    from .tables import GROUPS as groups

    return groups


#: Namelist groups of a deck (from the kernel's input table; set at the end of the module).
GROUPS: tuple[str, ...] = ()

#: Inputs whose defaults describe the source study's engine (Honda CRF450R: crank, conrod,
#: 96 mm bore) and its optimum top ring (face width, crown, tension, and a radial depth sized
#: for that bore). A case that sets some of these but not all gets the rest from that engine,
#: and :class:`SourceEngineDefaultWarning` says so. Not counted: the ring's density and
#: ``tension_unit`` (a material and a convention, not the engine), the operating point,
#: lubricant and surfaces (the study's, but not engine geometry; see docs/own_engine.md).
SOURCE_ENGINE_INPUTS: tuple[tuple[str, str], ...] = (
    ("engine", "crank_radius"),
    ("engine", "conrod_length"),
    ("engine", "bore_radius"),
    ("ring", "width"),
    ("ring", "crown_height"),
    ("ring", "crown_offset"),
    ("ring", "tension"),
    ("ring", "radial_depth"),
)


class SourceEngineDefaultWarning(UserWarning):
    """The source engine's (CRF450R) defaults fill engine-geometry or ring inputs of a case
    that sets some of its own (see :data:`SOURCE_ENGINE_INPUTS`).

    Examples
    --------
    >>> import warnings
    >>> with warnings.catch_warnings(record=True) as w:
    ...     warnings.simplefilter("always")
    ...     Case({"engine": {"bore_radius": 43e-3}}).with_numerics(dpsi_deg=2.0).validate()
    360
    >>> w[0].category.__name__, str(w[0].message).split(":")[0]
    ('SourceEngineDefaultWarning', "case 'case'")
    """


class EffectiveInput(NamedTuple):
    """One input as the kernel uses it, and where its value came from.

    ``origin`` is 'deck', 'calibration file', 'Python' (changed on the Case), "preset 'NAME'"
    (set by the numerics preset) or 'default' (the kernel's table).

    Examples
    --------
    >>> EffectiveInput("ring", "width", 1e-3, "m", "deck").origin
    'deck'
    """

    group: str
    name: str
    value: Any
    unit: str
    origin: str


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
        with kernel_case(case, load_trace=False, warn=False):
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
        with kernel_case(self, load_trace=False, warn=False) as k:
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
                f"{n} = {_format(v)}{'*' if (group, n) in self._changed and self._text else ''}"
                for n, v in values.items()
            )
            lines.append(f"  &{group:<10} {items}")
        if self._changed and self._text:
            lines.append("  (* changed in Python)")
        return "\n".join(lines)

    def _repr_html_(self) -> str:
        """A table of the values set (Jupyter)."""
        from .tables import INPUTS

        where = f" from <code>{html.escape(self.source)}</code>" if self.source else ""
        rows = []
        for group, values in self._nml.items():
            for n, v in values.items():
                spec = INPUTS.get((group, n))
                unit = spec.unit if spec and spec.unit not in ("1", "(unit)") else ""
                origin = "deck" if self._text and (group, n) not in self._changed else "Python"
                rows.append(
                    f"<tr><td>&amp;{group}</td><td>{html.escape(n)}</td><td>{html.escape(_format(v))}</td>"
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

    # where the values come from -------------------------------------------------------
    def _calibration_keys(self) -> set[tuple[str, str]]:
        path = self.get("calibration", "file")
        if not path:
            return set()
        try:
            nml = f90nml.read(path)
        except Exception:  # the kernel reports an unreadable calibration file
            return set()
        return {(g.lower(), n.lower()) for g, values in nml.items() for n in values}

    def origins(self) -> dict[tuple[str, str], str]:
        """Where each input's value comes from: 'deck', 'calibration file', 'Python',
        "preset 'NAME'" or 'default', for every input of the kernel's table.

        Examples
        --------
        >>> o = Case.from_namelist("inputs/crf450r_4000rpm_full_cold.nml").with_ring(width=1.1e-3).origins()
        >>> o["ring", "width"], o["ring", "crown_height"], o["surface", "zeta_kappa_sigma"]
        ('Python', 'deck', 'calibration file')
        >>> o["numerics", "nodes"], o["lubricant", "supply_film"]
        ("preset 'default'", 'default')
        """
        from .tables import INPUTS, PRESETS

        calibration = self._calibration_keys()
        preset = str(self.get("numerics", "preset", "default")).lower()
        preset_values = PRESETS.get(preset, PRESETS["default"])
        out = {}
        for group, name in INPUTS:
            key = (group, name)
            if key in self._changed:
                out[key] = "Python"
            elif name in self._nml.get(group, {}):
                out[key] = "deck"
            elif key in calibration:
                out[key] = "calibration file"
            elif group == "numerics" and name in preset_values:
                out[key] = f"preset '{preset}'"
            else:
                out[key] = "default"
        return out

    def effective_inputs(self) -> list[EffectiveInput]:
        """Every input of the kernel's table as the kernel reads this case, with its unit and
        where it came from (see :meth:`origins`).

        Returns
        -------
        list of EffectiveInput

        Raises
        ------
        InputError
            If the kernel rejects the case.

        Examples
        --------
        >>> rows = Case.from_namelist("inputs/crf450r_4000rpm_full_cold.nml").effective_inputs()
        >>> [r for r in rows if r.name == "crown_offset"][0]
        EffectiveInput(group='ring', name='crown_offset', value=-3.83e-05, unit='m', origin='deck')
        """
        from . import _kernel
        from .tables import INPUTS, _value

        origins = self.origins()
        rows = []
        with kernel_case(self, load_trace=False, warn=False) as k:
            for (group, name), spec in INPUTS.items():
                text, code, message = _kernel.rl_get(k.handle, group.encode(), name.encode())
                if code:
                    raise error_for(code, _text(message))
                rows.append(
                    EffectiveInput(
                        group, name, _value(spec.kind, _text(text)), spec.unit, origins[group, name]
                    )
                )
        return rows

    def source_engine_defaults(self) -> tuple[list[tuple[str, str]], list[tuple[str, str]]]:
        """(inputs of :data:`SOURCE_ENGINE_INPUTS` this case sets, those left to the source
        engine's defaults); a warning is due when both are non-empty.

        Examples
        --------
        >>> own, filled = Case({"engine": {"bore_radius": 43e-3}}).source_engine_defaults()
        >>> own, filled[:2]
        ([('engine', 'bore_radius')], [('engine', 'crank_radius'), ('engine', 'conrod_length')])
        """
        calibration = self._calibration_keys() if self.get("calibration", "file") else set()
        own, filled = [], []
        for group, name in SOURCE_ENGINE_INPUTS:
            is_set = name in self._nml.get(group, {}) or (group, name) in calibration
            (own if is_set else filled).append((group, name))
        return own, filled

    def warn_source_defaults(self, stacklevel: int = 2) -> str:
        """Warn (:class:`SourceEngineDefaultWarning`) if the source engine's defaults fill
        some engine-geometry or ring inputs of this case while it sets others; returns the
        message ('' when none is due).

        Parameters
        ----------
        stacklevel : int
            As for :func:`warnings.warn`.

        Examples
        --------
        >>> Case().warn_source_defaults()   # nothing set: the source engine, knowingly
        ''
        """
        own, filled = self.source_engine_defaults()
        if not (own and filled):
            return ""
        where = self.source or f"case {self.name!r}"
        message = (
            f"{where}: the source engine's (CRF450R) defaults fill {_names(filled)} "
            f"while the case sets {_names(own)}; set them for your engine (docs/own_engine.md)"
        )
        warnings.warn(message, SourceEngineDefaultWarning, stacklevel=stacklevel + 1)
        return message

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
def kernel_case(case: Case, load_trace: bool = True, warn: bool = True) -> Iterator[KernelCase]:
    """Context manager: the case parsed by the kernel (a :class:`KernelCase`).

    Parameters
    ----------
    case : Case
    load_trace : bool
        Read the gas-pressure file (else only check it exists).
    warn : bool
        Warn if source-engine defaults fill part of the case's engine geometry or ring
        (:class:`SourceEngineDefaultWarning`), once the kernel has accepted the case.

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
    if warn:
        case.warn_source_defaults(stacklevel=4)
    try:
        yield KernelCase(int(handle), int(nsteps), int(nliner))
    finally:
        _kernel.rl_close(handle)


def _names(keys: list[tuple[str, str]]) -> str:
    """'&engine a, b; &ring c' from [(group, name), ...]."""
    by_group: dict[str, list[str]] = {}
    for group, name in keys:
        by_group.setdefault(group, []).append(name)
    return "; ".join(f"&{g} {', '.join(n)}" for g, n in by_group.items())


def _with_group(group: str):
    """The method ``Case.with_<group>``, its docstring listing the group's variables."""
    from .tables import INPUTS, PRESETS

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
    from .tables import PRESETS, _value

    if spec.kind == "choice":
        return repr(spec.choices[-1])
    if spec.default == "(preset)":
        return repr(PRESETS["default"][spec.name])
    return repr(_value(spec.kind, spec.default))


GROUPS = _groups()
for _group in GROUPS:
    setattr(Case, f"with_{_group}", _with_group(_group))
del _group
