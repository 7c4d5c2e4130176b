"""docs/own_engine.md works as written (issue 18): its decks, commands and Python, taken out
of the page itself, run in an empty folder.

Every fenced block of the page is one of: a deck (first line ``! myengine/NAME: ...``, written
to that path), commands (```` ```sh ````, run line by line: ``ringlube`` in this process, others
as programs), Python (```` ```python ````, executed), or an illustration (```` ```text ````). A
block of any other kind fails the test, so nothing on the page goes unchecked.

Small sizes, changed in the decks the page gives (each change asserted to apply, so a page
edit that drops one fails here): numerics preset 'fast' and a study of 16 samples, NSGA-II
20 x 10 x 2; ``ringlube optimise`` gets ``--serial -q`` (the same study in this process, no
Dask cluster).
"""

from __future__ import annotations

import re
import shlex
import subprocess
import warnings

from ringlube import SourceEngineDefaultWarning
from ringlube.cli import main

from conftest import ROOT

DOC = ROOT / "docs" / "own_engine.md"

SMALL = {
    "ring.nml": [("preset = 'default'", "preset = 'fast'")],
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
    assert kinds.count("deck") == 2 and kinds.count("sh") == 4 and kinds.count("python") == 1


def _kind(info: str, text: str) -> str:
    if re.match(r"! myengine/\S+: ", text):
        return "deck"
    if info in ("sh", "python", "text"):
        return info
    return "unknown"


def test_own_engine_walkthrough(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)  # an empty folder
    ran = []
    for info, text in blocks():
        kind = _kind(info, text)
        if kind == "deck":
            path = tmp_path / re.match(r"! (myengine/\S+): ", text).group(1)
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_text(_small(path.name, text))
        elif kind == "sh":
            for line in filter(None, map(str.strip, text.splitlines())):
                argv = shlex.split(line)
                if argv[0] == "ringlube":
                    if argv[1] == "optimise":
                        argv += ["--serial", "-q"]
                    with warnings.catch_warnings():
                        warnings.simplefilter("error", SourceEngineDefaultWarning)  # the deck is complete
                        status = main(argv[1:])
                    out, err = capsys.readouterr()
                    assert status == 0, err
                    assert "warning" not in err
                    ran.append((argv[1], out))
                else:
                    subprocess.run(argv, check=True)
        elif kind == "python":
            exec(compile(text, str(DOC), "exec"), {})
            ran.append(("python", capsys.readouterr().out))
    assert [r[0] for r in ran] == ["gas", "show", "run", "plot", "python", "optimise"]
    out = dict(ran)
    page = DOC.read_text(encoding="utf-8")
    # the trace's numbers quoted on the page are the command's (the trace does not depend
    # on the numerics preset)
    peak = re.search(r"peak (\d+\.\d) bar at (\d+\.\d) deg", page).groups()
    assert f"peak {peak[0]}" in out["gas"] and f"at {peak[1]} deg" in out["gas"]
    assert "net IMEP 10.000 bar" in out["gas"] and "net IMEP 10.000 bar" in page
    assert "10/50/90 % burned at 355.2/368.5/382.5 deg" in out["gas"]
    root = tmp_path / "myengine"
    assert (root / "pressure.png").is_file() and (root / "pressure.pdf").is_file()
    assert "&ring       tension                  deck              15.0 [N]" in out["show"]
    assert (root / "ring.h5").is_file() and (root / "plots" / "ring_friction.png").is_file()
    assert " J, " in out["python"] and "mm3 to the chamber per cycle" in out["python"]
    report = (root / "study" / "report.md").read_text()
    assert "objectives (minimised): energy_loss [J], oil_to_chamber [mm^3]" in report
    assert "| reference | 1.2 | 8 |" in report
    assert "`oil_to_chamber <= reference`" in report and "## How sure is this answer" in report
    assert "rated: **not calibrated**" in report  # the page says so
    assert (
        root / "study" / "tradeoff_energy_loss_vs_oil_to_chamber.png"
    ).is_file()  # the name the page gives
    assert "tradeoff_energy_loss_vs_oil_to_chamber.png" in page
    header = (root / "study" / "pareto_rated.csv").read_text().splitlines()[0]
    assert header.startswith("width [m],crown_height [m],")
    # the reference row is the deck's own ring, run as it stands
    import ringlube
    from ringlube.study.deck import read_study
    from ringlube.study.store import Study

    r = ringlube.run(ringlube.Case.from_namelist(root / "ring.nml"))
    settings = read_study(root / "study.nml")
    st = Study.open(settings, root / "study" / "myring.h5")
    reference = dict(zip(settings.outputs, st.cases["rated"].reference.f_true[0]))
    assert [reference["energy_loss"], reference["oil_to_chamber"]] == [r.energy_loss, r.oil_to_chamber]


def test_page_numbers_at_the_default_preset(tmp_path, monkeypatch):
    """The run numbers the page quotes are those of its deck at the 'default' preset."""
    import ringlube
    from ringlube import gas

    monkeypatch.chdir(tmp_path)
    name = "ring.nml"
    deck = next(t for _, t in blocks() if t.startswith(f"! myengine/{name}"))
    (tmp_path / "myengine").mkdir()
    (tmp_path / "myengine" / name).write_text(deck)
    command = next(t for i, t in blocks() if i == "sh" and t.startswith("ringlube gas"))
    assert main([*shlex.split(command)[1:], "--no-figure"]) == 0
    r = ringlube.run(ringlube.Case.from_namelist(tmp_path / "myengine" / name))
    page = DOC.read_text(encoding="utf-8")
    assert f"{r.energy_loss:.3f} J per cycle, {r.mixed_share:.1f} % mixed, {r.ring_mass:.2f} g" in page
    assert gas.read_csv(tmp_path / "myengine" / "pressure.csv")[1].max() > 50e5
