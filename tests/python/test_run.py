"""Python runs against the standalone program, HDF5 round trip, precision, parallel runs."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import h5py
import numpy as np
import pytest
from scipy.integrate import quad

import ringlube
from ringlube import _kernel
from ringlube.tables import INT_SERIES, SERIES

from conftest import COLD, DECKS

pytestmark = pytest.mark.numerics


@pytest.mark.parametrize("deck", DECKS, ids=lambda p: p.stem)
@pytest.mark.cli
def test_python_identical_to_cli(deck, solver, tmp_path):
    """Every series and every scalar (but the run time) bit for bit, by name."""
    out = tmp_path / "cli.h5"
    subprocess.run([solver, "-q", str(deck), "-o", str(out)], check=True)
    cli = ringlube.load(out)
    py = ringlube.run(deck)
    assert set(py.series) == set(cli.series) and set(py.scalars) == set(cli.scalars)
    assert set(py.series) >= {k for k, s in {**SERIES, **INT_SERIES}.items() if not s.requires}
    for name in py.series:
        np.testing.assert_array_equal(getattr(py, name), getattr(cli, name), err_msg=name)
    for name in py.scalars:
        if name != "run_time":
            assert getattr(py, name) == getattr(cli, name), name


def _layout(path):
    """Everything of a file but the run time: names, dtypes, shapes, values, attributes."""

    def attrs(obj):
        return {
            k: (np.asarray(v).dtype.kind, np.asarray(v).tolist())
            for k, v in obj.attrs.items()
            if k != "run_time_s" and k not in ("DIMENSION_LIST", "REFERENCE_LIST")
        }

    with h5py.File(path) as f:
        items = {}
        f.visititems(
            lambda name, obj: items.__setitem__(
                name,
                (
                    type(obj).__name__,
                    getattr(obj, "dtype", None) and obj.dtype.str,
                    getattr(obj, "shape", None),
                    attrs(obj),
                    obj[()].tolist() if isinstance(obj, h5py.Dataset) else None,
                ),
            )
        )
        return attrs(f), items


@pytest.mark.cli
def test_cli_and_python_write_identical_files(solver, tmp_path):
    """ringlube-solve and `ringlube run` (the kernel's writer through Python) give the same
    layout, attributes and values (not a subset), the run time and the file each was written
    to (`output.file`) aside."""
    from ringlube.cli import main

    deck = str(COLD)
    subprocess.run([solver, "-q", deck, "-o", str(tmp_path / "cli.h5")], check=True)
    assert main(["run", deck, "-o", str(tmp_path / "py.h5")]) == 0
    cli_root, cli_items = _layout(tmp_path / "cli.h5")
    py_root, py_items = _layout(tmp_path / "py.h5")
    # each records where it was written
    assert cli_root.pop("output.file")[1] == str(tmp_path / "cli.h5")
    assert py_root.pop("output.file")[1] == str(tmp_path / "py.h5")
    assert py_root == cli_root
    assert py_items == cli_items
    for key in ("deck", "deck_path", "pressure_file", "ringlube_version", "film_solves"):
        assert key in py_root, key
    assert py_root["deck"][1] == cli_root["deck"][1]
    text = COLD.read_text()
    deck_attr = py_root["deck"][1]
    deck_attr = deck_attr.decode() if isinstance(deck_attr, bytes) else deck_attr
    assert deck_attr.startswith(text)  # the deck's own text, then its calibration file


def test_results_are_double_precision():
    r = ringlube.run(ringlube.Case.from_namelist(COLD).with_numerics(nodes=41, dpsi_deg=2.0))
    assert r.h0.dtype == np.float64 and r.friction.dtype == np.float64
    # F5/2 through the wrapper agrees with scipy quadrature far beyond single precision
    lam = np.array([0.3, 1.234, 2.5, 4.0])
    f2, f52 = _kernel.rl_greenwood_tripp(lam, 0)
    assert f52.dtype == np.float64
    for lv, fv in zip(lam, f52):
        ref = quad(lambda s, lv=lv: (s - lv) ** 2.5 * np.exp(-s * s / 2), lv, np.inf, epsabs=0, epsrel=1e-13)[
            0
        ] / np.sqrt(2 * np.pi)
        assert abs(fv - ref) <= 1e-9 * ref


def test_hdf5_round_trip(quick_case, tmp_path):
    r = ringlube.run(quick_case, output=tmp_path / "py.h5")
    path = r.path
    assert path == tmp_path / "py.h5"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["py.h5"]
    back = ringlube.load(path)
    assert set(back.series) == set(r.series) and set(back.scalars) == set(r.scalars)
    for name in r.series:
        np.testing.assert_array_equal(getattr(back, name), getattr(r, name))
    for name in r.scalars:
        assert getattr(back, name) == getattr(r, name), name
    assert back.deck == r.deck and "changed in Python" in r.deck


def test_run_many_equals_serial(quick_case):
    cases = [quick_case.with_ring(crown_offset=x) for x in (-40e-6, 0.0, 40e-6)]
    serial = [ringlube.run(c) for c in cases]
    parallel = ringlube.run_many(cases, workers=2, progress=False)
    assert len(parallel) == len(serial)
    for s, p in zip(serial, parallel):
        np.testing.assert_array_equal(s.h0, p.h0)
        assert s.energy_loss == p.energy_loss
    # the offsets really differ, so order is checked, not just equality of copies
    assert len({r.energy_loss for r in parallel}) == 3


def test_runs_from_several_threads_equal_serial(quick_case):
    """The kernel's case store is module state: the f2py layer holds the GIL for the whole of
    each call, so runs from several Python threads take turns and give the serial answers
    (opening, running and closing handles in between)."""
    from concurrent.futures import ThreadPoolExecutor

    cases = [quick_case.with_ring(crown_offset=x) for x in (-40e-6, -20e-6, 0.0, 20e-6, 40e-6, 30e-6)]
    serial = [ringlube.run(c).energy_loss for c in cases]
    with ThreadPoolExecutor(max_workers=4) as pool:
        threaded = list(pool.map(lambda c: ringlube.run(c).energy_loss, cases))
    assert threaded == serial and len(set(serial)) == len(serial)


def test_a_design_scales_the_trace_as_read(quick_case):
    """A design's pressure_scale multiplies the trace as read, as a deck with that value
    does: run_designs and run() give the same bits (the kernel rescaled the already scaled
    trace by new / old: the gas trace stored already scaled and re-scaled)."""
    from ringlube.solve import run_designs

    scales = (0.85, 1.0, 1.17)
    batch, ok, _ = run_designs(
        quick_case, ["operating:pressure_scale"], np.array(scales)[:, None], ["energy_loss"]
    )
    direct = [ringlube.run(quick_case.with_operating(pressure_scale=s)).energy_loss for s in scales]
    assert ok.all()
    np.testing.assert_array_equal(batch[:, 0], direct)


def test_repeated_runs_keep_no_state(quick_case):
    a = ringlube.run(quick_case)
    ringlube.run(quick_case.with_ring(width=1.3e-3, tension=20.0))
    b = ringlube.run(quick_case)
    np.testing.assert_array_equal(a.h0, b.h0)


def test_batch_returns_each_failure_message_without_rerunning(monkeypatch):
    """The batch call returns the kernel's message of each failed design (a failed design
    used to be run again, alone, to get its message)."""
    import ringlube.solve

    def no_rerun(*args, **kwargs):
        raise AssertionError("run() called again for a failed design")

    monkeypatch.setattr(ringlube.solve, "run", no_rerun)
    base = ringlube.Case.from_namelist(COLD).with_numerics(nodes=31, dpsi_deg=5.0)
    x = np.array([[1.0e-3, 8.0], [-1.0, 8.0], [1.0e-3, 1e9]])
    values, converged, errors = ringlube.run_designs(base, ["width", "tension"], x, ["energy_loss"])
    assert errors[0] is None and np.isfinite(values[0]).all()
    assert "&ring width" in errors[1] and "must be in" in errors[1]
    assert "&ring tension" in errors[2]
    assert np.isnan(values[1:]).all() and not converged[1:].any()


def test_friction_power_fmep_and_oil_per_hour(cold_case_starved):
    """The quoted results against the deck's own numbers: P = E n/120, FMEP = E / (pi r0^2
    2 r), oil [g/h] = V [mm^3] 1e-9 rho 1e3 (n/2 60)."""
    r, case = cold_case_starved
    n = case.value("operating", "speed_rpm")
    r0, crank = case.value("engine", "bore_radius"), case.value("engine", "crank_radius")
    assert r.friction_power == pytest.approx(r.energy_loss * n / 120, rel=1e-14)
    assert r.fmep == pytest.approx(r.energy_loss / (np.pi * r0**2 * 2 * crank) / 1e3, rel=1e-14)
    rho = case.value("lubricant", "oil_density")
    assert rho == 850.0
    assert r.oil_to_chamber > 0
    assert r.oil_to_chamber_rate == pytest.approx(r.oil_to_chamber * 1e-9 * rho * 1e3 * n / 2 * 60, rel=1e-14)
    assert r.flagged_steps == int(np.count_nonzero(r.flags))
    # the engine: FMEP x displacement x cycles per second is the friction power, and energy
    # per cycle x cycles per second x cylinders too (both 1e-14: a few roundings apart)
    four = ringlube.run(case.with_("engine", cylinders=4))
    assert four.energy_loss == r.energy_loss and four.fmep == r.fmep and four.fmep_bar == r.fmep / 100
    assert four.displacement == pytest.approx(4 * np.pi * r0**2 * 2 * crank * 1e3, rel=1e-14)
    cycles_per_second = n / 120
    assert four.fmep * 1e3 * four.displacement * 1e-3 * cycles_per_second == pytest.approx(
        four.engine_friction_power, rel=1e-14
    )
    assert four.energy_loss * cycles_per_second * 4 == pytest.approx(four.engine_friction_power, rel=1e-14)
    assert r.engine_friction_power == r.friction_power and "engine, top rings" not in r.summary()
    assert "engine, top rings" in four.summary() and "(4 cylinders, " in four.summary()
    # the oil density converts, nothing else
    heavy = ringlube.run(case.with_("lubricant", oil_density=900.0))
    assert heavy.energy_loss == r.energy_loss and heavy.oil_to_chamber == r.oil_to_chamber
    assert heavy.oil_to_chamber_rate == pytest.approx(r.oil_to_chamber_rate * 900 / 850, rel=1e-14)


@pytest.fixture(scope="module")
def cold_case_starved():
    case = ringlube.Case.from_namelist(COLD).with_physics(cavitation="jfo", inlet="starved")
    case = case.with_numerics(nodes=31, dpsi_deg=4.0)
    return ringlube.run(case), case


def test_oil_density_is_range_checked():
    with pytest.raises(ringlube.InputError, match=r"&lubricant oil_density: must be in"):
        ringlube.Case().with_("lubricant", oil_density=10.0).validate()


@pytest.mark.cli
def test_solve_and_ringlube_run_print_one_summary(solver, tmp_path):
    """ringlube-solve and `ringlube run` print the same summary (the kernel formats it),
    with units and the quoted results; only the run time differs."""
    cli = subprocess.run([solver, str(COLD), "-o", str(tmp_path / "a.h5")], capture_output=True, text=True)
    py = subprocess.run(
        [str(Path(sys.executable).parent / "ringlube"), "run", str(COLD), "-o", str(tmp_path / "a.h5")],
        capture_output=True,
        text=True,
    )
    assert cli.returncode == py.returncode == 0, py.stderr

    def lines(text):
        return [line for line in text.splitlines() if "run time" not in line]

    assert lines(cli.stdout) == lines(py.stdout)
    for words in ("mean friction power", " W ", "FMEP", "kPa", "J", "um", "written"):
        assert words in cli.stdout, words
    # and CycleResult.summary() of the file is the same text without title and file
    assert lines(ringlube.load(tmp_path / "a.h5").summary()) == lines(py.stdout)[1:-1]


def test_result_repr_and_html(quick_case):
    r = ringlube.run(quick_case)
    text = repr(r)
    assert text.startswith("<CycleResult") and "energy loss per cycle" in text and "W" in text
    page = r._repr_html_()
    assert page.startswith("<table") and "energy_loss" in page and "<td>J</td>" in page


def test_compare_table_and_figure(quick_case):
    runs = [ringlube.run(quick_case), ringlube.run(quick_case.with_ring(width=1.2e-3))]
    t = ringlube.compare(runs, labels=["a", "b"])
    assert t.values["energy_loss"].tolist() == [runs[0].energy_loss, runs[1].energy_loss]
    assert t.units["friction_power"] == "W" and t.units["fmep"] == "kPa"
    assert "oil_to_chamber" not in t.names  # no starved run: no row of dashes
    md = t.to_markdown().splitlines()
    assert md[0] == "| quantity | a | b |" and md[2].startswith("| energy_loss [J] |")
    assert str(t).splitlines()[0].split() == ["quantity", "a", "b"]
    assert len(t.figure().axes) == 3
    with pytest.raises(ringlube.InputError, match="unknown results"):
        ringlube.compare(runs, names=["nope"])
    with pytest.raises(ringlube.InputError, match="2 results"):
        ringlube.compare(runs, labels=["a"])


def test_summary_advice_when_not_periodic_depends_on_max_cycles(quick_case):
    """A run that found no period is told to try a larger max_cycles, unless it already ran
    the most max_cycles allows (1000): then the advice is a looser cycle_tol (a review found
    'try a larger max_cycles' printed after 1000 cycles)."""
    r = ringlube.run(quick_case)
    r.scalars.update(periodic=0.0, converged=0.0, period=0.0, cycles_run=10.0)
    assert "try a larger max_cycles" in r.summary()
    r.scalars["cycles_run"] = 1000.0
    text = r.summary()
    assert "in 1000 cycles, the most max_cycles allows: loosen cycle_tol" in text
    assert "try a larger max_cycles" not in text
