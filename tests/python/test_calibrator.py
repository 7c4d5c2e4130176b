"""The one calibrator of `ringlube calibrate` and `ringlube readings`, and the one table of the
published trends."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import OptimizeResult

from ringlube import calibrate as cal, trends
from ringlube.calibrate.calibrator import Param, calibrate_inputs, start_design
from ringlube.readings import reading as rd
from ringlube.validate import compute as vc

pytestmark = pytest.mark.unit

FIELDS = ("x", "u", "fun", "score", "nfev", "nit", "status", "message", "success", "active_mask")


def test_least_squares_returns_an_optimize_result():
    p = [Param("a", "g:a", 1.0, 3.0), Param("b", "g:b", 1e-3, 1e-1, log=True)]
    r = calibrate_inputs(lambda U: np.c_[U[:, 0] - 0.25, U[:, 1] - 0.5], p, start=start_design(2), budget=40)
    assert isinstance(r, OptimizeResult) and all(k in r for k in FIELDS + ("grad", "jac"))
    np.testing.assert_allclose(r.u, [0.25, 0.5], atol=1e-6)
    np.testing.assert_allclose(r.x, [1.5, 1e-2], rtol=1e-5)  # physical values
    assert r.success and r.status > 0 and r.score == pytest.approx(np.sqrt(np.sum(r.fun**2)))
    assert r.active_mask.tolist() == [0, 0]


def test_least_squares_budget_and_start_design_only():
    f = lambda U: np.c_[U[:, 0] - 0.3, U[:, 1] - 0.7]  # noqa: E731
    r = calibrate_inputs(f, start=start_design(2), budget=12)
    assert not r.success and r.status == 0 and r.message == "evaluation budget (12) spent"
    r = calibrate_inputs(f, start=start_design(2), budget=9)
    assert r.message == "start design only" and r.nit == 0 and r.nfev == 9 + 2  # + the gradient


def test_bracket_solves_each_target_on_its_input():
    """Residual 0 (first input) and 1 (second input), each increasing in its input."""
    p = [Param("z", "", 0.02, 0.10), Param("s", "", 0.8, 1.2)]
    g = lambda x: (x[0] * x[1] - 0.05, x[1] ** 2 - 1.05)  # noqa: E731
    r = calibrate_inputs(g, p, "bracket", nominal=1.0)
    assert isinstance(r, OptimizeResult) and all(k in r for k in FIELDS)
    assert r.within_bounds and r.status == 1 and r.success and r.nit == 12
    assert r.x[1] == pytest.approx(np.sqrt(1.05), abs=0.4 / 2**12)
    assert abs(r.fun[0]) < 1e-6


def test_bracket_ends_on_a_bound_when_a_target_is_out_of_reach():
    p = [Param("z", "", 0.0, 1.0), Param("s", "", 0.0, 1.0)]
    r = calibrate_inputs(lambda x: (x[0] - 2.0, x[1] - 0.5), p, "bracket")
    assert r.x[0] == 1.0 and r.active_mask.tolist() == [1, 0]
    assert not r.within_bounds and r.status == 2 and "bound" in r.message
    with pytest.raises(ValueError, match="unknown calibration method"):
        calibrate_inputs(lambda x: x, p, "nelder-mead")


def test_brent_solves_one_input_or_ends_on_a_bound():
    """One residual increasing in one input: its root (x^3 = 0.2 on [0, 1]: 0.2^(1/3)); a
    root outside the bounds ends on the bound, marked."""
    p = [Param("z", "", 0.0, 1.0)]
    r = calibrate_inputs(lambda x: (x[0] ** 3 - 0.2,), p, "brent", xtol=1e-12, rtol=1e-14)
    assert isinstance(r, OptimizeResult) and all(k in r for k in FIELDS)
    assert r.x[0] == pytest.approx(0.2 ** (1 / 3), abs=1e-11) and r.within_bounds and r.status == 1
    r = calibrate_inputs(lambda x: (x[0] - 2.0,), p, "brent")
    assert r.x[0] == 1.0 and r.active_mask.tolist() == [1] and not r.within_bounds and "bound" in r.message
    with pytest.raises(ValueError, match="'brent' fits one input, not 2"):
        calibrate_inputs(lambda x: x, [p[0], p[0]], "brent")


def test_calibrate_and_readings_fit_the_same_inputs_on_the_same_bounds():
    assert [(p.name, p.lo, p.hi) for p in cal.PARAMS] == [(k, *cal.BOUNDS[k]) for k in cal.BOUNDS]
    assert rd._params(rd.Reading("JFO flooded", "lumped", "N/m")) == cal.PARAMS


def test_one_table_of_trends():
    """validate and readings use the trends of ringlube.trends, nothing else."""
    assert vc.TRENDS is trends.TRENDS and vc.trend_verdicts is trends.trend_verdicts
    assert rd.RING == tuple(t.name for t in trends.TRENDS) == tuple(rd.SWEEP_POINTS)
    for t in trends.TRENDS:
        lo, hi = t.range
        assert lo < hi and t.says and t.points >= 2
    with pytest.raises(KeyError, match="no published trend"):
        trends.trend_measures({"colour": (np.arange(3.0), np.arange(3.0) + 1)})
    assert trends.trend_measures({"colour": ([0, 1], [1.0, np.nan])}) == {"colour": trends.FAILED_MEASURE}
