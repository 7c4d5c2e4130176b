"""Branch risk: how close a run came to a change of state, as margins that are continuous in
the inputs and change sign where the state changes (docs/model.md, "Branch risk").

- ``lift_margin``: (F - W at h0_ceiling) / F, the least over the intake stroke; < 0 where the
  ring can be lifted off the liner. Swept with ``&operating pressure_scale`` across the
  intake stroke's threshold, where the decks read in N/m (``conftest.per_length``) sit.
- ``seal_margin`` ('trailing_gas'): the film's barrier against the trailing gas; > 0 where the
  face ends its decisions sealed, <= 0 blown. Swept with the crank step across the switch of
  the cold deck's expansion stroke (read in N/m) between the sealed and the blown face.
"""

from __future__ import annotations

import numpy as np
import pytest

import ringlube
from ringlube.tables import FLAGS, MARGINS

from conftest import COLD, per_length

pytestmark = pytest.mark.numerics

OUT = ["lift_margin", "liner_lift_share", "energy_loss", "lift_margin_angle"]
LOAD_TOL = 1e-3  # preset 'default'


@pytest.fixture(scope="module")
def starved():
    cold = per_length(COLD).inline_calibration()
    return cold.with_physics(cavitation="jfo", inlet="starved")


def test_lift_margin_is_continuous_and_changes_sign_where_the_ring_lifts_off(starved):
    # pressure_scale sets the chamber pressure on the intake stroke, and with it the load F
    # pressing the ring on the liner; the starved film at the ceiling carries the crankcase
    # pressure over the face (a face partly filled across its width), so the margin is
    # 1 - W / F with W fixed: linear in the scale (dm/ds = W p_intake / F^2, about 1)
    s = np.array([0.92, 0.925, 0.929, 0.931, 0.932, 0.9325, 0.9328, 0.933, 0.934, 0.937, 0.94])
    v, conv, errors = ringlube.run_designs(starved, ["operating:pressure_scale"], s[:, None], OUT)
    assert not any(errors)
    margin, lifted = v[:, 0], v[:, 1] > 0
    # the state changes inside the sweep
    assert lifted[0] and not lifted[-1]
    # the sign is the state wherever the margin is outside the balance's own tolerance (within
    # load_tol of the threshold a step at h0_ceiling is accepted as a root, unflagged)
    clear = np.abs(margin) > LOAD_TOL
    assert clear.sum() >= 6
    np.testing.assert_array_equal((margin < 0)[clear], lifted[clear])
    # no jump: the slope between neighbours stays within 15 % of its median, across the
    # threshold too (a film landing on another state at the ceiling would jump by ~4 %)
    slope = np.diff(margin) / np.diff(s)
    assert np.all(np.abs(slope / np.median(slope) - 1) < 0.15), slope
    assert 0.8 < np.median(slope) < 1.2, slope


def test_lift_margin_of_a_lifted_step_is_the_balance_residual_there(starved):
    # at a step held at h0_ceiling the step's margin is the balance's own -(W - F) / F there:
    # the run's, the least over the intake stroke, is at most that of every such step
    r = ringlube.run(starved)
    intake = r.crank_angle_deg <= 180.0
    held = (r.flags & FLAGS["h0_ceiling"]) != 0
    assert np.count_nonzero(intake & held) > 10
    assert r.lift_margin <= np.min(-r.load_residual[intake & held])
    # the deck read in N/m sits within 0.45 % of the threshold: warned of
    assert -0.0045 < r.lift_margin < 0
    assert "WARNING: lift-off margin" in r.summary()
    assert f"{MARGINS['lift_margin'].threshold:.3f}" in r.summary()
    # the margin's film solves on copies: one per step of the intake stroke not held at the
    # ceiling, none counted in the run's film solves
    assert r.margin_film_solves == np.count_nonzero(intake & ~held)


def test_seal_margin_changes_sign_with_the_crank_step_where_the_face_blows():
    # cold deck read in N/m, flooded 'trailing_gas': after firing TDC the face seals (energy 0.74-0.78 J)
    # at the larger steps and blows (0.43-0.44 J) at the smaller ones
    tg = per_length(COLD).with_physics(cavitation="jfo", cavity_pressure="trailing_gas")
    steps = np.array([2.0, 1.5, 1.25, 1.2, 1.0, 0.5])
    v, conv, errors = ringlube.run_designs(
        tg, ["numerics:dpsi_deg"], steps[:, None], ["seal_margin", "energy_loss", "seal_margin_angle"]
    )
    assert not any(errors) and conv.all()
    margin, energy = v[:, 0], v[:, 1]
    sealed = energy > 0.6
    assert sealed[0] and not sealed[-1]
    np.testing.assert_array_equal(margin > 0, sealed)
    # one switch, and both sides of it within the threshold of 0; the step that blows the face
    # is after firing TDC
    k = int(np.flatnonzero(np.diff(sealed.astype(int)))[0])
    assert np.count_nonzero(np.diff(sealed.astype(int))) == 1
    threshold = MARGINS["seal_margin"].threshold
    assert abs(margin[k]) < threshold and abs(margin[k + 1]) < threshold, margin
    assert 360.0 < v[k + 1, 2] < 400.0


def test_no_seal_margin_without_the_trailing_gas(quick_case):
    r = ringlube.run(quick_case.with_physics(cavitation="jfo"))
    with pytest.raises(AttributeError, match="cavity_pressure = 'trailing_gas'"):
        _ = r.seal_margin
    assert "seal margin" not in r.summary()


def test_convergence_shows_which_state_each_crank_step_took(monkeypatch, tmp_path, starved):
    # ringlube convergence: the reference's state in the header and each setting's state in
    # its row, so that a crank step on the other branch shows (runs faked: a lifted result at
    # 2 deg, one on the liner at every other setting)
    import ringlube.convergence as conv

    on = ringlube.run(ringlube.Case.from_namelist(COLD).with_numerics(preset="fast"))
    lifted = ringlube.run(starved.with_numerics(preset="fast"))
    assert on.liner_lift_share == 0 and lifted.liner_lift_share > 0
    monkeypatch.setattr(conv, "run", lambda case: lifted if case.value("numerics", "dpsi_deg") == 2.0 else on)
    reference, rows = conv.convergence_study(COLD, quick=True, repeats=1, progress=False)
    md = conv.write_report(str(COLD), reference, rows, tmp_path, "ringlube convergence")[0].read_text()
    assert f"The reference's state: on the liner (lift margin {on.lift_margin:+.4f})" in md
    row = next(line for line in md.splitlines() if "| dpsi_deg = 2.0 |" in line)
    assert f"| lifted {lifted.liner_lift_share:.3g} % (lift margin {lifted.lift_margin:+.4f} (!)) |" in row
    others = [line for line in md.splitlines() if "| dpsi_deg = 1.0 |" in line or "| nodes = 25 |" in line]
    assert len(others) == 2 and all("| on the liner (lift margin" in line for line in others)


def test_a_study_marks_designs_near_a_change_of_state():
    # the design marks (as a design that did not converge is marked) and the "How sure" table:
    # the designs below a threshold, or whose re-run at 'accurate' took the other sign
    from types import SimpleNamespace

    from ringlube.study.format import BRANCH_RISK, branch_risks
    from ringlube.study.report import branch_risk_lines

    study = SimpleNamespace(s=SimpleNamespace(outputs=["energy_loss", "lift_margin", "seal_margin"]))
    knee = np.array([1.0, -0.0037, 0.5])
    assert branch_risks(study, knee) == [f"{BRANCH_RISK} (lift_margin -0.0037, below 0.01)"]
    seal = f"{BRANCH_RISK} (seal_margin +0.0500, below 0.1)"
    assert branch_risks(study, np.array([1.0, 0.2, 0.05])) == [seal]
    assert branch_risks(study, np.array([1.0, 0.2, -0.2])) == []
    sure = SimpleNamespace(
        names=["knee", "min energy", "far"],
        nominal=np.array([knee, [1.0, 0.2, 0.05], [1.0, 0.2, -0.2]]),
        accurate=np.array([[1.0, 0.002, 0.5], [1.0, 0.2, 0.06], [1.0, 0.3, 0.3]]),
    )
    text = "\n".join(branch_risk_lines(study, [("cold", sure)]))
    assert "### Branch risk" in text and "threshold 0.01" in text and "threshold 0.1" in text
    assert MARGINS["lift_margin"].reason in text
    assert "| cold | knee | `lift_margin` | -0.0037 | +0.0020 | yes |" in text
    assert "| cold | min energy | `seal_margin` | +0.0500 | +0.0600 | no |" in text
    # far from its thresholds, but blown at the study's preset and sealed at 'accurate'
    assert "| cold | far | `seal_margin` | -0.2000 | +0.3000 | yes |" in text
    assert "| cold | far | `lift_margin`" not in text
