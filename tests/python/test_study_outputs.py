"""What a design study hands a person: figures, summary, report and Pareto CSV with units"""

from __future__ import annotations

import csv

import matplotlib.pyplot as plt
import numpy as np
import pytest

from ringlube import InputError
from ringlube.case import Case
from ringlube.executor import Executor
from ringlube.study import run_study
from ringlube.study.format import LIFTED_COLUMN
from ringlube.study.plots import Axis, Mark, TradeoffSeries, map_figure, tradeoff_figure
from ringlube.study.summary import summary
from ringlube.study.variables import OUTPUTS, display, output_units, variable_unit

from conftest import INPUTS

pytestmark = pytest.mark.io

COLD = INPUTS / "crf450r_4000rpm_full_cold.nml"
HOT = INPUTS / "crf450r_4000rpm_full_hot.nml"


@pytest.fixture(scope="module")
def study(tmp_path_factory):
    """Two cases, two variables, objectives without ring mass, a reference design."""
    d = tmp_path_factory.mktemp("study")
    deck = d / "o.nml"
    deck.write_text(f"""&study
  name = 'o', cases = '{COLD}', '{HOT}', labels = 'cold', 'hot'
  variables = 'width', 'crown_offset', lower = 0.8e-3, -40e-6, upper = 1.2e-3, 40e-6
  objectives = 'energy_loss', 'mixed_share'
  samples = 24, seed = 3, population = 16, generations = 6, repeats = 2
  reference = 1.004e-3, -38.3e-6
/
""")
    return run_study(deck, d / "out", executor=Executor(serial=True), progress=False), d / "out"


@pytest.mark.slow
def test_tradeoff_is_drawn_without_ring_mass_and_names_designs(study):
    st, out = study
    assert (out / "tradeoff_energy_loss_vs_mixed_share.png").stat().st_size > 1000
    assert not list(out.glob("tradeoff_*ring_mass*"))
    assert (out / "report.md").is_file()


def test_tradeoff_figure_plots_the_given_points():
    front = np.array([[8.0, 2.0], [9.0, 1.8], [10.0, 1.7]])
    fig = tradeoff_figure(
        [
            TradeoffSeries(
                "cold",
                front,
                [
                    ("knee", 9.1, 1.79, "chosen"),
                    ("min a", 8.0, 2.0, "chosen"),
                    ("min b", 8.0, 2.0, "chosen"),
                    ("reference", 8.5, 1.9, "reference"),
                ],
            )
        ],
        "mixed share [%]",
        "energy loss [J/cycle]",
    )
    ax = fig.axes[0]
    np.testing.assert_array_equal(ax.collections[0].get_offsets(), front)
    assert not ax.texts  # designs are named in the legend: no label can overlap another
    entries = [t.get_text() for t in ax.get_legend().get_texts()]
    assert entries[1:] == [f"cold: {n} (true model)" for n in ("knee", "min a", "min b", "reference")]
    markers = [c.get_paths()[0].vertices.tobytes() for c in ax.collections[1:]]
    assert len(set(markers)) == 4  # coincident designs stay apart by their markers
    fig.canvas.draw()
    legend = ax.get_legend().get_window_extent()
    assert legend.x0 >= ax.get_window_extent().x1  # outside: hides no point
    plt.close(fig)


def test_two_variable_map_is_one_panel_with_marked_designs():
    axes = [Axis("width [mm]", 1e3, 0.8e-3, 1.2e-3), Axis("crown offset [µm]", 1e6, -4e-5, 4e-5)]
    marks = [Mark("knee", np.array([1e-3, 0.0])), Mark("reference", np.array([1e-3, 1e-5]), "reference")]
    fig = map_figure("e (cold)", "e [J]", lambda x: x[:, 0] * 1e3 + x[:, 1] * 1e4, axes, marks)
    panels = [a for a in fig.axes if a.get_label() != "<colorbar>"]
    assert len(panels) == 1
    ax = panels[0]
    assert ax.get_xlabel() == "width [mm]" and ax.get_ylabel() == "crown offset [µm]"
    offsets = np.vstack([c.get_offsets() for c in ax.collections if type(c).__name__ == "PathCollection"])
    np.testing.assert_allclose(offsets, [[1.0, 0.0], [1.0, 10.0]])
    plt.close(fig)


def test_near_constant_field_says_so():
    axes = [Axis("a", 1.0, 0.0, 1.0), Axis("b", 1.0, 0.0, 1.0), Axis("c", 1.0, 0.0, 1.0)]
    fig = map_figure("m", "ring_mass [g]", lambda x: 7.45 + 1e-9 * x[:, 0], axes)
    text = " ".join(t.get_text() for a in fig.axes for t in a.texts)
    assert "constant to 1e-06" in text and "7.45" in text
    assert not any(a.get_label() == "<colorbar>" for a in fig.axes)
    plt.close(fig)
    # a field that varies along one variable only: one colour scale shared by every panel
    fig = map_figure("m", "ring_mass [g]", lambda x: 4 + 6 * x[:, 0] + 1e-4 * x[:, 1], axes)
    assert sum(a.get_label() == "<colorbar>" for a in fig.axes) == 1
    plt.close(fig)


def test_tension_label_follows_the_decks_unit():
    assert variable_unit(Case.from_namelist(COLD), "tension") == "N"  # the deck says N
    assert variable_unit(Case({"ring": {"tension": 10.0}}), "tension") == "N"  # kernel default
    assert variable_unit(Case({"ring": {"tension_unit": "N/m"}}), "tension") == "N/m"
    assert display("tension", "N", 8, 26) == ("tension [N]", 1.0)
    assert display("width", "m", 0.54e-3, 1.34e-3) == ("width [mm]", 1e3)
    assert display("crown_offset", "m", -54e-6, 67e-6) == ("crown offset [µm]", 1e6)


def test_summary_lines_carry_units(study):
    st, _ = study
    text = summary(st)
    units = output_units()
    for line in text.splitlines():
        if line.strip().startswith("surface"):
            name = line.split()[1]
            assert f" {units[name]} (" in line, line
        if line.strip().startswith(("min ", "knee", "reference")):
            assert "mm" in line and "µm" in line and " J" in line and " %" in line, line
    assert text.splitlines()[2].endswith(" s")  # run time in seconds on the runs line


def test_pareto_csv_has_units_and_the_front(study):
    st, out = study
    with open(out / "pareto_cold.csv") as fh:
        rows = list(csv.reader(fh))
    units = output_units()
    results = [f"{o} [{units[o]}] (surrogate)" for o in OUTPUTS]
    assert rows[0] == ["width [m]", "crown_offset [m]", *results, LIFTED_COLUMN]
    assert {r[-1] for r in rows[1:]} <= {"yes", "no"}
    values = np.array([r[:-1] for r in rows[1:]], float)
    front = st.cases["cold"].front
    np.testing.assert_array_equal(values[:, :2], front.x)
    np.testing.assert_array_equal(values[:, 2:4], front.f)  # energy_loss, mixed_share


def test_report_names_chosen_and_reference_designs(study):
    _, out = study
    text = (out / "report.md").read_text()
    for piece in (
        "| knee |",
        "| reference |",
        "| min energy_loss |",
        "width [mm]",
        "crown offset [µm]",
        "energy_loss [J]",
        "![tradeoff_energy_loss_vs_mixed_share](tradeoff_energy_loss_vs_mixed_share.png)",
    ):
        assert piece in text, piece


def test_how_sure_ranking_counts_strict_reorders_only():
    """The ranking of the designs "changes" only if two designs ranked strictly one way are
    ranked strictly the other way: with half the supply film no design puts oil in the chamber,
    and four zeros reorder nothing (before, their index order was reported as a new ranking)."""
    from ringlube.study.report import _order, _reordered

    assert not _reordered(np.array([0.3, 0.2, 0.4]), np.zeros(3))
    assert not _reordered(np.array([1.0, 1.0, 2.0]), np.array([3.0, 2.0, 4.0]))
    assert _reordered(np.array([0.3, 0.2, 0.4]), np.array([0.1, 0.2, 0.4]))
    assert _order(["a", "b", "c"], np.array([1.0, 0.0, 0.0])) == "b = c < a"


# --- a study never writes over its inputs, another study's outputs or stale ones ------------


def _deck(path, name, cases, extra=""):
    path.write_text(
        f"&study\n  name = '{name}', cases = {', '.join(repr(str(c)) for c in cases)}\n"
        "  variables = 'width', 'crown_offset', lower = 0.8e-3, -40e-6, upper = 1.2e-3, 40e-6\n"
        f"  samples = 24, seed = 5, population = 12, generations = 4, repeats = 2\n{extra}/\n"
    )
    return path


def test_a_study_refuses_to_write_over_the_files_it_reads(tmp_path):
    """A pressure trace named like a Pareto CSV, and a study deck named like the report, in the
    output folder: refused before any run, both files untouched."""
    import shutil

    shutil.copy(INPUTS / "calibration.nml", tmp_path)
    trace = tmp_path / "pareto_r4000.csv"
    shutil.copy(INPUTS / "pressure" / "crf450r_4000rpm_full.csv", trace)
    base = tmp_path / "r4000.nml"
    base.write_text(COLD.read_text().replace("pressure/crf450r_4000rpm_full.csv", "pareto_r4000.csv"))
    assert "pareto_r4000.csv" in base.read_text()
    before = trace.read_bytes()
    deck = _deck(tmp_path / "s.nml", "s", [base])
    with pytest.raises(InputError, match=r"pareto_r4000.csv: is an input"):
        run_study(deck, tmp_path, executor=Executor(serial=True), progress=False, figures=False)
    assert trace.read_bytes() == before and not (tmp_path / "s.h5").exists()

    report = _deck(tmp_path / "report.md", "t", [COLD])
    before = report.read_bytes()
    with pytest.raises(InputError, match=r"report.md: is an input"):
        run_study(report, tmp_path, executor=Executor(serial=True), progress=False, figures=False)
    assert report.read_bytes() == before and not (tmp_path / "t.h5").exists()


def test_a_second_study_in_the_same_folder_is_refused(study, tmp_path):
    import shutil

    _, out = study
    shared = tmp_path / "out"
    shutil.copytree(out, shared)
    before = (shared / "report.md").read_bytes()
    deck = _deck(tmp_path / "p.nml", "p", [COLD])
    with pytest.raises(InputError, match=r"holds the outputs of the study 'o'"):
        run_study(deck, shared, executor=Executor(serial=True), progress=False, figures=False)
    assert (shared / "report.md").read_bytes() == before and not (shared / "p.h5").exists()
    (shared / "o.h5").unlink()  # the report alone still tells whose outputs these are
    with pytest.raises(InputError, match=r"holds the outputs of the study 'o'"):
        run_study(deck, shared, executor=Executor(serial=True), progress=False, figures=False)


def test_a_resumed_study_leaves_no_stale_outputs(study, tmp_path):
    """Resumed without the scene (an edit of the study deck), the scene's Pareto CSV and
    figures of the earlier run are removed with the report rewritten."""
    import shutil

    _, out = study
    folder = tmp_path / "out"
    shutil.copytree(out, folder)
    o = (out.parent / "o.nml").read_text()
    deck = tmp_path / "o.nml"
    deck.write_text(o.replace("/\n", "  scene = .true.\n/\n"))
    run_study(deck, folder, executor=Executor(serial=True), progress=False)
    scene = ["pareto_scene.csv", "fit_scene.png", "fit_scene.pdf", "map_scene_energy_loss.png"]
    assert all((folder / f).is_file() for f in scene)
    deck.write_text(o)
    run_study(deck, folder, executor=Executor(serial=True), progress=False)
    assert not [f for f in scene if (folder / f).exists()]
    assert "scene" not in (folder / "report.md").read_text().split("## Cases")[1].split("##")[0]
    assert (folder / "fit_cold.png").is_file() and (folder / "pareto_hot.csv").is_file()
