"""Safe output files: every file ringlube writes (figures, reports, CSV files, calibration
files) goes through :func:`check_output` and is written atomically.

A path is refused, with one line naming it, when it is a symbolic link (writing through it
would overwrite whatever it points at, e.g. a result or a deck), a folder or anything else
that is not a regular file, in a folder that does not exist, or one of the inputs of the
work (compared as files, not by spelling). Writing goes to a uniquely named temporary file
in the same folder that is renamed when complete (:func:`atomic_path`), so an interrupted
writer leaves neither a half-written file nor a temporary one.
"""

from __future__ import annotations

import contextlib
import os
import tempfile
from collections.abc import Iterable, Iterator
from pathlib import Path

from .errors import InputError

__all__ = ["check_output", "atomic_path", "write_text", "save_figure"]


def check_output(
    path: str | os.PathLike, inputs: Iterable[str | os.PathLike | None] = (), option: str = ""
) -> Path:
    """Check that ``path`` may be written: a new name or a regular file, not an input.

    Parameters
    ----------
    path : path
        The file to be written.
    inputs : iterable of path
        Files the work reads (``None`` entries are skipped).
    option : str
        What gave the path, for the message (e.g. ``"--out"``).

    Returns
    -------
    Path

    Raises
    ------
    InputError
        A symbolic link, a folder, a device, a path in a missing folder, or an input.

    Example
    -------
    >>> check_output("/tmp/new_file.csv").name
    'new_file.csv'
    """
    out = Path(path)
    what = f"{option} {out}" if option else str(out)
    if out.is_symlink():
        raise InputError(f"{what}: is a symbolic link; refusing to write through it (remove it first)")
    if out.exists() and out.is_dir():
        raise InputError(f"{what}: is a folder; give a file name")
    if out.exists() and not out.is_file():
        raise InputError(f"{what}: exists and is not a regular file")
    parent = out.parent if str(out.parent) else Path(".")
    if not parent.is_dir():
        raise InputError(f"{what}: folder '{parent}' does not exist")
    if out.exists():
        for p in inputs:
            if p and Path(p).exists() and os.path.samefile(out, p):
                raise InputError(f"{what}: is an input of this run; choose another name")
    return out


@contextlib.contextmanager
def atomic_path(
    path: str | os.PathLike, inputs: Iterable[str | os.PathLike | None] = (), option: str = ""
) -> Iterator[Path]:
    """A temporary path beside ``path``, renamed onto it when the block ends without error.

    ``path`` is checked first (:func:`check_output`). The rename replaces a directory entry,
    never the file a link points at.

    Parameters
    ----------
    path : path
    inputs, option
        As in :func:`check_output`.

    Yields
    ------
    Path
        Where to write.

    Example
    -------
    >>> with atomic_path("/tmp/ringlube_doc.txt") as tmp:
    ...     _ = tmp.write_text("x")
    >>> Path("/tmp/ringlube_doc.txt").read_text()
    'x'
    """
    out = check_output(path, inputs, option)
    folder = out.parent if str(out.parent) else Path(".")
    fd, tmp = tempfile.mkstemp(dir=folder, prefix=f".{out.name}.", suffix=".part")
    os.close(fd)
    os.chmod(tmp, 0o666 & ~_umask())  # as open() would have made it, not mkstemp's 0o600
    try:
        yield Path(tmp)
        os.replace(tmp, out)
    finally:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(tmp)


def _umask() -> int:
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def write_text(
    path: str | os.PathLike, text: str, inputs: Iterable[str | os.PathLike | None] = (), option: str = ""
) -> Path:
    """Write ``text`` (UTF-8) to ``path`` safely (:func:`atomic_path`).

    Parameters
    ----------
    path : path
    text : str
    inputs, option
        As in :func:`check_output`.

    Returns
    -------
    Path

    Example
    -------
    >>> write_text("/tmp/ringlube_doc.md", "# hi\\n").read_text()
    '# hi\\n'
    """
    with atomic_path(path, inputs, option) as tmp:
        tmp.write_text(text, encoding="utf-8")
    return Path(path)


def save_figure(
    fig, path: str | os.PathLike, inputs: Iterable[str | os.PathLike | None] = (), **kwargs
) -> Path:
    """``fig.savefig`` to ``path`` safely (:func:`atomic_path`); the format is the suffix's.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
    path : path
    inputs : iterable of path
        As in :func:`check_output`.
    **kwargs
        Passed to ``savefig`` (``dpi``, ``metadata``).

    Returns
    -------
    Path

    Example
    -------
    >>> import matplotlib.pyplot as plt
    >>> save_figure(plt.figure(), "/tmp/ringlube_doc.png").suffix
    '.png'
    """
    path = Path(path)
    with atomic_path(path, inputs) as tmp:
        fig.savefig(tmp, format=path.suffix.lstrip(".") or "png", **kwargs)
    return path
