"""Exceptions raised by ringlube (the kernel's error codes as Python types)."""

from __future__ import annotations

__all__ = ["RinglubeError", "InputError", "NotConvergedError", "error_for"]


class RinglubeError(RuntimeError):
    """An error reported by the kernel; ``code`` is ringlube-solve's exit status."""

    code = 1


class InputError(RinglubeError, ValueError):
    """Bad input: the message names the file, namelist group and variable."""

    code = 2


class NotConvergedError(RinglubeError):
    """The run did not reach a converged periodic cycle (only raised on request)."""

    code = 3


def error_for(code: int, message: str) -> RinglubeError:
    """The exception matching a kernel error code."""
    cls = {2: InputError, 3: NotConvergedError}.get(code, RinglubeError)
    return cls(message)
