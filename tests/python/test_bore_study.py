"""The distorted bore in design studies and on the validation page: the results of a
distorted bore (face leakage, light gaps, conformability) as objectives and constraints, the
`&bore` lists read from a deck into a case, the shipped bore study deck read, the trade that
study is for (tension buys conformity on a distorted bore, no sealing on a round one), and the
validation page's section rendered from its runs."""

from __future__ import annotations

import re
import warnings

import numpy as np
import pytest

from ringlube.case import Case
from ringlube.errors import InputError
from ringlube.study import read_study

from conftest import COLD, DISTORTED_DECKS, INPUTS

pytestmark = [pytest.mark.numerics]

DISTORTED = INPUTS / "crf450r_4000rpm_full_hot_distorted.nml"
BORE_RESULTS = ("face_leakage", "light_gap_share", "conformability")


def conformability(case: Case, width: float, tension: float) -> float:
    """The classical conformability of the case's bore at (width, tension), from the closed
    form (docs/bore.md), not from the kernel: the largest A_k over q r0^4 / (E I (k^2 - 1)^2),
    q = F_T / r0 (tension in N), I = b d^3 / 12."""
    assert case.value("ring", "tension_unit") == "N"
    r0 = case.value("engine", "bore_radius")
    e = case.value("surface", "e_ring")
    d = case.value("ring", "radial_depth")
    q = tension / r0
    ei = e * width * d**3 / 12.0
    orders, amps = case.value("bore", "order"), case.value("bore", "amplitude")
    return max(a / (q * r0**4 / (ei * (k * k - 1) ** 2)) for k, a in zip(orders, amps))


def test_case_reads_the_bore_lists(tmp_path):
    case = Case.from_namelist(DISTORTED)
    assert case["bore", "order"] == [2, 3, 4]
    assert case["bore", "amplitude"] == [6.5e-6] * 3
    assert case.value("bore", "amplitude") == [6.5e-6] * 3
    # written out and read back: the same lists
    path = tmp_path / "again.nml"
    case.to_namelist(path)
    again = Case.from_namelist(path)
    assert again["bore", "order"] == [2, 3, 4] and again["bore", "amplitude"] == [6.5e-6] * 3


def study_deck(tmp_path, base, objectives, constraints="", sizes=None, name="bore") -> object:
    sizes = sizes or "samples = 24, population = 8, generations = 3, repeats = 1"
    path = tmp_path / f"{name}.nml"
    path.write_text(f"""&study
  name = '{name}', cases = '{base}', labels = 'r4000'
  variables = 'width', 'tension', lower = 0.54e-3, 8.0, upper = 1.34e-3, 26.0
  reference = 1.004e-3, 8.0
  objectives = {objectives}
  {constraints}
  {sizes}, seed = 2, batch = 4
/
""")
    return path


@pytest.mark.parametrize("name", BORE_RESULTS)
def test_bore_results_are_objectives_and_constraints_of_a_distorted_deck(tmp_path, name):
    base = tmp_path / "d.nml"
    Case.from_namelist(DISTORTED).to_namelist(base)
    s = read_study(
        study_deck(tmp_path, base, f"'energy_loss', '{name}'", f"constraints = '{name} <= reference'")
    )
    assert name in s.objectives and name in s.outputs
    assert [str(c) for c in s.parsed_constraints] == [f"{name} <= reference"]


@pytest.mark.parametrize("name", BORE_RESULTS)
@pytest.mark.parametrize("where", ["objectives", "constraints"])
def test_bore_results_on_a_round_deck_name_the_switch(tmp_path, name, where):
    if where == "objectives":
        path = study_deck(tmp_path, COLD, f"'energy_loss', '{name}'")
    else:
        path = study_deck(tmp_path, COLD, "'energy_loss'", f"constraints = '{name} <= 1'")
    with pytest.raises(InputError) as exc:
        read_study(path)
    msg = str(exc.value)
    assert re.match(rf"{re.escape(str(path))}:\d+: &study {where}: ", msg), msg
    assert f"'{name}' needs &physics bore = 'distorted' in every base deck" in msg, msg


def test_a_bore_list_is_no_study_variable(tmp_path):
    base = tmp_path / "d.nml"
    Case.from_namelist(DISTORTED).to_namelist(base)
    path = study_deck(tmp_path, base, "'energy_loss'")
    path.write_text(
        path.read_text()
        .replace("'width', 'tension'", "'width', 'bore:amplitude'")
        .replace("8.0, upper", "1e-6, upper")
        .replace("1.34e-3, 26.0", "1.34e-3, 2e-5")
        .replace("1.004e-3, 8.0", "1.004e-3, 5e-6")
    )
    with pytest.raises(InputError) as exc:
        read_study(path)
    assert str(exc.value).endswith(
        "&study variables: 'bore:amplitude' is not a number (&bore amplitude takes a list of "
        "values); a study samples real values: vary it with one base deck per value instead"
    ), str(exc.value)


def test_shipped_bore_study_reads():
    s = read_study(INPUTS / "study_bore.nml")
    assert s.labels == ["r4000", "r12000"] and not s.scene
    assert s.variables == ["width", "tension", "crown_height"] and s.units == ["m", "N", "m"]
    assert {"energy_loss", "blowby", "oil_to_chamber", "light_gap_share"} <= set(s.outputs)
    for deck in s.cases:
        case = Case.from_namelist(deck)
        physics = {n: case.value("physics", n) for n in ("bore", "ring_pack", "cavitation", "inlet")}
        assert physics == {"bore": "distorted", "ring_pack": "gas", "cavitation": "jfo", "inlet": "starved"}
        assert case.value("ring", "tension_unit") == "N"
        # the reference ring (1.004 mm, 8 N) does not conform dry to the order-4 distortion
        assert conformability(case, 1.004e-3, 8.0) == pytest.approx(1.20, abs=0.01)


def shipped_pair(tension: float) -> tuple:
    """The shipped 4000 r/min distorted deck at ``tension`` and the same deck on a round bore,
    both run as shipped (24 sectors, preset 'default': a few seconds together)."""
    import ringlube
    from ringlube.validate.bore import round_bore

    case = Case.from_namelist(DISTORTED).with_ring(tension=tension)
    return case, ringlube.run(case), ringlube.run(round_bore(case))


@pytest.mark.slow
def test_tension_buys_conformity_on_the_distorted_bore_only():
    """The trade the bore study is for: on the shipped distorted bore the source ring at 8 N
    does not conform to order 4 (1.20 of its limit, closed form) and leaves light gaps that
    pass gas through its faces; at 26 N it conforms, with no light gap and no face leakage,
    for more friction. On the round bore the same tension buys no sealing: its blowby does not
    fall. (At 4000 r/min the gaps open on the low-pressure strokes, so the face leakage is
    small beside the blowby: docs/validation.md, "Bore distortion and conformability".)"""
    low_case, low, low_round = shipped_pair(8.0)
    _, high, high_round = shipped_pair(26.0)
    w = low_case.value("ring", "width")
    assert low.scalars["conformability"] == pytest.approx(conformability(low_case, w, 8.0), rel=1e-12)
    assert low.scalars["conformability"] > 1.0 > high.scalars["conformability"]
    # the distorted bore: light gaps and face leakage at 8 N, none at 26 N
    assert low.scalars["light_gap_share"] > 0.5 and high.scalars["light_gap_share"] == 0.0
    assert low.scalars["face_leakage"] > 0.0 == high.scalars["face_leakage"]
    # the tension's price on both bores
    assert high.energy_loss > 1.2 * low.energy_loss and high_round.energy_loss > 1.2 * low_round.energy_loss
    # the round bore: no sealing bought (the end gaps decide the blowby)
    assert high_round.blowby >= low_round.blowby
    assert "light_gap_share" not in low_round.scalars or low_round.scalars["light_gap_share"] == 0


@pytest.mark.slow
def test_the_bore_section_renders_its_runs(monkeypatch):
    """The validation page's bore section from its runs (here one speed, two tensions, coarse):
    every run a row with its own numbers, the closed-form limit beside the kernel's
    conformability, and the verdict from the numbers."""
    import ringlube.validate.bore as vb

    monkeypatch.setattr(vb, "BORE_DECKS", (("CRF450R", DISTORTED.name),))
    monkeypatch.setattr(vb, "BORE_TENSIONS", (8.0, 26.0))
    monkeypatch.setattr(vb, "BORE_WIDTHS", ())
    bore = vb.bore_validation(INPUTS.parent, adjust=coarse)
    assert [(e, s, b, t) for e, s, b, _, t, _ in bore["rows"]] == [
        ("CRF450R", 4000, "round", 8.0),
        ("CRF450R", 4000, "round", 26.0),
        ("CRF450R", 4000, "distorted", 8.0),
        ("CRF450R", 4000, "distorted", 26.0),
    ]
    md = "\n".join(vb.render_bore(bore))
    assert md.startswith("## Bore distortion and conformability")
    base = bore["bases"]["CRF450R", 4000]
    for engine, speed, b, w, t, r in bore["rows"]:
        row = f"| {engine} | {speed} | {b} | {w * 1e3:.4g} mm, {t:g} N |"
        assert f"{row} " in md and f"| {r.energy_loss:.3f} | {r.friction_power:.1f} | {r.blowby:.2f} |" in md
        if b == "distorted":
            want = conformability(base, w, t)
            assert f"| {want:.4f} | {r.scalars['conformability']:.4f} |" in md
            assert r.scalars["conformability"] == pytest.approx(want, rel=1e-12)
            assert f"| {r.scalars['light_gap_share']:.2f} | {r.scalars['sector_jumps']:.0f} |" in md
    assert "- **CRF450R, 4000 r/min, 1.004 mm ring, 8 to 26 N.**" in md
    assert f"conforms dry from {8.0 * conformability(base, base.value('ring', 'width'), 8.0):.1f} N" in md


def test_a_row_without_a_period_says_so_beside_a_step_at_the_ceiling():
    """A run not periodic in its cycles whose only flagged step is one held at the ceiling
    (the ring pushed off the liner: an answer, not a failure) is 'no (no period)', not
    'no (1 flagged)' (the 12,000 r/min deck's rows said so)."""
    import ringlube.validate.bore as vb

    class Run:
        energy_loss, friction_power, converged, flagged_steps = 3.583, 358.3, False, 1
        scalars = dict.fromkeys(
            ("conformability", "blowby", "face_leakage", "oil_to_chamber", "light_gap_share"), 1.0
        ) | {"sector_jumps": 19.0, "radial_collapse_share": 0.28, "flutter_events": 1.0, "periodic": 0.0}

    assert vb._row("CRF450R", 12000, "distorted", 1.004e-3, 14.0, Run()).endswith("| no (no period) |")
    Run.scalars = Run.scalars | {"periodic": 1.0}
    assert vb._row("CRF450R", 12000, "distorted", 1.004e-3, 14.0, Run()).endswith("| no (1 flagged) |")


def test_a_span_of_equal_numbers_is_one_number():
    """The radial collapse's range over the tensions read '0.28-0.28 %' where every tension
    gave 0.28."""
    from ringlube.validate.bore import _span

    assert _span([0.2777, 0.2778, 0.2781], ".2f") == "0.28"
    assert _span([0.42, 0.2777], ".2f") == "0.28-0.42"


def test_validation_page_has_the_bore_section():
    text = (INPUTS.parent / "docs" / "validation.md").read_text()
    lines = text.splitlines()
    assert "## Bore distortion and conformability" in lines
    assert "### Where the tension optimum lands, and why" in lines
    assert lines.index("## Bore distortion and conformability") < lines.index("## Figures")


def coarse(deck) -> Case:
    """A shipped distorted deck (a path or a case) at coarse settings (8 sectors, 'fast', at
    most 2 cycles)."""
    case = deck if isinstance(deck, Case) else Case.from_namelist(deck)
    return case.with_bore(sectors=8).with_numerics(preset="fast", max_cycles=2)


@pytest.mark.cli
@pytest.mark.parametrize("deck", DISTORTED_DECKS, ids=lambda p: p.stem)
def test_distorted_deck_round_trips_and_runs_alike_in_python_and_the_cli(deck, solver, tmp_path):
    import subprocess

    import ringlube

    case = Case.from_namelist(deck)
    case.to_namelist(tmp_path / "copy.nml")
    assert Case.from_namelist(tmp_path / "copy.nml") == case
    path = tmp_path / "coarse.nml"
    coarse(deck).to_namelist(path)
    out = tmp_path / "cli.h5"
    done = subprocess.run([solver, "-q", str(path), "-o", str(out)], capture_output=True, text=True)
    assert done.returncode in (0, 3), done.stderr  # 3: not converged, its result written (2 cycles)
    cli = ringlube.load(out)
    with warnings.catch_warnings():  # the decks set every source-engine input themselves
        warnings.simplefilter("error", ringlube.SourceEngineDefaultWarning)
        py = ringlube.run(Case.from_namelist(path))
    assert set(py.series) == set(cli.series) and set(py.scalars) == set(cli.scalars)
    for name in py.series:
        np.testing.assert_array_equal(getattr(py, name), getattr(cli, name), err_msg=name)
    for name in py.scalars:
        if name != "run_time":
            assert getattr(py, name) == getattr(cli, name), name
    # the kernel's conformability is the closed form's
    w, t = case.value("ring", "width"), case.value("ring", "tension")
    assert py.scalars["conformability"] == pytest.approx(conformability(case, w, t), rel=1e-12)
