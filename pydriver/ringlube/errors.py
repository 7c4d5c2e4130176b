"""Exceptions raised by ringlube (the kernel's error codes as Python types)."""

from __future__ import annotations

import os
from pathlib import Path

__all__ = ["RinglubeError", "InputError", "NotConvergedError", "error_for", "input_file"]


class RinglubeError(RuntimeError):
    """An error reported by the kernel; ``code`` is ringlube-solve's exit status.

    Examples
    --------
    >>> RinglubeError("disk full").code
    1
    """

    code = 1


class InputError(RinglubeError, ValueError):
    """Bad input: the message names the file, namelist group and variable.

    Examples
    --------
    >>> isinstance(InputError("deck.nml:3: &ring width: ..."), ValueError), InputError.code
    (True, 2)
    """

    code = 2


class NotConvergedError(RinglubeError):
    """The run did not reach a converged periodic cycle (only raised on request).

    Examples
    --------
    >>> NotConvergedError.code
    3
    """

    code = 3


def error_for(code: int, message: str) -> RinglubeError:
    """The exception matching a kernel error code.

    Parameters
    ----------
    code : int
        2 input, 3 not converged, else runtime.
    message : str

    Returns
    -------
    RinglubeError

    Examples
    --------
    >>> type(error_for(2, "bad")).__name__
    'InputError'
    """
    cls = {2: InputError, 3: NotConvergedError}.get(code, RinglubeError)
    return cls(message)


def input_file(
    path: str | os.PathLike, missing: str = "file not found", not_file: str = "not a file"
) -> Path:
    """``path`` if it names a regular file, else an :class:`InputError` ``'PATH: MISSING'``
    or ``'PATH: NOT_FILE'`` (a folder or a device).

    Parameters
    ----------
    path : path
    missing, not_file : str
        What the message says when there is nothing at ``path``, or something other than a
        file.

    Returns
    -------
    Path

    Examples
    --------
    >>> input_file("nowhere.nml")
    Traceback (most recent call last):
    ...
    ringlube.errors.InputError: nowhere.nml: file not found
    """
    path = Path(path)
    if not path.exists():
        raise InputError(f"{path}: {missing}")
    if not path.is_file():
        raise InputError(f"{path}: {not_file}")
    return path
