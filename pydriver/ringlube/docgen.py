"""Regenerate the sections of the docs that are generated from the kernel's tables
(docs/model.md) and from the ``&study`` table (docs/optimisation.md).

python -m ringlube.docgen [docs/model.md docs/optimisation.md ...]
"""

from __future__ import annotations

import sys

from .study.table import study_markdown
from .tables import inputs_markdown, results_markdown

_MARK = "<!-- {} {} (generated from {}: python -m ringlube.docgen) -->"


#: The generated sections of the docs: name -> (where the text comes from, its maker).
_SECTIONS = {
    "inputs": ("the kernel's tables", inputs_markdown),
    "results": ("the kernel's tables", results_markdown),
    "study": ("the &study table", study_markdown),
}


def update_doc(path: str, write: bool = True) -> bool:
    """Replace the generated sections of a Markdown file (those it marks: the kernel's input
    and result tables, the ``&study`` table).

    Parameters
    ----------
    path : str or Path
        The Markdown file.
    write : bool
        Write the file when a section changed (else only compare).

    Returns
    -------
    bool
        True if every generated section was current.

    Examples
    --------
    >>> update_doc("docs/model.md", write=False)  # doctest: +SKIP
    True
    """
    from pathlib import Path

    p = Path(path)
    text = p.read_text(encoding="utf-8")
    new = text
    found = []
    for name, (source, make) in _SECTIONS.items():
        begin, end = _MARK.format("BEGIN", name, source), _MARK.format("END", name, source)
        if begin not in new and end not in new:
            continue
        if begin not in new or end not in new:
            raise ValueError(f"{path}: '{begin}' without its '{end}' (or the other way round)")
        a, b = new.index(begin) + len(begin), new.index(end)
        new = new[:a] + "\n" + make() + "\n" + new[b:]
        found.append(name)
    if not found:
        raise ValueError(f"{path}: no generated section (known: {', '.join(_SECTIONS)})")
    if write and new != text:
        p.write_text(new, encoding="utf-8")
    return new == text


def main(argv: list[str] | None = None) -> int:
    """Rewrite each file's generated sections; prints whether each was current.

    Parameters
    ----------
    argv : list of str, optional
        Markdown files (default: docs/model.md and docs/optimisation.md).

    Returns
    -------
    int
        0.

    Examples
    --------
    >>> main(["docs/model.md"])  # doctest: +SKIP
    docs/model.md: current
    0
    """
    for doc in (argv if argv is not None else sys.argv[1:]) or ["docs/model.md", "docs/optimisation.md"]:
        print(f"{doc}: {'current' if update_doc(doc) else 'regenerated'}")
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
