"""docs/width.md prints what its commands print: the output blocks of the two cheap parts of
``tests/bench/width_story.py`` ('mechanism': 36 Swift-Stieber runs, 'gas': 36 starved runs
with the ring pack, and the two calibrations both print first) are run here and every line of
each block must be a line of the script's output now (the timing lines excepted). The
'readings' (800 runs) and 'doe' (two studies, minutes) blocks are checked by rerunning the
script, as the page says.
"""

from __future__ import annotations

import importlib.util
import re
import sys

import pytest

from conftest import ROOT

pytestmark = pytest.mark.numerics

DOC = ROOT / "docs" / "width.md"
SCRIPT = ROOT / "tests" / "bench" / "width_story.py"
#: lines that carry a wall time, not a result: the calibration's "[1 s]" and "N runs, T s on W workers"
TIMING = (re.compile(r" \[\d+ s\]$"), re.compile(r"^\d+ runs, \d+ s on \d+ workers$"))


def _script():
    spec = importlib.util.spec_from_file_location("width_story", SCRIPT)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _untimed(line: str) -> str | None:
    if TIMING[1].match(line):
        return None
    return TIMING[0].sub("", line)


def page_block(part: str) -> list[str]:
    """The lines of the output block right after the page's command block that runs ``part``."""
    text = DOC.read_text(encoding="utf-8")
    m = re.search(
        r"^```sh\n[^\n]*width_story\.py " + part + r"\b[^\n]*\n```\n\s*^```output\n(.*?)^```",
        text,
        flags=re.S | re.M,
    )
    assert m, f"docs/width.md has no output block after a command running width_story.py {part}"
    return [line for line in m.group(1).splitlines() if line.strip()]


@pytest.mark.parametrize("part", ["mechanism", "gas"])
@pytest.mark.slow
def test_width_page_blocks_are_the_script_s_output(part, monkeypatch, capsys):
    expected = [x for x in map(_untimed, page_block(part)) if x is not None]
    monkeypatch.setattr(sys, "argv", ["width_story.py", part, "--workers", "1"])
    _script().main()
    printed = {x for x in map(_untimed, capsys.readouterr().out.splitlines()) if x is not None}
    missing = [line for line in expected if line not in printed]
    assert not missing, (
        f"docs/width.md, the '{part}' block: {len(missing)} of {len(expected)} lines are not "
        f"printed now (rerun `.venv/bin/python tests/bench/width_story.py {part}`), first: {missing[0]}"
    )


def test_every_command_of_the_page_runs_the_script():
    """Each command block of the page runs one part of the script, so each block of numbers has
    its command beside it."""
    text = DOC.read_text(encoding="utf-8")
    commands = re.findall(r"^```sh\n(.*?)^```", text, flags=re.S | re.M)
    outputs = re.findall(r"^```output\n", text, flags=re.M)
    parts = [re.search(r"width_story\.py (\w+)", c).group(1) for c in commands]
    assert parts == ["readings", "mechanism", "gas", "doe"]
    assert len(outputs) == len(commands) + 1  # the calibration block, then one per command
