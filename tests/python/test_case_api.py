"""The Case API: a warning when the source engine's defaults fill part of an
engine's geometry or ring, `ringlube show` with where every input came from,
`Case.with_<group>` for every group of the kernel's table, and a readable repr."""

from __future__ import annotations

import warnings

import pytest

import ringlube
from ringlube import Case, InputError, SourceEngineDefaultWarning
from ringlube.case.origins import SOURCE_ENGINE_INPUTS
from ringlube.cli import main
from ringlube.tables import GROUPS, INPUTS, PRESETS

from conftest import COLD, DECKS

pytestmark = pytest.mark.unit

FAST = dict(nodes=31, dpsi_deg=4.0)


def _warnings(fn):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        fn()
    return [w for w in caught if issubclass(w.category, SourceEngineDefaultWarning)]


# -- source-engine defaults -----------------------------------------------------------
def test_partial_engine_warns_naming_what_the_defaults_fill():
    """A case with its own bore but no crown_offset got -38.3 um silently."""
    case = Case(name="own").with_engine(bore_radius=43e-3).with_ring(width=1.2e-3).with_numerics(**FAST)
    caught = _warnings(lambda: ringlube.run(case))
    assert len(caught) == 1
    message = str(caught[0].message)
    assert message.startswith("case 'own': the source engine's (CRF450R) defaults fill ")
    assert (
        "&engine crank_radius, conrod_length; &ring crown_height, crown_offset, tension, radial_depth"
        in message
    )
    assert "while the case sets &engine bore_radius; &ring width" in message
    assert caught[0].filename == __file__  # points at the caller's line


@pytest.mark.parametrize("deck", DECKS, ids=lambda p: p.stem)
def test_shipped_decks_and_the_plain_source_engine_do_not_warn(deck):
    assert _warnings(lambda: ringlube.run(Case.from_namelist(deck).with_numerics(**FAST))) == []
    assert _warnings(lambda: Case().with_numerics(**FAST).validate()) == []  # nothing set: knowingly


def test_a_complete_own_engine_does_not_warn():
    own = {g: {} for g, _ in SOURCE_ENGINE_INPUTS}
    values = dict(crank_radius=43e-3, conrod_length=143.5e-3, bore_radius=43e-3, width=1.2e-3)
    values.update(crown_height=8e-6, crown_offset=0.0, tension=15.0, radial_depth=3.4e-3)
    for g, n in SOURCE_ENGINE_INPUTS:
        own[g][n] = values[n]
    case = Case(own).with_numerics(**FAST)
    assert _warnings(case.validate) == []
    assert case.source_engine_defaults() == (list(SOURCE_ENGINE_INPUTS), [])
    assert _warnings(case.with_ring(width=1.0e-3).validate) == []  # a study's variations of it


def test_deck_with_partial_engine_warns_once_in_the_cli(tmp_path, capsys):
    deck = tmp_path / "part.nml"
    deck.write_text("&engine bore_radius = 43e-3 /\n&numerics nodes = 31, dpsi_deg = 4.0 /\n")
    assert main(["run", str(deck), "-o", str(tmp_path / "r.h5"), "-q"]) == 0
    err = capsys.readouterr().err.strip().splitlines()
    assert err == [
        f"ringlube: warning: {deck}: the source engine's (CRF450R) defaults fill &engine crank_radius, "
        "conrod_length; &ring width, crown_height, crown_offset, tension, radial_depth while the case "
        "sets &engine bore_radius; set them for your engine (docs/own_engine.md)"
    ]


# -- ringlube show ----------------------------------------------------------------------
def test_show_lists_every_input_with_its_origin(capsys):
    assert main(["show", str(COLD)]) == 0
    out, err = capsys.readouterr()
    lines = out.splitlines()
    assert len(lines) == 2 + len(INPUTS) and err == ""
    rows = {tuple(line.split()[:2]): line.split()[2:] for line in lines[2:]}
    assert rows["&ring", "crown_offset"] == ["deck", "-3.83e-05", "[m]"]
    assert rows["&ring", "tension"] == ["deck", "8.0", "[N]"]  # the unit the deck says
    assert rows["&surface", "zeta_kappa_sigma"][:2] == ["calibration", "file"]
    assert rows["&numerics", "nodes"] == ["preset", "'default'", str(PRESETS["default"]["nodes"])]
    assert rows["&lubricant", "supply_film"][0] == "default"


def test_show_set_only_and_warning(tmp_path, capsys):
    deck = tmp_path / "part.nml"
    deck.write_text("&ring width = 1.2e-3 /\n&numerics preset = 'fast' /\n")
    assert main(["show", str(deck)]) == 0
    out, err = capsys.readouterr()
    assert "&numerics   nodes                    preset 'fast'" in out
    assert err.startswith(f"ringlube: warning: {deck}: the source engine's") and len(err.splitlines()) == 1
    assert main(["show", str(deck), "--set"]) == 0
    out = capsys.readouterr().out.splitlines()[2:]
    assert [line.split()[:3] for line in out] == [["&ring", "width", "deck"], ["&numerics", "preset", "deck"]]


def test_show_bad_deck_is_one_line(tmp_path, capsys):
    deck = tmp_path / "bad.nml"
    deck.write_text("&ring widht = 1e-3 /\n")
    assert main(["show", str(deck)]) == 2
    err = capsys.readouterr().err
    assert "widht" in err and len(err.strip().splitlines()) == 1


def test_origins_in_python():
    case = Case.from_namelist(COLD).with_ring(width=1.1e-3)
    o = case.origins()
    assert o["ring", "width"] == "Python" and o["ring", "tension"] == "deck"
    assert o["operating", "pressure_scale"] == "calibration file"
    values = {(r.group, r.name): r.value for r in case.effective_inputs()}
    assert values["ring", "width"] == 1.1e-3 and values["operating", "pressure_scale"] == case.value(
        "operating", "pressure_scale"
    )
    assert Case({"ring": {"width": 1e-3}}).origins()["ring", "width"] == "Python"


# -- with_<group> and repr ---------------------------------------------------------------
@pytest.mark.parametrize("group", GROUPS)
def test_with_group_for_every_group(group):
    method = getattr(Case, f"with_{group}")
    names = [n for g, n in INPUTS if g == group]
    assert all(n in method.__doc__ for n in names)
    spec = INPUTS[group, names[0]]
    value = spec.default_value if spec.kind != "string" else "x.txt"
    if value is None or spec.kind == "choice":
        value = spec.choices[0] if spec.kind == "choice" else PRESETS["default"][names[0]]
    base = Case()
    new = method(base, **{names[0]: value})
    assert new is not base and base.to_dict() == {}
    assert str(new[group, names[0]]).endswith(str(value))


def test_with_group_checks_names():
    with pytest.raises(InputError, match=r"&lubricant eta: unknown variable; did you mean eta0\?"):
        Case().with_lubricant(eta=0.1)
    with pytest.raises(InputError, match=r"&engine zzz: unknown variable \(known: crank_radius"):
        Case().with_engine(zzz=1.0)


def test_repr_is_readable():
    case = Case.from_namelist(COLD).with_ring(width=1.1e-3)
    text = repr(case)
    lines = text.splitlines()
    assert lines[0].startswith(f"<Case 'crf450r_4000rpm_full_cold' from {COLD}: ")
    assert any(line.split()[0] == "&ring" and "width = 0.0011*" in line for line in lines)
    assert lines[-1] == "  (* changed in Python)"
    html = case._repr_html_()
    assert (
        "<table>" in html
        and "<td>&amp;ring</td><td>width</td><td>0.0011</td><td>m</td><td>Python</td>" in html
    )
    assert "<td>crown_height</td><td>9.31e-06</td><td>m</td><td>deck</td>" in html
    assert repr(Case()) == "<Case 'case': 0 inputs set, the rest defaults>"
