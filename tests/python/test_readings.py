"""ringlube readings: the continuous trend measures, the calibrator, the command."""

from __future__ import annotations

import numpy as np
import pytest

import ringlube
from ringlube.calibrate.calibrator import Param, calibrate_inputs, start_design
from ringlube.readings import fit as rf, reading as rd, report as rr
from ringlube.trends import FAILED_MEASURE, TRENDS, trend_measures, trend_verdicts

pytestmark = pytest.mark.numerics

NAMES = [t.name for t in TRENDS]


def _sweeps(rng, shape: str) -> dict:
    """Random sweeps of every trend (no ties): 'random', 'rising' or 'falling' energies."""
    out = {}
    for t in TRENDS:
        name, (lo, hi) = t.name, t.range
        n = rd.SWEEP_POINTS[name] if rng.random() < 0.5 else 5
        e = 1.0 + rng.random(n)
        if shape == "rising":
            e = np.sort(e)
        elif shape == "falling":
            e = np.sort(e)[::-1]
        out[name] = (np.linspace(lo, hi, n), e)
    return out


def test_trend_measure_is_zero_exactly_when_the_verdict_holds():
    rng = np.random.default_rng(9)
    seen = {(n, v) for n in NAMES for v in (True, False)}
    for k in range(3000):
        sweeps = _sweeps(rng, ("random", "rising", "falling")[k % 3])
        verdicts = trend_verdicts(sweeps)
        measures = trend_measures(sweeps)
        for name in NAMES:
            m = measures[name]
            assert m >= 0.0
            assert (m == 0.0) == verdicts[name], (name, sweeps[name][1], m)
            seen.discard((name, verdicts[name]))
    assert not seen, f"some verdicts never occurred: {seen}"


def test_trend_measure_values_by_hand():
    x5 = np.linspace(0, 1, 5)
    # tension should rise: one fall of 0.5 over a mean energy of 2.5 -> 0.2
    m = trend_measures({"tension": (x5, [1.0, 2.0, 3.0, 2.5, 4.0])})["tension"]
    assert m == pytest.approx(0.5 / 2.5)
    # crown height should fall: two rises of 1, mean 2 -> 1
    m = trend_measures({"crown_height": (x5, [3.0, 1.0, 2.0, 1.5, 2.5])})["crown_height"]
    assert m == pytest.approx(2.0 / 2.0)
    # offset: negative end 3, positive end 1 -> (3 - 1) / 2
    assert trend_measures({"crown_offset": (x5[[0, -1]], [3.0, 1.0])})["crown_offset"] == pytest.approx(1.0)
    # width: monotonic rise, lowest interior 2 over lower end 1, mean 3 -> 1/3
    assert trend_measures({"width": (x5, [1.0, 2.0, 3.0, 4.0, 5.0])})["width"] == pytest.approx(1 / 3)
    # a failed point: the whole energy the wrong way, and the verdict says no
    bad = {n: (x5, [1.0, np.nan, 0.5, 0.4, 0.3]) for n in NAMES}
    assert set(trend_measures(bad).values()) == {FAILED_MEASURE}
    assert not any(rd._verdicts(bad).values())


def test_residuals_are_in_units_of_the_goal():
    t = {"energy_loss": 2.0, "mixed_share": 10.0}
    r = rd.residuals(2.0 * (1 - rd.GOAL["energy_loss"]), 10.0 + rd.GOAL["mixed_share"], {"width": 0.1}, t)
    np.testing.assert_allclose(r, [-1.0, 1.0, 0.1 / rd.GOAL["energy_loss"]])
    assert np.all(rd.residuals(float("nan"), 1.0, {"width": 0.0}, t) == rd.FAILED_RESIDUAL)


def test_calibrator_recovers_a_bounded_least_squares_minimum():
    """Three inputs, four residuals with a known zero at (0.2, 0.65, 0.9)."""
    u0 = np.array([0.2, 0.65, 0.9])

    def batch(U):
        d = U - u0
        return np.c_[d[:, 0] + 0.5 * d[:, 1], np.sinh(d[:, 1]), 2 * d[:, 2] + d[:, 0] ** 2, d.sum(1)]

    m = calibrate_inputs(batch, start=start_design(3), budget=60)
    assert np.max(np.abs(m.u - u0)) < 5e-3
    assert m.score < 1e-2


def test_calibrator_stops_at_a_bound_and_reports_the_outward_gradient():
    """The unconstrained minimum lies beyond u = 1: the fit ends there, the score falls outward."""

    def batch(U):
        return np.c_[U[:, 0] - 1.4, 3 * (U[:, 1] - 0.5)]

    m = calibrate_inputs(batch, start=start_design(2), budget=40)
    assert m.u[0] > 1 - rd.AT_BOUND and abs(m.u[1] - 0.5) < 5e-3
    assert m.grad[0] < 0  # d(score^2/2)/du < 0 at the upper bound: would fall beyond it


def _synthetic(truth: dict, t: dict):
    """A smooth stand-in for the kernel: Table 2 met exactly at ``truth``, every published trend
    present everywhere (interior width optimum near 1 mm)."""

    def run_batch(case, variables, x):
        col = {v.split(":")[1]: x[:, i] for i, v in enumerate(variables)}
        z = col["zeta_kappa_sigma"] / truth["zeta_kappa_sigma"]
        s = col["pressure_scale"] / truth["pressure_scale"]
        ring = (
            1.0
            + 0.01 * (col["tension"] - 8.0) / 18.0
            - 0.05 * (col["crown_height"] - 9.31e-6) / 7e-6
            + 0.02 * (col["crown_offset"] + 38.3e-6) / 121e-6
            + 0.3 * ((col["width"] - 1.004e-3) / 0.8e-3) ** 2
        )
        energy = t["energy_loss"] * z**0.3 * s**0.5 * ring
        mixed = t["mixed_share"] * s**2 * z**-0.5
        return np.c_[energy, mixed], np.ones(len(x), bool)

    return run_batch


def test_fit_reading_recovers_known_inputs(monkeypatch):
    truth = {"zeta_kappa_sigma": 0.05, "pressure_scale": 1.1}
    t = {"energy_loss": 1.92, "mixed_share": 8.47}
    monkeypatch.setattr(rd, "_run_batch", _synthetic(truth, t))
    ring = {"width": 1.004e-3, "crown_height": 9.31e-6, "crown_offset": -38.3e-6, "tension": 8.0}
    case = ringlube.Case({"ring": ring})
    row = rf.fit_reading(rd.Reading("JFO flooded", "lumped", "N/m"), case, case, t, budget=40)
    for p in row["params"]:
        assert abs(p.normalised(row["cold"].inputs[p.name]) - p.normalised(truth[p.name])) < 5e-3, p.name
    assert all(row["cold"].verdicts.values()) and not any(row["cold"].measures.values())
    assert row["min"].score < 0.05
    assert row["runs"] == (row["min"].nfev + 1) * (1 + sum(rd.SWEEP_POINTS.values()))


def test_select_readings():
    assert len(rd.select_readings(None)) == 20
    assert [r.id for r in rd.select_readings(["jfo-starved-trailing-gas/local/N"])] == [
        "jfo-starved-trailing-gas/local/N"
    ]
    assert len(rd.select_readings(["jfo*/lumped/*"])) == 8
    with pytest.raises(ringlube.InputError, match="matches no reading"):
        rd.select_readings(["no-such"])


def test_quick_smoke_run_of_one_reading(tmp_path, capsys):
    from ringlube.cli import main

    out = tmp_path / "readings.md"
    code = main(["readings", "--quick", "--readings", "swift-stieber/lumped/N/m", "--out", str(out)])
    assert code == 0
    text = out.read_text()
    assert "Quick mode" in text and "| 1 | swift-stieber/lumped/N/m |" in text
    assert "ringlube readings --readings swift-stieber/lumped/N/m --quick" in text
    assert "## Summary (computed)" in text and "Closest by score: **swift-stieber/lumped/N/m**" in text


def test_bad_reading_is_a_clear_error_and_writes_nothing(tmp_path, capsys):
    from ringlube.cli import main

    out = tmp_path / "readings.md"
    assert main(["readings", "--quick", "--readings", "nope", "--out", str(out)]) == 2
    assert "matches no reading" in capsys.readouterr().err
    assert not out.exists()
    assert main(["readings", "--quick", "--out", str(tmp_path / "missing" / "r.md")]) == 2


def test_bound_sides_give_the_outward_derivative():
    """A fit pressed against u = 1 (and one against u = 0): the outward derivative is negative."""

    def batch(U):
        return np.c_[U[:, 0] - 1.4, 3 * (U[:, 1] + 0.3)]

    m = calibrate_inputs(batch, start=start_design(2), budget=40)
    params = [Param("a", "x:a", 0.0, 1.0), Param("b", "x:b", 0.0, 1.0)]
    sides = rf._bound_sides({"params": params, "min": m})
    assert [(p.name, side) for p, side, _ in sides] == [("a", "upper"), ("b", "lower")]
    assert all(g < 0 for _, _, g in sides)


def test_a_bound_that_stops_the_fit_is_reported_and_relaxed(monkeypatch, tmp_path):
    """Synthetic truth beyond the upper zeta_kappa_sigma bound: the fit ends on the bound, the
    report says the score falls beyond it, and the relaxed re-fit finds the truth."""
    truth = {"zeta_kappa_sigma": 0.15, "pressure_scale": 1.0}
    t = {"energy_loss": 1.92, "mixed_share": 8.47}
    monkeypatch.setattr(rd, "_run_batch", _synthetic(truth, t))
    out = rf.calibrate_readings(
        rd.select_readings(["jfo/lumped/N/m"]), budget=40, workers=1, relax=1, progress=False
    )
    (row,), (relaxed,) = out["rows"], out["relaxed"]
    zks = [p for p in row["params"] if p.name == "zeta_kappa_sigma"][0]
    assert row["cold"].inputs["zeta_kappa_sigma"] > zks.hi - rd.AT_BOUND * (zks.hi - zks.lo)
    assert [(p.name, side) for p, side, g in rf._bound_sides(row) if g < 0] == [("zeta_kappa_sigma", "upper")]
    assert relaxed["cold"].inputs["zeta_kappa_sigma"] == pytest.approx(0.15, rel=0.02)
    assert relaxed["min"].score < 0.1 < row["min"].score
    text = rr.write_readings(out, tmp_path / "r.md", "test", 0.0).read_text()
    assert "| jfo/lumped/N/m | zeta_kappa_sigma | upper (0.1) |" in text and "| yes |" in text
    assert "Outside the physical range" in text
