"""The example inputs shipped with the package: decks, calibration, gas traces, studies.

The wheel holds a copy of the repository's ``inputs/`` folder as ``ringlube/examples/``
(the layout is kept, so the decks' relative paths to ``calibration.nml`` and
``pressure/*.csv`` resolve). Copy them out before editing them: the installed copy
belongs to the package and is replaced when it is reinstalled.
"""

from __future__ import annotations

import shutil
from pathlib import Path

__all__ = ["examples_dir", "copy_examples"]

_INSTALLED = Path(__file__).resolve().parent / "examples"
_SOURCE_TREE = Path(__file__).resolve().parents[2] / "inputs"


def examples_dir() -> Path:
    """The folder holding the shipped example inputs.

    Returns
    -------
    pathlib.Path
        ``ringlube/examples`` inside the installed package; when the package runs from a
        source tree without that folder, the tree's ``inputs/`` folder.

    Raises
    ------
    FileNotFoundError
        Neither folder exists (an incomplete installation).

    Examples
    --------
    >>> from ringlube.examples import examples_dir
    >>> (examples_dir() / "crf450r_4000rpm_full_cold.nml").is_file()
    True
    """
    for folder in (_INSTALLED, _SOURCE_TREE):
        if (folder / "calibration.nml").is_file():
            return folder
    raise FileNotFoundError(
        f"ringlube example inputs not found (looked in {_INSTALLED} and {_SOURCE_TREE}); "
        "reinstall the package"
    )


def copy_examples(dest: str | Path, overwrite: bool = False) -> list[Path]:
    """Copy the example inputs into a folder, keeping their layout.

    Parameters
    ----------
    dest : str or pathlib.Path
        Target folder; created (with parents) if missing.
    overwrite : bool, optional
        Replace files that already exist in `dest`. Default False.

    Returns
    -------
    list of pathlib.Path
        The copied files, sorted, under `dest`.

    Raises
    ------
    FileExistsError
        A file to be copied already exists in `dest` and `overwrite` is False; nothing is
        copied then.
    FileNotFoundError
        The example inputs are missing from the installation (see `examples_dir`).

    Examples
    --------
    >>> import tempfile
    >>> from pathlib import Path
    >>> from ringlube.examples import copy_examples
    >>> with tempfile.TemporaryDirectory() as tmp:
    ...     copied = copy_examples(tmp)
    ...     names = sorted(p.stem for p in copied if p.parent.name == "pressure")
    >>> names[:4]
    ['crf450r_12000rpm_full', 'crf450r_3000rpm_half', 'crf450r_4000rpm_full', 'crf450r_8000rpm_full']
    >>> names[4:]
    ['own86_3000rpm_full']
    """
    src = examples_dir()
    dest = Path(dest)
    files = sorted(p for p in src.rglob("*") if p.is_file())
    targets = [dest / p.relative_to(src) for p in files]
    if not overwrite:
        clashes = [t for t in targets if t.exists()]
        if clashes:
            raise FileExistsError(
                f"{clashes[0]} already exists ({len(clashes)} example file(s) would be "
                "overwritten); choose another folder or pass overwrite=True"
            )
    for source, target in zip(files, targets):
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(source, target)
    return targets
