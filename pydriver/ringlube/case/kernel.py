"""A case handed to the kernel: parsed in memory by the kernel's own reader (:func:`kernel_case`)."""

from __future__ import annotations

import contextlib
import warnings
from collections.abc import Iterator
from typing import NamedTuple, Protocol

from ..errors import error_for

__all__ = ["KernelCase", "UnusedInputWarning", "kernel_case"]


class UnusedInputWarning(UserWarning):
    """The case sets inputs of a model that is off, which the run does not use (e.g.
    ``&ring_pack`` variables with ``&physics ring_pack = 'none'``); the kernel's message
    names the file, line and the first such variable.

    Examples
    --------
    >>> import warnings
    >>> from ringlube import Case
    >>> with warnings.catch_warnings(record=True) as w:
    ...     warnings.simplefilter("always")
    ...     Case().with_("ring_pack", top_gap_area=0.2e-6).with_numerics(dpsi_deg=2.0).validate()
    360
    >>> w[-1].category.__name__
    'UnusedInputWarning'
    """


def kernel_text(message) -> str:
    """A message, name or path the kernel returned, as text (bytes decoded, NULs and blanks
    stripped)."""
    if isinstance(message, bytes):
        message = message.decode("utf-8", errors="replace")
    return str(message).rstrip("\0 ").strip()


def _deck_text(text: str, name: str) -> bytes:
    """Deck text for the kernel; a NUL byte is an input error naming the file and line (the
    f2py layer would end the text there, where ringlube-solve reads on: two readings)."""
    if "\0" in text:
        from ..errors import InputError

        line = text.count("\n", 0, text.index("\0")) + 1
        raise InputError(f"{name}:{line}: a NUL byte (binary data, not text) in the deck")
    return _arg(text)


def _arg(s: str) -> bytes:
    """A string argument for the f2py layer (UTF-8 bytes; f2py would refuse non-ASCII;
    bytes of a path that are not UTF-8 go through unchanged)."""
    return s.encode("utf-8", "surrogateescape")


class _Deck(Protocol):
    """What the kernel's reader needs of a case (a :class:`~ringlube.case.Case` is one)."""

    def kernel_inputs(self) -> tuple[str, str, str, str, str]: ...

    def warn_source_defaults(self, stacklevel: int = 2) -> str: ...


class KernelCase(NamedTuple):
    """A case parsed by the kernel: its handle, and the crank steps, liner cells, sectors (0
    for a round bore) and orders of the distortion of a run.

    Examples
    --------
    >>> KernelCase(1, 720, 0).nsteps, KernelCase(1, 720, 0).nsectors
    (720, 0)
    """

    handle: int
    nsteps: int
    nliner: int
    nsectors: int = 0
    norders: int = 0


@contextlib.contextmanager
def kernel_case(case: _Deck, load_trace: bool = True, warn: bool = True) -> Iterator[KernelCase]:
    """Context manager: the case parsed by the kernel (a :class:`KernelCase`).

    Parameters
    ----------
    case : Case
    load_trace : bool
        Read the gas-pressure file (else only check it exists).
    warn : bool
        Warn if source-engine defaults fill part of the case's engine geometry or ring
        (:class:`~ringlube.case.origins.SourceEngineDefaultWarning`), once the kernel has
        accepted the case.

    Examples
    --------
    >>> from ringlube import Case
    >>> with kernel_case(Case().with_numerics(dpsi_deg=2.0)) as k:
    ...     k.nsteps
    360

    Raises
    ------
    InputError
        If the kernel rejects the case (its message names file, line, group, variable).
    """
    from .. import _kernel

    text, name, base, overrides, overrides_name = case.kernel_inputs()
    if base and not base.endswith("/"):
        base += "/"
    handle, nsteps, nliner, nsectors, norders, code, message, notes = _kernel.rl_open(
        _deck_text(text, name),
        _arg(name),
        _arg(base),
        _deck_text(overrides, overrides_name),
        _arg(overrides_name),
        1 if load_trace else 0,
    )
    if code:
        raise error_for(code, kernel_text(message))
    if warn:
        case.warn_source_defaults(stacklevel=4)
        if kernel_text(notes):
            warnings.warn(kernel_text(notes), UnusedInputWarning, stacklevel=3)
    try:
        yield KernelCase(int(handle), int(nsteps), int(nliner), int(nsectors), int(norders))
    finally:
        _kernel.rl_close(handle)
