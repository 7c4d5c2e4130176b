"""Plots and the ringlube command."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
import pytest

import ringlube
from ringlube.cli import main
from ringlube.plot import film_figure, friction_figure, plot_results

from conftest import COLD

pytestmark = [pytest.mark.cli, pytest.mark.io]


@pytest.fixture(autouse=True)
def _close_figures():
    """The figure builders return open pyplot figures; close them after each test."""
    yield
    plt.close("all")


def test_plot_files_and_data(quick_case, tmp_path):
    a = ringlube.run(quick_case.with_ring(crown_offset=60e-6))
    a.label = "offset +60 um"
    b = ringlube.run(quick_case.with_ring(crown_offset=-60e-6))
    b.label = "offset -60 um"
    files = plot_results([a, b], tmp_path)
    assert {f.suffix for f in files} == {".png", ".pdf"} and len(files) == 6
    for f in files:
        assert f.stat().st_size > 1000
    fig = friction_figure([a, b])
    lines = fig.axes[0].lines
    np.testing.assert_array_equal(lines[0].get_xdata(), a.crank_angle_deg)
    np.testing.assert_array_equal(lines[0].get_ydata(), a.friction)
    np.testing.assert_array_equal(lines[1].get_ydata(), a.viscous_friction)
    np.testing.assert_array_equal(lines[2].get_ydata(), a.boundary_friction)
    np.testing.assert_array_equal(lines[3].get_ydata(), b.friction)
    fig = film_figure([a])
    np.testing.assert_allclose(fig.axes[0].lines[0].get_ydata(), a.lambda_min * a.sigma * 1e6, rtol=1e-15)


def test_cli_run_and_plot(tmp_path, capsys):
    deck = tmp_path / "q.nml"
    ringlube.Case.from_namelist(COLD).with_numerics(nodes=41, dpsi_deg=2.0).to_namelist(deck)
    out = tmp_path / "r.h5"
    assert main(["run", str(deck), "-o", str(out)]) == 0
    assert "energy loss" in capsys.readouterr().out
    assert main(["plot", str(out), "-o", str(tmp_path / "plots")]) == 0
    assert (tmp_path / "plots" / "r_friction.png").stat().st_size > 1000
    assert (tmp_path / "plots" / "r_gas.png").stat().st_size > 1000  # the gas pressure


def test_figures_state_sign_and_time(quick_case, tmp_path):
    """The friction plot states its sign convention, the liner film plot when in the
    cycle the film is taken, and the gas figure of a result draws the pressure it ran with."""
    from ringlube.plot import _gas_of_results, liner_figure

    r = ringlube.run(quick_case.with_operating(pressure_scale=1.1))
    fig = friction_figure([r])
    assert "positive towards the crankcase" in fig.axes[0].get_title()
    gas = _gas_of_results([r]).axes[0].lines[0]
    np.testing.assert_array_equal(gas.get_xdata(), r.crank_angle_deg)
    np.testing.assert_array_equal(gas.get_ydata(), r.gas_pressure / 1e5)
    starved = ringlube.run(quick_case.with_physics(cavitation="jfo", inlet="starved"))
    assert "720 deg" in liner_figure([starved]).axes[0].get_title()


def test_cli_bad_input_exit_code(tmp_path, capsys):
    deck = tmp_path / "bad.nml"
    deck.write_text("&numerics nodes = 2.5 /\n")
    assert main(["run", str(deck)]) == 2
    assert "&numerics nodes: malformed integer" in capsys.readouterr().err


def test_ring_pack_figure_gives_each_result_one_colour(quick_case):
    """Overlaid results keep their colour in every panel of the ring-pack figure (the lift and
    flow panels used to cycle colours on their own, so a result changed colour between
    panels; a review, 2026-11-26)."""
    from matplotlib.colors import to_hex

    from ringlube.plot import ring_pack_figure

    case = quick_case.with_physics(ring_pack="gas")
    results = [ringlube.run(case), ringlube.run(case.with_ring(tension=20.0))]
    results[0].label, results[1].label = "soft", "stiff"
    fig = ring_pack_figure(results)
    drawn = [[line for line in ax.lines if not line.get_label().startswith("_")] for ax in fig.axes]
    for lines in drawn:  # (the crank-angle marks are unlabelled)
        by_result = {}
        for line in lines:
            tag = line.get_label().split(" ")[0]
            by_result.setdefault(tag, set()).add(to_hex(line.get_color()))
        assert len(by_result) == 2 and all(len(c) == 1 for c in by_result.values()), by_result
    colours = [{to_hex(line.get_color()) for line in lines} for lines in drawn]
    assert colours[0] == colours[1] == colours[2] and len(colours[0]) == 2, colours
    plt.close(fig)
