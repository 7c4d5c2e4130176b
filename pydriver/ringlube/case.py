"""A ringlube case: a namelist deck you can read, change, validate and write back."""

from __future__ import annotations

import os
import tempfile
from pathlib import Path
from typing import Any

import f90nml

from .errors import InputError

__all__ = ["Case", "GROUPS"]

#: Namelist groups of a deck (SPEC section 9).
GROUPS = ("engine", "operating", "ring", "lubricant", "surface", "physics", "numerics", "output",
          "calibration")
_PATH_VARS = {("operating", "pressure_file"), ("output", "file"), ("calibration", "file")}


class Case:
    """One operating point and ring design, held as a namelist.

    Values are addressed by group and variable, ``case["ring", "width"]``; anything not
    set takes the kernel's documented default. Relative paths are resolved against the
    deck's folder when the deck is read, so a case can be run from anywhere.

    >>> case = Case.from_namelist("inputs/crf450r_4000rpm_full_cold.nml")
    >>> wider = case.with_ring(width=1.2e-3)
    """

    def __init__(self, groups: dict[str, dict[str, Any]] | None = None, name: str = "case",
                 source: str | os.PathLike | None = None):
        self.name = name
        #: The deck this case was read from (named in error messages), if any.
        self.source = str(source) if source is not None else None
        self._nml = f90nml.Namelist()
        for group, values in (groups or {}).items():
            self.set(group, **values)

    # construction and I/O -------------------------------------------------------------
    @classmethod
    def from_namelist(cls, path: str | os.PathLike) -> "Case":
        """Read a deck; relative paths in it become absolute (relative to its folder)."""
        from . import _kernel

        path = Path(path)
        if not path.is_file():
            raise InputError(f"{path}: file not found")
        # the kernel's own reader first: its messages name file, line, group and variable,
        # and it rejects values that f90nml would silently reinterpret
        _, code, message = _kernel.rl_count_steps(str(path))
        if code:
            raise InputError(_text(message))
        try:
            nml = f90nml.read(path)
        except Exception as exc:  # f90nml raises several types for bad syntax
            raise InputError(f"{path}: cannot parse namelist: {exc}") from exc
        case = cls(name=path.stem, source=path)
        for group, values in nml.items():
            case.set(group, **dict(values))
        for group, var in _PATH_VARS:
            value = case.get(group, var)
            if value and not os.path.isabs(value):
                case.set(group, **{var: str((path.parent / value).resolve())})
        return case

    def to_namelist(self, path: str | os.PathLike | None = None) -> str:
        """The deck as text; also written to ``path`` if given."""
        text = str(self._nml) + "\n"
        if path is not None:
            Path(path).write_text(text)
        return text

    # access ---------------------------------------------------------------------------
    def get(self, group: str, name: str, default: Any = None) -> Any:
        """Value of ``&group name``, or ``default`` if the deck does not set it."""
        group, name = group.lower(), name.lower()
        return self._nml.get(group, {}).get(name, default)

    def set(self, group: str, **values: Any) -> "Case":
        """Set variables of one group in place; returns the case."""
        group = group.lower()
        if group not in GROUPS:
            raise InputError(f"unknown namelist group &{group} (known: {', '.join(GROUPS)})")
        if group not in self._nml:
            self._nml[group] = f90nml.Namelist()
        for name, value in values.items():
            if hasattr(value, "item"):  # numpy scalar -> Python scalar
                value = value.item()
            self._nml[group][name.lower()] = value
        return self

    def __getitem__(self, key: tuple[str, str]) -> Any:
        return self.get(*key)

    def __setitem__(self, key: tuple[str, str], value: Any) -> None:
        self.set(key[0], **{key[1]: value})

    def to_dict(self) -> dict[str, dict[str, Any]]:
        """Plain nested dict of the values set."""
        return {g: dict(v) for g, v in self._nml.items()}

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Case) and self.to_dict() == other.to_dict()

    def __repr__(self) -> str:
        return f"Case({self.name!r}, {self.to_dict()!r})"

    # variants -------------------------------------------------------------------------
    def copy(self) -> "Case":
        """An independent copy (values are immutable scalars, so copying groups suffices)."""
        new = Case.__new__(Case)
        new.name, new.source = self.name, self.source
        new._nml = f90nml.Namelist()
        for group, values in self._nml.items():
            new._nml[group] = f90nml.Namelist(values)
        return new

    def with_(self, group: str, **values: Any) -> "Case":
        """A copy with variables of ``group`` changed."""
        return self.copy().set(group, **values)

    def with_ring(self, **values: Any) -> "Case":
        return self.with_("ring", **values)

    def with_operating(self, **values: Any) -> "Case":
        return self.with_("operating", **values)

    def with_numerics(self, **values: Any) -> "Case":
        return self.with_("numerics", **values)

    def with_physics(self, **values: Any) -> "Case":
        return self.with_("physics", **values)

    def inline_calibration(self) -> "Case":
        """A copy with the calibration file's values written into the deck itself (no
        ``&calibration`` group), so that any calibrated variable can then be changed."""
        path = self.get("calibration", "file")
        c = self.copy()
        if path is None:
            return c
        c._nml.pop("calibration", None)
        for group, values in Case.from_namelist(path).to_dict().items():
            c.set(group, **values)
        return c

    # checking -------------------------------------------------------------------------
    def validate(self) -> int:
        """Check the case with the kernel's own reader; returns the number of crank steps.

        Raises :class:`InputError` naming the group and variable on a bad value. The gas
        pressure file is checked to exist here; its rows are checked when the case runs.
        """
        from . import _kernel

        with self.deck_file() as deck:
            nsteps, code, message = _kernel.rl_count_steps(deck)
            if code:
                raise InputError(self.describe_message(message, deck))
        return int(nsteps)

    def describe_message(self, message: bytes | str, deck: str) -> str:
        """A kernel message with the temporary deck's path replaced by the case's origin."""
        text = _text(message)
        origin = self.source or f"<case {self.name}>"
        return text.replace(deck, origin)

    def deck_file(self) -> "_DeckFile":
        """Context manager: the deck written to a temporary file, for the kernel."""
        return _DeckFile(self)


class _DeckFile:
    def __init__(self, case: Case):
        self.case = case

    def __enter__(self) -> str:
        fd, self.path = tempfile.mkstemp(prefix=f"ringlube-{self.case.name}-", suffix=".nml")
        self.text = self.case.to_namelist()
        with os.fdopen(fd, "w") as fh:
            fh.write(self.text)
        return self.path

    def __exit__(self, *exc: object) -> None:
        os.unlink(self.path)


def _text(message: bytes | str) -> str:
    if isinstance(message, bytes):
        message = message.decode(errors="replace")
    return message.strip()
