"""docs/own_engine.md works as written: its decks and commands run (issue 12 item 25)."""

from __future__ import annotations

import re
import shlex
import shutil
import subprocess

import numpy as np

from ringlube.cli import main

from conftest import INPUTS

DOC = INPUTS.parent / "docs" / "own_engine.md"


def blocks() -> list[str]:
    return re.findall(r"^```\n(.*?)^```", DOC.read_text(), flags=re.S | re.M)


def test_own_engine_walkthrough(tmp_path, monkeypatch, capsys):
    shutil.copytree(INPUTS, tmp_path / "inputs")
    monkeypatch.chdir(tmp_path)
    commands = 0
    for block in blocks():
        if block.startswith("! My engine"):
            (tmp_path / "myengine" / "ring.nml").write_text(block)
        elif block.startswith("&study"):
            (tmp_path / "myengine" / "study.nml").write_text(block)
        elif block.split()[0] in ("mkdir", "cp", "ringlube"):
            for line in block.strip().splitlines():
                argv = shlex.split(line)
                if argv[0] == "ringlube":
                    if argv[1] == "optimise":
                        argv += ["--serial", "-q"]
                    assert main(argv[1:]) == 0, capsys.readouterr().err
                else:
                    subprocess.run(argv, check=True)
                commands += 1
    assert commands == 5
    out = tmp_path / "myengine"
    assert (out / "ring.h5").is_file() and (out / "plots" / "ring_friction.png").is_file()
    report = (out / "study" / "report.md").read_text()
    assert "tension [N]" in report and "| reference |" in report
    header = (out / "study" / "pareto_rated.csv").read_text().splitlines()[0]
    assert header.startswith("width [m],crown_height [m],crown_offset [m],tension [N],")
    # the reference row is the deck's own ring, run as it stands
    import ringlube

    r = ringlube.run(ringlube.Case.from_namelist(out / "ring.nml"))
    from ringlube.study_settings import read_study
    from ringlube.study_store import Study

    st = Study.open(read_study(out / "study.nml"), out / "study" / "myring.h5")
    np.testing.assert_array_equal(st.cases["rated"].reference.f_true[0, :2], [r.energy_loss, r.mixed_share])
