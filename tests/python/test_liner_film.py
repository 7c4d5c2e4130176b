"""The liner oil film of a starved run has no cell-aliasing spikes: the film the
ring lays over a stroke is smooth from cell to cell. Before the fix the strip an edge swept
in one crank step shared a cell with the next step's strip, and the two takes left
f (1 - f) of that cell's film: one isolated cell per step (176 in this run, 632 at 201
nodes and 0.25 deg)."""

from __future__ import annotations

import numpy as np
import pytest

import ringlube
from ringlube import Case

from conftest import COLD, INPUTS

pytestmark = pytest.mark.numerics

HOT = INPUTS / "crf450r_4000rpm_full_hot.nml"


def isolated_spikes(h: np.ndarray, rel: float = 0.1, floor: float = 0.02e-6) -> np.ndarray:
    """Indices of cells above (or below) both neighbours by more than ``rel`` of the larger
    neighbour plus ``floor`` [m]: a single-cell spike or dip.

    Examples
    --------
    >>> isolated_spikes(np.array([1.0, 1.0, 1.5, 1.0, 1.0, 0.5, 1.0]) * 1e-6)
    array([2, 5])
    """
    left, mid, right = h[:-2], h[1:-1], h[2:]
    margin = rel * np.maximum(left, right) + floor
    up = mid - np.maximum(left, right) > margin
    down = np.minimum(left, right) - mid > margin
    return np.nonzero(up | down)[0] + 1


@pytest.mark.parametrize("deck", [COLD, HOT], ids=["cold", "hot"])
def test_liner_film_has_no_single_cell_spikes(deck):
    case = (
        Case.from_namelist(deck)
        .with_physics(cavitation="jfo", inlet="starved")
        .with_numerics(nodes=101, dpsi_deg=1.0)
    )
    r = ringlube.run(case)
    h, z = r.liner["liner_oil_film"], r.liner["liner_position"]
    spikes = isolated_spikes(h)
    # allowed: the bank the leading edge leaves on one cell at each dead centre (2 per cycle)
    # and the first cell of the lower rings' film below the travel; nothing along the stroke
    half_width = 0.5 * case["ring", "width"]
    stroke = 2 * case["engine", "crank_radius"]
    inside = spikes[(z[spikes] > 2 * half_width) & (z[spikes] < stroke - 2 * half_width)]
    assert len(spikes) <= 3, (z[spikes] * 1e3, h[spikes] * 1e6)
    assert len(inside) == 0
