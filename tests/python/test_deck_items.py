"""One deck parser: the kernel's scanner exported as ``rl_items``
(:mod:`ringlube.case.items`) reads kernel decks, calibration files and ``&study`` decks."""

from __future__ import annotations

import dataclasses

import pytest

import ringlube
from ringlube import InputError
from ringlube.case.items import items, python_value
from ringlube.case.text import format_value

from conftest import COLD, INPUTS

pytestmark = [pytest.mark.unit, pytest.mark.io]

KERNEL_DECKS = sorted(p for p in INPUTS.glob("*.nml") if not p.name.startswith("study_"))
STUDY_DECKS = sorted(INPUTS.glob("study_*.nml"))


def _as_text(its) -> str:
    """Items written back as a deck (one group block per group opening)."""
    out, opened = [], None
    for it in its:
        if (it.group, it.group_line) != opened:
            if opened:
                out.append("/")
            out.append(f"&{it.group}")
            opened = (it.group, it.group_line)
        value = "'" + it.value.replace("'", "''") + "'" if it.quoted else it.value
        out.append(f"  {it.name} = {value}" if it.index == 1 else f"    {value}")
    return "\n".join([*out, "/", ""])


def _key(its):
    return [(i.group, i.name, i.value, i.index, i.quoted) for i in its]


@pytest.mark.parametrize("deck", KERNEL_DECKS + STUDY_DECKS, ids=lambda p: p.name)
def test_rl_items_round_trips_every_shipped_deck(deck):
    lists = deck.name.startswith("study_") or "&bore" in deck.read_text()  # (&bore order = 2, 3, 4)
    first = items(deck.read_text(), str(deck), lists=lists)
    again = items(_as_text(first), "again.nml", lists=lists)
    assert first and _key(again) == _key(first)
    text = deck.read_text().splitlines()
    for it in first:  # each item's line holds its value (as written, quoted or not)
        written = format_value(it.value) if it.quoted else it.value
        assert written.replace("''", "'") in text[it.line - 1].replace("''", "'"), (it, text[it.line - 1])


def test_round_tripped_deck_reads_to_the_same_case(tmp_path):
    first = items(COLD.read_text(), str(COLD))
    copy = tmp_path / COLD.name
    copy.write_text(_as_text(first))
    (tmp_path / "calibration.nml").write_text((INPUTS / "calibration.nml").read_text())
    (tmp_path / "pressure").symlink_to(INPUTS / "pressure")
    a, b = ringlube.Case.from_namelist(COLD), ringlube.Case.from_namelist(copy)
    paths = {("operating", "pressure_file"), ("output", "file"), ("calibration", "file")}
    assert [r[:3] for r in a.effective_inputs() if r[:2] not in paths] == [
        r[:3] for r in b.effective_inputs() if r[:2] not in paths
    ]


def test_values_keep_their_quotes_blanks_and_lines():
    text = "! c\n&study name = 'it''s ', w = 1, 2.5,\n   3d0 ! three\n s = .true. /\n"
    its = items(text, "s.nml", lists=True)
    assert [(i.name, i.value, i.line, i.index) for i in its] == [
        ("name", "it's ", 2, 1),
        ("w", "1", 2, 1),
        ("w", "2.5", 2, 2),
        ("w", "3d0", 3, 3),
        ("s", ".true.", 4, 1),
    ]
    assert [python_value(i) for i in its] == ["it's ", 1, 2.5, 3.0, True]
    assert {i.group_line for i in its} == {2}


@pytest.mark.parametrize(
    "line", ["width = 1.0e-3, 1.2e-3", "width = 1.0e-3 1.2e-3", "width = 1.0e-3,\n  1.2e-3"]
)
def test_a_list_for_a_kernel_scalar_is_refused(tmp_path, line):
    deck = tmp_path / "d.nml"
    deck.write_text(f"&engine\n  crank_radius = 31.5e-3\n/\n&ring\n  {line}\n/\n")
    with pytest.raises(
        InputError, match=r"d\.nml:[56]: &ring width: malformed value .*one value per variable"
    ):
        ringlube.Case.from_namelist(deck)
    with pytest.raises(InputError, match=r"d\.nml:[56]: &ring width: .*one value per variable"):
        items(deck.read_text(), str(deck))
    assert [i.value for i in items(deck.read_text(), str(deck), lists=True)][-2:] == ["1.0e-3", "1.2e-3"]


@pytest.mark.parametrize(
    "text, message",
    [
        (
            "&study lower(1) = 3 /",
            r's\.nml:1: &study lower: "lower\(1\)": no array elements .*give the whole list',
        ),
        ("&study samples = 3, lower(1) = 3 /", r's\.nml:1: &study lower: "lower\(1\)": no array elements'),
        (
            "&ring width = 1e-3, density(1) = 7800 /",
            r's\.nml:1: &ring density: "density\(1\)" is not an input',
        ),
        (
            "&ring width = 1e-3, crown_height%x = 1e-6 /",
            r's\.nml:1: &ring crown_height: "crown_height%x" is not an',
        ),
        ("&study cases = 'a.nml\n/", r"s\.nml:1: &study cases: unterminated string"),
        ("&study samples = 3\n", r"s\.nml:2: &study \(opened on line 1\) is not closed"),
    ],
)
def test_scanner_errors_name_file_line_group_and_variable(text, message):
    """The variable named is the one written wrongly (an array element or a component after
    another variable used to be blamed on that one: '&ring width: malformed value')."""
    with pytest.raises(InputError, match=message):
        items(text, "s.nml", lists=text.startswith("&study"))


def test_case_values_come_from_the_scanner():
    case = ringlube.Case.from_namelist(COLD)
    first = items(COLD.read_text(), str(COLD))
    for it in first:
        if (it.group, it.name) in {
            ("operating", "pressure_file"),
            ("output", "file"),
            ("calibration", "file"),
        }:
            assert case[it.group, it.name].endswith(it.value)  # paths are made absolute
        else:
            assert case[it.group, it.name] == python_value(it)
            assert type(case[it.group, it.name]) is type(python_value(it))


# --- &study decks through the same scanner ----------------------------------------------


def _study(tmp_path, body: str):
    path = tmp_path / "s.nml"
    path.write_text(f"! a study\n&study\n  cases = '{COLD}'\n{body}/\n")
    return path


@pytest.mark.parametrize(
    "body, message",
    [
        ("  samples = 64.5\n", r"s\.nml:4: &study samples: must be a whole number, got 64\.5"),
        ("  samples = 'many'\n", r"s\.nml:4: &study samples: must be a whole number, got 'many'"),
        ("  samples = 0\n", r"s\.nml:4: &study samples: must be at least 1, got 0"),
        ("  samples = 2000000\n", r"s\.nml:4: &study samples: must be at most 1,000,000"),
        ("  seed = 1, 2\n", r"s\.nml:4: &study seed: takes one value, got 2"),
        ("  sampler = 'halton'\n", r"s\.nml:4: &study sampler: must be one of 'sobol', 'lhs'"),
        ("  labels = cold\n", r"s\.nml:4: &study labels: must be quoted names, got cold"),
        ("  weights = 1.0,\n    nan\n", r"s\.nml:5: &study weights: must be finite numbers, got nan"),
        ("  scene = 'yes'\n", r"s\.nml:4: &study scene: must be \.true\. or \.false\."),
        ("  sampels = 64\n", r"s\.nml:4: &study sampels: unknown variable \(known: "),
        ("  folds = 1\n", r"s\.nml:4: &study folds: must be at least 2, got 1"),
        ("  labels = 'a', 'b'\n", r"s\.nml:4: &study labels: one distinct label per case \(1 cases\)"),
        ("  lower(1) = 1e-3\n", r"s\.nml:4: &study lower: \"lower\(1\)\": no array elements"),
        ("  name = 'x'\n/\n&ring width = 1e-3\n", r"s\.nml:6: &ring: not a group of a study deck"),
    ],
)
def test_study_errors_carry_file_line_group_and_variable(tmp_path, body, message):
    from ringlube.study.deck import read_study

    with pytest.raises(InputError, match=message) as exc:
        read_study(_study(tmp_path, body))
    assert "\n" not in str(exc.value)


def test_study_table_drives_the_settings_and_the_docs():
    from ringlube.study.settings import StudySettings
    from ringlube.study.table import STUDY, study_markdown

    fields = {f.name: f for f in dataclasses.fields(StudySettings)}
    for row in STUDY.values():
        assert row.name in fields  # every &study variable is a setting
        if row.kind in ("integer", "choice", "logical"):
            assert fields[row.name].default == row.default
    assert all(f"| `{name}` |" in study_markdown() for name in STUDY)


def test_optimisation_md_study_table_is_current():
    from ringlube.docgen import update_doc

    from conftest import ROOT

    assert update_doc(ROOT / "docs" / "optimisation.md", write=False), (
        "docs/optimisation.md is stale: run `.venv/bin/python -m ringlube.docgen`"
    )


def test_a_value_of_any_length_reads_whole_as_in_ringlube_solve():
    """The f2py layer held a value to 4096 bytes, where ringlube-solve reads any length."""
    assert items("&study\n name = '" + "x" * 5000 + "' /", "s.nml", lists=True)[0].value == "x" * 5000
    assert items("&study name = '" + "x" * 4096 + "' /", "s.nml", lists=True)[0].value == "x" * 4096
    values = [i.value for i in items("&s a = 'é" + "y" * 9000 + "', '', 'z' /", "s.nml", lists=True)]
    assert values == ["é" + "y" * 9000, "", "z"]
    with pytest.raises(InputError, match=r"s\.nml:1: &s " + "n" * 65 + ": longer than 64 bytes"):
        items("&s " + "n" * 65 + " = 1 /", "s.nml", lists=True)


@pytest.mark.parametrize(
    "line, message",
    [
        ("&physics inlet = 'starved' /", r"d\.nml:3: &physics inlet: 'starved' needs"),
        (
            "&physics cavity_pressure = 'trailing_gas' /",
            r"d\.nml:3: &physics cavity_pressure: 'trailing_gas'",
        ),
        ("&numerics dpsi_deg = 7 /", r"d\.nml:3: &numerics dpsi_deg: must divide 720"),
        ("&numerics h0_floor = 1e-5, h0_ceiling = 2e-5 /", r"d\.nml:3: &numerics h0_ceiling: must exceed"),
        ("&operating cavitation_pressure = 2e5 /", r"d\.nml:3: &operating cavitation_pressure: must not"),
        ("&operating pressure_file = 'none.csv' /", r"d\.nml:3: &operating pressure_file: .*not found"),
        ("&calibration file = 'none.nml' /", r"d\.nml:3: &calibration file: .*none\.nml"),
    ],
)
def test_checks_of_the_whole_case_name_the_line(tmp_path, line, message):
    """The checks that relate inputs (run after the deck is read) and the files it names give
    the line that sets the variable, as the scanner's errors do (README: file, line, group
    and variable); before, only the file."""
    deck = tmp_path / "d.nml"
    deck.write_text(f"! a deck\n&engine crank_radius = 0.043 /\n{line}\n")
    with pytest.raises(InputError, match=message):
        ringlube.Case.from_namelist(deck).value("ring", "width")


def test_a_calibration_file_changed_in_python_is_blamed_at_its_change():
    """A missing calibration file named by a change in Python is reported at that change,
    not at the deck's own &calibration line (which names a file that exists)."""
    case = ringlube.Case.from_namelist(COLD).with_("calibration", file="/nonexistent/cal.nml")
    with pytest.raises(InputError, match=r"changed in Python>:\d+: &calibration file: /nonexistent/cal\.nml"):
        case.validate()


def test_a_component_names_the_variable_meant():
    """'ring%density = 7800' in &ring suggests 'density = value', not 'ring = value' (also
    written without blanks, 'ring%density=7800')."""
    for text in ("&ring ring%density = 7800 /", "&ring ring%density=7800 /"):
        with pytest.raises(InputError, match=r"e\.g\. density = value"):
            items(text, "s.nml")


@pytest.mark.cli
def test_a_study_deck_run_as_a_case_says_so(tmp_path, solver):
    """`ringlube-solve STUDY.nml` (and a study deck read as a case) says it is a study deck,
    instead of a malformed value of its first list."""
    import subprocess

    p = subprocess.run([solver, str(INPUTS / "study_default.nml"), "-q"], capture_output=True, text=True)
    assert p.returncode == 2 and "this is a study deck, not a case deck" in p.stderr, p.stderr
    with pytest.raises(InputError, match="this is a study deck"):
        ringlube.Case.from_namelist(INPUTS / "study_default.nml").value("ring", "width")
