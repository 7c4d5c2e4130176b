"""The ring-pack and oil-sensitivity sections of docs/validation.md and the
split of `ringlube validate` into computing and rendering."""

from __future__ import annotations

import numpy as np
import pytest

from ringlube import Case
from ringlube.validate.compute import STORY_RINGS, STORY_SPEEDS, ring_pack_validation
from ringlube.validate.render import _charge_mg, _render_ring_pack

from conftest import COLD, ROOT

pytestmark = pytest.mark.numerics


def test_ring_pack_section_renders_the_computed_runs():
    """Every story run appears in the table with its own numbers; the share of the charge is
    the blowby mass over the swept volume's air at 0.1 MPa and 300 K (530 mg for the 96 mm
    bore and 63 mm stroke)."""
    cold = Case.from_namelist(COLD).with_numerics(preset="fast")
    hot = Case.from_namelist(COLD.with_name("crf450r_4000rpm_full_hot.nml")).with_numerics(preset="fast")
    rp = ring_pack_validation({"cold": cold, "hot": hot})
    assert len(rp["story"]) == len(STORY_RINGS) * len(STORY_SPEEDS)
    charge = np.pi * 0.048**2 * 0.063 * 1e5 / (287 * 300) * 1e6
    assert abs(_charge_mg(cold) / charge - 1) < 1e-12 and abs(charge - 530) < 1
    md = "\n".join(_render_ring_pack(rp, cold))
    for speed, name, r in rp["story"]:
        row = f"| {speed:.0f} | {name} | {r.energy_loss:.3f} | {r.friction_power:.1f} | {r.blowby:.2f} |"
        assert row in md, row
    r = rp["decks"]["cold"]
    assert f"| {r.blowby_mass / charge:.2%} |" in md


def test_generated_validation_has_the_sections():
    text = (ROOT / "docs" / "validation.md").read_text()
    lines = text.splitlines()
    assert "## Oil to the chamber against the supply film" in lines
    assert "## The gas around the ring: blowby, inter-ring pressure, ring lift" in lines
    assert "**For a ring engineer**" in text
