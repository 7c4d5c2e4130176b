"""docs/own_engine.md works as written: its decks, commands and Python, taken out
of the page itself, run in an empty folder.

Every fenced block of the page is one of: a deck (first line ``! myengine/NAME: ...``, written
to that path), a file (```` ```csv ````, first line ``# myengine/NAME: ...``, written to that
path), commands (```` ```sh ````, run line by line: ``ringlube`` in this process, others as
programs), Python (```` ```python ````, executed), the output of the command block before it
(```` ```output ````: each of its lines is a line of that output), or an illustration
(```` ```text ````). A block of any other kind fails the test, so nothing on the page goes
unchecked.

Small sizes, changed in the decks the page gives (each change asserted to apply, so a page
edit that drops one fails here): numerics preset 'fast' and a study of 16 samples, NSGA-II
20 x 10 x 2; ``ringlube optimise`` gets ``--serial -q`` (the same study in this process, no
Dask cluster). The output blocks of ``ringlube gas`` (no preset) are checked there; those of
the runs before the study, at the page's own 'default' preset, by
:func:`test_page_numbers_at_the_default_preset`; the study's and the overrun check's, at full
size, by ``tests/bench/own_engine_walk.py`` (minutes).
"""

from __future__ import annotations

import re
import shlex
import subprocess
import warnings

import pytest

from ringlube import SourceEngineDefaultWarning
from ringlube.cli import main

from conftest import ROOT

pytestmark = pytest.mark.cli

DOC = ROOT / "docs" / "own_engine.md"

SMALL = {
    "ring.nml": [("preset = 'default'", "preset = 'fast'")],
    "overrun.nml": [("preset = 'default'", "preset = 'fast'")],
    "study.nml": [
        ("samples = 64", "samples = 16"),
        (
            "population = 100, generations = 100, repeats = 5",
            "population = 20, generations = 10, repeats = 2",
        ),
    ],
}


def blocks() -> list[tuple[str, str]]:
    """(info string, text) of every fenced block of the page."""
    return re.findall(r"^```(\w*)\n(.*?)^```", DOC.read_text(encoding="utf-8"), flags=re.S | re.M)


def _small(name: str, text: str) -> str:
    for old, new in SMALL.get(name, []):
        assert old in text, f"docs/own_engine.md: {name} no longer has {old!r}; update SMALL"
        text = text.replace(old, new)
    return text


def test_page_blocks_are_all_checked():
    kinds = [_kind(info, text) for info, text in blocks()]
    assert "unknown" not in kinds, [b for b, k in zip(blocks(), kinds) if k == "unknown"]
    assert kinds.count("deck") == 3 and kinds.count("file") == 1
    assert kinds.count("sh") == 6 and kinds.count("python") == 2 and kinds.count("output") == 5
    # every output block follows a command block
    previous = [_kind(*b) for b in blocks()]
    for i, kind in enumerate(kinds):
        if kind == "output":
            assert previous[i - 1] in ("sh", "python"), blocks()[i][1][:60]


def _kind(info: str, text: str) -> str:
    if info == "" and re.match(r"! myengine/\S+: ", text):
        return "deck"
    if info == "csv" and re.match(r"# myengine/\S+: ", text):
        return "file"
    if info in ("sh", "python", "text", "output"):
        return info
    return "unknown"


def _output_lines_missing(expected: str, out: str) -> list[str]:
    """The lines of an output block that are not lines of the command's output."""
    lines = set(map(str.rstrip, out.splitlines()))
    return [x for x in expected.splitlines() if x.strip() and x.rstrip() not in lines]


def _write(tmp_path, kind: str, text: str, small: bool) -> None:
    """A deck or file block of the page, written to its path under ``tmp_path``."""
    path = tmp_path / re.match(r"[!#] (myengine/\S+): ", text).group(1)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(_small(path.name, text) if small and kind == "deck" else text)


def _ringlube(argv: list[str], capsys) -> str:
    """``ringlube ARGS`` in this process: its stdout; no warning (the decks are complete)."""
    with warnings.catch_warnings():
        warnings.simplefilter("error", SourceEngineDefaultWarning)
        status = main(argv[1:])
    out, err = capsys.readouterr()
    assert status == 0, err
    assert "warning" not in err
    return out


@pytest.mark.slow
def test_own_engine_walkthrough(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)  # an empty folder
    ran = []
    for info, text in blocks():
        kind = _kind(info, text)
        if kind in ("deck", "file"):
            _write(tmp_path, kind, text, small=True)
        elif kind == "sh":
            out = ""
            for line in filter(None, map(str.strip, text.splitlines())):
                argv = shlex.split(line)
                if argv[0] == "ringlube":
                    if argv[1] == "optimise":
                        argv += ["--serial", "-q"]
                    out += _ringlube(argv, capsys)
                    ran.append((argv[1], out))
                else:
                    subprocess.run(argv, check=True)
        elif kind == "python":
            exec(compile(text, str(DOC), "exec"), {})
            ran.append(("python", capsys.readouterr().out))
        elif kind == "output" and ran[-1][0] == "gas":  # the trace does not depend on the preset
            assert not _output_lines_missing(text, ran[-1][1]), text
    assert [r[0] for r in ran] == ["gas", "gas", "show", "run", "plot", "python", "run", "optimise", "python"]
    page = DOC.read_text(encoding="utf-8")
    # the rated trace's numbers quoted on the page are the command's
    peak = re.search(r"peak (\d+\.\d) bar at (\d+\.\d) deg", page).groups()
    assert f"peak {peak[0]}" in ran[0][1] and f"at {peak[1]} deg" in ran[0][1]
    assert "net IMEP 10.000 bar" in ran[0][1] and "net IMEP 10.000 bar" in page
    assert "10/50/90 % burned at 355.2/368.5/382.5 deg" in ran[0][1]
    assert "motored (no combustion)" in ran[1][1]
    root = tmp_path / "myengine"
    assert (root / "pressure.png").is_file() and (root / "overrun.pdf").is_file()
    show = ran[2][1]
    for line in (
        "&ring       tension                  deck              15.0 [N]",
        "&ring       profile                  deck              'gauge'",
        "&lubricant  grade                    deck              '5W-30'",
        "&operating  liner_temperature_top    deck              413.0 [K]",
        "&operating  liner_temperature_bottom deck              373.0 [K]",
    ):
        assert line in show, line
    assert (root / "ring.h5").is_file() and (root / "plots" / "ring_friction.png").is_file()
    python = ran[5][1].splitlines()
    assert python[0].startswith("373 K: 5W-30 ") and python[3].startswith("measured face: FMEP ")
    assert "flutter margin" in ran[6][1] and (root / "overrun.h5").is_file()
    report = (root / "study" / "report.md").read_text()
    assert "objectives (minimised): fmep [kPa], oil_to_chamber [mm^3]" in report
    assert "| reference | 1.2 | 5 | 3 |" in report
    assert "`oil_to_chamber <= reference`" in report and "`blowby <= 1.05 * reference`" in report
    assert "## How sure is this answer" in report
    assert "rated: **not calibrated**" in report  # the page says so
    assert (root / "study" / "tradeoff_fmep_vs_oil_to_chamber.png").is_file()  # the name the page gives
    assert "tradeoff_fmep_vs_oil_to_chamber.png" in page
    header = (root / "study" / "pareto_rated.csv").read_text().splitlines()[0]
    assert header.startswith("width [m],gauge_drop_top [m],gauge_drop_bottom [m],")
    # the overrun check ran the reference and the three chosen designs
    check = ran[8][1].splitlines()
    assert [x.split(":")[0] for x in check] == ["reference", "min fmep", "min oil_to_chamber", "knee"]
    # the reference row is the deck's own ring, run as it stands
    import ringlube
    from ringlube.study.deck import read_study
    from ringlube.study.store import Study

    r = ringlube.run(ringlube.Case.from_namelist(root / "ring.nml"))
    settings = read_study(root / "study.nml")
    st = Study.open(settings, root / "study" / "myring.h5")
    reference = dict(zip(settings.outputs, st.cases["rated"].reference.f_true[0]))
    assert [reference["fmep"], reference["oil_to_chamber"], reference["blowby"]] == [
        r.fmep,
        r.oil_to_chamber,
        r.blowby,
    ]
    # the overrun check's reference is the overrun deck as it stands
    o = ringlube.run(ringlube.Case.from_namelist(root / "overrun.nml"))
    assert check[0].startswith(f"reference: flutter margin {o.flutter_margin:.1f} N ")


def test_page_numbers_at_the_default_preset(tmp_path, monkeypatch, capsys):
    """The run numbers the page quotes (its output blocks up to the study) are those of its
    decks at their own preset ('default'): every block before the study runs as written
    (``ringlube plot`` and the figures of ``ringlube gas`` left out), and each output block's
    lines are lines of the output of the command block before it."""
    monkeypatch.chdir(tmp_path)
    checked, last = 0, ""
    for info, text in blocks():
        kind = _kind(info, text)
        if kind in ("deck", "file"):
            _write(tmp_path, kind, text, small=False)
        elif kind == "sh":
            if "ringlube optimise" in text:
                break
            last = ""
            for line in filter(None, map(str.strip, text.splitlines())):
                argv = shlex.split(line)
                if argv[0] != "ringlube":
                    subprocess.run(argv, check=True)
                elif argv[1] == "gas":
                    last += _ringlube([*argv, "--no-figure"], capsys)
                elif argv[1] != "plot":
                    last += _ringlube(argv, capsys)
        elif kind == "python":
            exec(compile(text, str(DOC), "exec"), {})
            last = capsys.readouterr().out
        elif kind == "output":
            assert not _output_lines_missing(text, last), (text, last)
            checked += 1
    assert checked == 4  # the overrun trace, the rated run, the Python variants, the overrun run
