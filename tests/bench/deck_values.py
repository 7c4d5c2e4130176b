"""What every shipped deck and study deck reads to, as JSON, to compare two versions of the
deck reader (one deck parser changes no value of a valid deck).

For each ``inputs/*.nml``: a kernel deck's values as set (``Case.to_dict``, with their Python
types), where each input comes from (``Case.origins``) and every effective input
(``Case.effective_inputs``); a ``&study`` deck's :class:`StudySettings`, every field.

Usage (each run with the ``ringlube`` installed in the environment)::

    python tests/bench/deck_values.py dump before.json     # with the old reader installed
    python tests/bench/deck_values.py dump after.json      # with the new one
    python tests/bench/deck_values.py compare before.json after.json

``compare`` exits 1 when a value differs. A benchmark-style script, not run by the tests.
"""

from __future__ import annotations

import dataclasses
import json
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def dump(out: str) -> None:
    """Write the values of every shipped deck to ``out`` (JSON of reprs); decks are named
    relative to the repository (as messages and ``StudySettings.source`` show them)."""
    import os

    import ringlube
    from ringlube.study.deck import read_study

    out = os.path.abspath(out)
    os.chdir(ROOT)
    values = {}
    for path in sorted(Path("inputs").glob("*.nml")):
        key = str(path)
        if path.name.startswith("study_"):
            fields = dataclasses.asdict(read_study(path))
            values[key] = {k: repr(v) for k, v in fields.items()}
            continue
        case = ringlube.Case.from_namelist(path)
        values[key] = {
            "values": repr(case.to_dict()),
            "types": repr(
                {g: {n: type(v).__name__ for n, v in vs.items()} for g, vs in case.to_dict().items()}
            ),
            "origins": repr(sorted(case.origins().items())),
            "effective": repr(case.effective_inputs()),
        }
    Path(out).write_text(json.dumps(values, indent=1, sort_keys=True))
    print(f"{out}: {len(values)} decks")


def compare(a: str, b: str) -> int:
    """Print the fields that differ between two dumps; 0 when none does."""
    before, after = json.loads(Path(a).read_text()), json.loads(Path(b).read_text())
    differ = [
        (deck, field)
        for deck in sorted(set(before) | set(after))
        for field in sorted(set(before.get(deck, {})) | set(after.get(deck, {})))
        if before.get(deck, {}).get(field) != after.get(deck, {}).get(field)
    ]
    for deck, field in differ:
        print(f"differs: {deck} {field}")
    n = sum(len(v) for v in before.values())
    print(f"{n} fields of {len(before)} decks compared: {len(differ)} differ")
    return 1 if differ else 0


if __name__ == "__main__":
    if len(sys.argv) == 3 and sys.argv[1] == "dump":
        dump(sys.argv[2])
    elif len(sys.argv) == 4 and sys.argv[1] == "compare":
        sys.exit(compare(sys.argv[2], sys.argv[3]))
    else:
        sys.exit(__doc__)
