"""Hostile inputs of the distorted bore: the `&bore` lists and distortion file, and the
Python API around them. A bad value is a named error (file, group, variable, row) in
ringlube-solve and in Python, and nothing is written."""

from __future__ import annotations

import re
import shutil
import subprocess

import numpy as np
import pytest

import ringlube
from ringlube import InputError

from conftest import INPUTS

pytestmark = [pytest.mark.unit, pytest.mark.io]

DISTORTED = INPUTS / "crf450r_4000rpm_full_hot_distorted.nml"
BORE_LINE = re.compile(r"^&bore .*$", re.M)


def own_deck(folder, bore: str, files: dict[str, str | bytes] | None = None):
    """The shipped distorted deck (its calibration file and trace beside it) with its `&bore`
    line replaced by `bore` (and files written beside it); returns the deck and its line."""
    (folder / "pressure").mkdir()
    shutil.copy(INPUTS / "pressure" / "crf450r_4000rpm_full.csv", folder / "pressure")
    shutil.copy(INPUTS / "calibration.nml", folder)
    text = DISTORTED.read_text()
    assert len(BORE_LINE.findall(text)) == 1
    text = BORE_LINE.sub(bore, text)
    deck = folder / "d.nml"
    deck.write_text(text)
    for name, content in (files or {}).items():
        if isinstance(content, bytes):
            (folder / name).write_bytes(content)
        else:
            (folder / name).write_text(content)
    return deck


def line_of(deck, group: str) -> int:
    """The line of the deck that opens `group` (e.g. '&bore')."""
    text = deck.read_text()
    return text[: re.search(f"^{group} ", text, re.M).start()].count("\n") + 1


def refused(solver, deck, message: str) -> None:
    """ringlube-solve exits with an input error naming `message` and writes nothing; the
    Python reader raises the same message."""
    out = deck.parent / "r.h5"
    p = subprocess.run([solver, str(deck), "-q", "-o", str(out)], capture_output=True, text=True)
    assert p.returncode == 2, p.stderr
    assert message in p.stderr and "Traceback" not in p.stderr, p.stderr
    assert sorted(f.name for f in deck.parent.iterdir() if f.name.startswith("r.h5")) == []
    with pytest.raises(InputError, match=re.escape(message)):
        ringlube.Case.from_namelist(deck)


# --- a distorted bore names its distortion ------------------------------------------------


@pytest.mark.cli
@pytest.mark.parametrize("bore", ["&bore sectors = 24 /", "&bore distortion_file = '' /", ""])
def test_a_distorted_bore_without_its_distortion_is_refused(tmp_path, solver, bore):
    """No lists and no file (or no `&bore` at all) is no distortion: refused at the line that
    asks for a distorted bore, not run as a round bore on 24 sectors."""
    deck = own_deck(tmp_path, bore)
    line = line_of(deck, "&physics")
    refused(solver, deck, f"d.nml:{line}: &physics bore: 'distorted' needs the distortion")
    case = ringlube.Case().with_physics(bore="distorted", cavitation="jfo")
    with pytest.raises(InputError, match="&physics bore: 'distorted' needs the distortion"):
        case.validate()


@pytest.mark.cli
def test_a_phase_in_degrees_is_refused(tmp_path, solver):
    """Phases are in rad, within one turn: 45 (degrees meant) is refused; 2 pi is read."""
    deck = own_deck(tmp_path, "&bore order = 2, amplitude = 6.5e-6, phase = 45 /")
    line = line_of(deck, "&bore")
    refused(solver, deck, f"d.nml:{line}: &bore phase: value 1: must be in [-6.2832, 6.2832] rad")
    case = ringlube.Case.from_namelist(DISTORTED)
    assert case.with_bore(phase=[2 * np.pi, -2 * np.pi, 0.785]).validate() > 0


# --- the distortion file -----------------------------------------------------------------

ROWS = "0.0, 2, 6.5e-6, 0\n0.06, 2, 3e-6, 0.5\n0.0, 4, 2e-6, 0\n"


def test_a_distortion_file_with_a_byte_order_mark_reads_as_without(tmp_path):
    """A spreadsheet's UTF-8 byte-order mark before the first row (no header) is not data:
    the file reads as the same file without it."""
    for name, content in (("plain", ROWS.encode()), ("bom", b"\xef\xbb\xbf" + ROWS.encode())):
        folder = tmp_path / name
        folder.mkdir()
        deck = own_deck(folder, "&bore distortion_file = 'dist.csv' /", {"dist.csv": content})
        assert ringlube.Case.from_namelist(deck).validate() > 0


@pytest.mark.cli
def test_a_distortion_file_holds_at_most_ten_thousand_rows(tmp_path, solver):
    rows = "".join(f"{i * 1e-6:.6e}, 2, 1e-6, 0\n" for i in range(10001))
    deck = own_deck(tmp_path, "&bore distortion_file = 'dist.csv' /", {"dist.csv": rows})
    refused(solver, deck, f"{tmp_path / 'dist.csv'}:10001: more than 10000 rows")
    (tmp_path / "dist.csv").write_text(rows[: rows.rindex("\n", 0, len(rows) - 1) + 1])
    assert ringlube.Case.from_namelist(deck).validate() > 0


@pytest.mark.cli
def test_the_rows_of_an_order_increase_in_z_between_rows_of_other_orders(tmp_path, solver):
    """Rows of several orders may interleave; each order's own rows must increase in z."""
    ok = "0.0, 2, 6.5e-6, 0\n0.0, 4, 3e-6, 0\n0.01, 2, 3e-6, 0\n0.01, 4, 3e-6, 0\n"
    deck = own_deck(tmp_path, "&bore distortion_file = 'dist.csv' /", {"dist.csv": ok})
    assert ringlube.Case.from_namelist(deck).validate() > 0
    (tmp_path / "dist.csv").write_text("0.0, 2, 6.5e-6, 0\n0.01, 4, 3e-6, 0\n0.0, 2, 3e-6, 0\n")
    refused(solver, deck, f"{tmp_path / 'dist.csv'}:3: the rows of order 2 must increase strictly in z")


@pytest.mark.cli
@pytest.mark.parametrize("lists", ["order = 2, amplitude = 1e-6", "amplitude = 1e-6", "phase = 0.5"])
def test_a_distortion_file_beside_any_list_is_refused(tmp_path, solver, lists):
    """The file gives the orders, amplitudes and phases: a list beside it is the distortion
    given twice (not a list of the wrong length)."""
    deck = own_deck(tmp_path, f"&bore {lists}, distortion_file = 'dist.csv' /", {"dist.csv": ROWS})
    line = line_of(deck, "&bore")
    refused(solver, deck, f"d.nml:{line}: &bore distortion_file: give the distortion as the lists")


@pytest.mark.cli
def test_the_distortion_file_is_never_the_output(tmp_path, solver):
    """Like the deck and its other files, the distortion file is an input the result may not
    replace: refused before the run, in ringlube-solve and in ringlube.run, the file intact."""
    deck = own_deck(tmp_path, "&bore distortion_file = 'dist.csv' /", {"dist.csv": ROWS})
    dist = tmp_path / "dist.csv"
    p = subprocess.run([solver, str(deck), "-q", "-o", str(dist)], capture_output=True, text=True)
    assert p.returncode == 2 and "the distortion file" in p.stderr, p.stderr
    assert dist.read_text() == ROWS
    with pytest.raises(InputError, match="the distortion file"):
        ringlube.run(deck, output=dist)
    assert dist.read_text() == ROWS


# --- the Python API ----------------------------------------------------------------------


def test_numpy_lists_are_bore_lists():
    """A numpy array, or a list of numpy scalars, is the list it holds."""
    case = ringlube.Case.from_namelist(DISTORTED)
    for order, amplitude in (
        (np.array([2, 3, 4]), np.array([6.5e-6, 5e-6, 4e-6])),
        ([np.int64(2), np.int64(3), np.int64(4)], list(np.array([6.5e-6, 5e-6, 4e-6]))),
    ):
        c = case.with_bore(order=order, amplitude=amplitude)
        assert c["bore", "order"] == [2, 3, 4] and c["bore", "amplitude"] == [6.5e-6, 5e-6, 4e-6]
        assert c.validate() > 0
        assert c.value("bore", "amplitude") == [6.5e-6, 5e-6, 4e-6]


@pytest.mark.parametrize("value", [[[2, 3], 4], np.array([[2], [3], [4]])])
def test_a_list_of_lists_is_refused(value):
    with pytest.raises(InputError, match="&bore order: a list of lists"):
        ringlube.Case.from_namelist(DISTORTED).with_bore(order=value)


def test_the_distortion_file_is_a_path_like_the_others(tmp_path, monkeypatch):
    """Read from a deck, the file is absolute (a deck written elsewhere still finds it); set
    in Python, a relative path means the working directory of when it was set."""
    deck = own_deck(tmp_path, "&bore distortion_file = 'dist.csv' /", {"dist.csv": ROWS})
    case = ringlube.Case.from_namelist(deck)
    assert case["bore", "distortion_file"] == str(tmp_path / "dist.csv")
    (tmp_path / "elsewhere").mkdir()
    case.to_namelist(tmp_path / "elsewhere" / "d.nml")
    assert ringlube.Case.from_namelist(tmp_path / "elsewhere" / "d.nml").validate() > 0
    monkeypatch.chdir(tmp_path)
    built = ringlube.Case().with_physics(bore="distorted", cavitation="jfo")
    built = built.with_bore(distortion_file="dist.csv")
    assert built["bore", "distortion_file"] == str(tmp_path / "dist.csv")
    monkeypatch.chdir(tmp_path / "elsewhere")
    assert built.validate() > 0


# --- the study deck's bore constraints ---------------------------------------------------


@pytest.mark.parametrize(
    "constraint, why",
    [
        ("light_gap_share <= -5", "light_gap_share is 0 .. 100 %"),
        ("light_gap_share >= 101", "light_gap_share is 0 .. 100 %"),
        ("conformability <= -1", "conformability is at least 0"),
    ],
)
def test_a_bore_constraint_that_never_holds_is_refused(tmp_path, constraint, why):
    """A bound outside the values the result can take would leave every design infeasible
    after the whole study has run: refused when the study deck is read."""
    from ringlube.study.deck import read_study

    text = (INPUTS / "study_bore.nml").read_text()
    text = re.sub(r"'(crf450r_\w+\.nml)'", lambda m: f"'{INPUTS / m.group(1)}'", text)
    study = tmp_path / "study.nml"
    study.write_text(text.replace("  batch = 2\n", f"  batch = 2\n  constraints = '{constraint}'\n"))
    line = study.read_text().splitlines().index(f"  constraints = '{constraint}'") + 1
    message = f"study.nml:{line}: &study constraints: '{constraint}' never holds: {why}"
    with pytest.raises(InputError, match=re.escape(message)):
        read_study(study)
    study.write_text(text.replace("  batch = 2\n", "  batch = 2\n  constraints = 'light_gap_share <= 100'\n"))
    assert [str(c) for c in read_study(study).parsed_constraints] == ["light_gap_share <= 100"]


# --- the bore figures ------------------------------------------------------------------


@pytest.fixture(scope="module")
def distorted_result():
    case = ringlube.Case().with_physics(bore="distorted", cavitation="jfo")
    case = case.with_("bore", order=[4], amplitude=[10e-6], sectors=8).with_numerics(preset="fast")
    return ringlube.run(case)


def test_the_bore_figures_take_one_result_and_one_angle(distorted_result):
    import matplotlib.pyplot as plt

    from ringlube.plot_bore import bore_map_figure, bore_polar_figure, crank_angles, face_flow_figure

    assert len(bore_polar_figure(distorted_result, angles=380).axes) == 1
    assert crank_angles(np.array([90.0, 380.0])) == (90.0, 380.0) == crank_angles([90, 380])
    bore_map_figure(distorted_result)
    face_flow_figure(distorted_result)
    plt.close("all")
    with pytest.raises(InputError, match=r"--angles: 'None' is not a crank angle in deg"):
        bore_polar_figure([distorted_result], angles=None)


def test_the_bore_figures_name_what_is_not_a_result(distorted_result, tmp_path):
    from ringlube.plot_bore import bore_map_figure

    with pytest.raises(InputError, match=r"map of the gap: result 2 is a str, not a result \(ringlube.run"):
        bore_map_figure([distorted_result, str(tmp_path / "r.h5")])


# --- a study on a deck that names a distortion file -------------------------------------


@pytest.mark.parametrize(
    "bore, profile",
    [("&bore distortion_file = 'dist.csv' /", ""), ("&bore order = 2, amplitude = 6.5e-6 /", "face.csv")],
)
def test_a_study_resumed_after_its_distortion_or_profile_file_was_edited_is_refused(tmp_path, bore, profile):
    """The distortion file and the face profile are inputs of every run of a study: edited
    between its start and its resume, the resume is refused as for the deck, its calibration
    file and its trace (the stored runs were made with the old file); a study file that did not
    record them (written before they were) still resumes."""
    import json

    import h5py

    from ringlube.study.deck import read_study
    from ringlube.study.store import Study

    files = {"dist.csv": ROWS, "face.csv": "x_m, S_m\n0, 5e-6\n0.5e-3, 0\n1.004e-3, 6e-6\n"}
    deck = own_deck(tmp_path, bore, files)
    if profile:
        table = f"&ring profile = 'table', profile_file = '{profile}', "
        deck.write_text(re.sub(r"^&ring ", table, deck.read_text(), flags=re.M))
    study = tmp_path / "s.nml"
    study.write_text(
        f"&study\n  name = 's'\n  cases = '{deck}'\n  labels = 'd'\n  samples = 8\n"
        "  variables = 'tension'\n  lower = 10\n  upper = 20\n/\n"
    )
    edited = tmp_path / (profile or "dist.csv")
    s = read_study(study)
    assert str(edited) in s.inputs
    Study.open(s, tmp_path / "s.h5").save()
    Study.open(read_study(study), tmp_path / "s.h5")  # unchanged: resumes
    edited.write_text(edited.read_text().replace("6", "7"))
    with pytest.raises(InputError, match=rf"other contents of {re.escape(str(edited))}"):
        Study.open(read_study(study), tmp_path / "s.h5")
    with h5py.File(tmp_path / "s.h5", "r+") as h:  # a file that did not record it
        started = json.loads(h.attrs["inputs"])
        del started[str(edited)]
        h.attrs["inputs"] = json.dumps(started)
    Study.open(read_study(study), tmp_path / "s.h5")


def test_crank_angles_take_any_iterable_of_angles():
    """Angles given as a generator or a dict's keys are the angles they hold, as a list is
    (they were taken as one angle named '<generator object ...>' and refused)."""
    from ringlube.plot_bore import crank_angles

    assert crank_angles(a for a in (90.0, 380.0)) == (90.0, 380.0)
    assert crank_angles({90.0: "a", 380.0: "b"}.keys()) == (90.0, 380.0)
    assert crank_angles(np.float64(380.0)) == (380.0,) == crank_angles(380)
