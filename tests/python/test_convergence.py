"""Convergence of the whole cycle in the crank-angle step, and the numerics presets."""

from __future__ import annotations

import numpy as np
import pytest

import ringlube
from ringlube import Case, InputError

from conftest import COLD


def test_crank_step_convergence_order():
    """Energy loss against the crank step at tight tolerances: the differences between
    successive halvings shrink with an observed order between 1 (backward Euler) and 2."""
    base = Case.from_namelist(COLD).with_numerics(nodes=51, pressure_tol=1e-8, load_tol=1e-7)
    steps = (2.0, 1.0, 0.5, 0.25)
    energy = np.array([ringlube.run(base.with_numerics(dpsi_deg=d)).energy_loss for d in steps])
    diffs = np.abs(np.diff(energy))
    orders = np.log2(diffs[:-1] / diffs[1:])
    print(f"\nenergy {energy}, successive differences {diffs}, observed orders {orders}")
    assert np.all(diffs[1:] < diffs[:-1])
    assert np.all((orders > 0.8) & (orders < 2.5))


def test_presets_and_explicit_override():
    base = Case.from_namelist(COLD)
    assert base.with_numerics(preset="fast").validate() == 360           # 2 deg
    assert base.with_numerics(preset="accurate").validate() == 2880      # 0.25 deg
    assert base.with_numerics(preset="fast", dpsi_deg=1.0).validate() == 720
    with pytest.raises(InputError, match=r"&numerics preset: unknown preset 'turbo'"):
        base.with_numerics(preset="turbo").validate()
