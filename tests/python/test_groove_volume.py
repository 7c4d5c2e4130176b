"""The top ring groove's gas volume can follow the ring (docs/ring_pack.md, "The groove"): with
`&ring_pack groove_volume = 0` the kernel takes the groove cut for the ring, from its width and
radial depth, the side clearance and the back clearance; a volume given (the default 0.1 cm^3
included) is used as it is."""

from __future__ import annotations

import math

import pytest

import ringlube
from ringlube import Case, InputError

from conftest import INPUTS

pytestmark = pytest.mark.unit

DECK = INPUTS / "crf450r_12000rpm_full_hot_gas.nml"


def _ruled(**numerics):
    """The deck with the groove's rule (groove_volume = 0)."""
    return Case.from_namelist(DECK).with_("ring_pack", groove_volume=0.0).with_numerics(**numerics)


def _groove(r0, a, b, clearance, back):
    """The rule written out here: the space behind the ring (back clearance ``back``) over the
    groove height, plus the side clearance over the ring's radial depth (annuli)."""
    behind = math.pi * ((r0 - a) ** 2 - (r0 - a - back) ** 2) * (b + clearance)
    side = math.pi * (r0**2 - (r0 - a) ** 2) * clearance
    return behind + side


@pytest.mark.parametrize("width, back", [(0.54e-3, 0.3e-3), (1.34e-3, 0.7e-3)])
def test_default_volume_is_the_groove_of_the_ring(width, back):
    """A run with groove_volume = 0 is bit for bit the run with the rule's volume given."""
    case = _ruled(preset="fast").with_("ring", width=width)
    if back != 0.3e-3:
        case = case.with_("ring_pack", back_clearance=back)
    assert case.value("ring_pack", "groove_volume") == 0.0
    volume = _groove(48e-3, 3.5e-3, width, 40e-6, back)
    ruled, given = ringlube.run(case), ringlube.run(case.with_("ring_pack", groove_volume=volume))
    for name in ("energy_loss", "blowby", "ring_lift_share", "flutter_events"):
        assert getattr(ruled, name) == getattr(given, name), name
    assert (ruled.groove_pressure == given.groove_pressure).all()


def test_the_volumes_the_page_quotes():
    """docs/ring_pack.md quotes the groove of the study's widths (cm^3) with the default 0.3 mm
    back clearance."""
    quoted = {0.54e-3: 0.0892, 1.004e-3: 0.1280, 1.34e-3: 0.1560}
    for width, cm3 in quoted.items():
        assert round(_groove(48e-3, 3.5e-3, width, 40e-6, 0.3e-3) * 1e6, 4) == cm3


def test_impossible_grooves_are_refused_by_name():
    deep = _ruled().with_("ring", radial_depth=0.04).with_("ring_pack", back_clearance=0.01)
    root = "&ring_pack back_clearance: with the ring's radial_depth must be smaller than bore_radius"
    with pytest.raises(InputError, match=root):
        deep.validate()
    tiny = r"&ring_pack groove_volume: must be 0 \(from the groove\) or at least"
    with pytest.raises(InputError, match=tiny):
        _ruled().with_("ring_pack", groove_volume=1e-12).validate()
    deep.with_("ring_pack", groove_volume=1e-7).validate()  # a given volume needs no groove
