"""Regenerate the sections of the docs that are generated from the kernel's tables
(docs/model.md) and from the ``&study`` table (docs/optimisation.md).

python -m ringlube.docgen [docs/model.md docs/optimisation.md ...]
"""

from __future__ import annotations

import sys

from .tables import update_doc


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
