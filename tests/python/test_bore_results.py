"""A distorted bore's results in Python: the sector series and the conformability per order
from the f2py layer equal ringlube-solve's and the HDF5 file's; the summary, the comparison
table, and the figures (made for a distorted result, refused for a round one)."""

from __future__ import annotations

import copy
import os
import subprocess
import sys

import h5py
import matplotlib.pyplot as plt
import numpy as np
import pytest

import ringlube
from ringlube import InputError
from ringlube.cli import main
from ringlube.tables import SECTORS

from conftest import COLD, INPUTS

pytestmark = [pytest.mark.numerics, pytest.mark.io]

HOT_GAS = INPUTS / "crf450r_4000rpm_full_hot_gas.nml"


def distorted(case: ringlube.Case, sectors: int = 8) -> ringlube.Case:
    """Orders 4 and 2 (given in that order) beyond their conformability limits, with the
    starved mass-conserving film (its faces open) at coarse numerics: about 0.3 s a run."""
    return (
        case.with_physics(bore="distorted", cavitation="jfo", inlet="starved")
        .with_("bore", order=[4, 2], amplitude=[10e-6, 12e-6], sectors=sectors)
        .with_numerics(preset="fast", nodes=21, dpsi_deg=4.0, max_cycles=3)
    )


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")


@pytest.fixture(scope="module")
def runs(tmp_path_factory, solver):
    """The distorted deck with the ring pack run by ringlube-solve and by ringlube.run (both
    writing their file; 3 cycles, not yet periodic: the numbers need not be converged to be
    compared)."""
    tmp = tmp_path_factory.mktemp("bore")
    deck = tmp / "distorted.nml"
    distorted(ringlube.Case.from_namelist(HOT_GAS)).to_namelist(deck)
    cli = subprocess.run([solver, str(deck), "-o", str(tmp / "cli.h5")], capture_output=True, text=True)
    py = ringlube.run(deck, output=tmp / "py.h5")
    # (3 cycles: not periodic yet, exit 3, written all the same)
    assert cli.returncode == (0 if py.converged else 3), cli.stderr
    return {"deck": deck, "tmp": tmp, "cli_file": tmp / "cli.h5", "cli_stdout": cli.stdout, "py": py}


@pytest.fixture(scope="module")
def round_result():
    return ringlube.run(ringlube.Case.from_namelist(COLD).with_numerics(preset="fast"))


@pytest.mark.cli
def test_a_distorted_deck_reads_in_python(runs):
    """A deck with the lists of &bore reads as a Case (its lists as lists: it was refused,
    'malformed value "4 2" (one value per variable)', so `ringlube run` could not run it)."""
    case = ringlube.Case.from_namelist(runs["deck"])
    assert case.get("bore", "order") == [4, 2] and case.get("bore", "amplitude") == [10e-6, 12e-6]
    assert case.value("bore", "order") == [4, 2]
    again = runs["tmp"] / "again.nml"
    case.with_ring(tension=9.0).to_namelist(again)
    assert ringlube.Case.from_namelist(again).get("bore", "amplitude") == [10e-6, 12e-6]
    with pytest.raises(InputError, match=r"&ring width: malformed value"):
        bad = runs["tmp"] / "bad.nml"
        bad.write_text(runs["deck"].read_text().replace("&ring", "&ring width = 1e-3, 2e-3,", 1))
        ringlube.Case.from_namelist(bad)


@pytest.mark.cli
def test_sector_series_and_orders_reach_python(runs):
    r = runs["py"]
    m = 8
    assert r.distorted
    assert set(r.sectors) == set(SECTORS) == {"sector_h0", "sector_load"}
    assert r.sector_h0.shape == r.sector_load.shape == (len(r.crank_angle_deg), m)
    np.testing.assert_array_equal(r.sector_angle_deg, 360.0 * np.arange(m) / m)
    assert list(r.conformability_by_order) == [4, 2]  # in the order the deck gives them
    assert r.conformability == max(r.conformability_by_order.values())
    # the ring's film is the smallest of the sectors' (docs/bore.md)
    np.testing.assert_array_equal(r.h0, r.sector_h0.min(axis=1))
    assert r.units("sector_h0") == "m" and r.units("sector_load") == "N/m"
    assert {"sector_h0", "sector_angle_deg", "conformability_by_order"} <= set(dir(r))


@pytest.mark.cli
def test_conformability_per_order_is_the_closed_form(runs):
    """A_k / (q C_k), q = p_e b (F_T / r0 for a tension read in N, the tension itself in N/m),
    C_k = r0^4 / (E I (k^2 - 1)^2), I = b d^3 / 12: the classical limit, computed here from the
    deck's values."""
    case = ringlube.Case.from_namelist(runs["deck"])
    b, d = case.value("ring", "width"), case.value("ring", "radial_depth")
    r0, e = case.value("engine", "bore_radius"), case.value("surface", "e_ring")
    unit = case.value("ring", "tension_unit")
    q = case.value("ring", "tension") / (r0 if unit == "N" else 1.0)
    expected = {
        k: a / (q * r0**4 / (e * b * d**3 / 12 * (k * k - 1) ** 2))
        for k, a in zip(case.value("bore", "order"), case.value("bore", "amplitude"))
    }
    got = runs["py"].conformability_by_order
    assert got.keys() == expected.keys()
    for k in expected:
        assert got[k] == pytest.approx(expected[k], rel=1e-12), k


@pytest.mark.cli
def test_python_run_equals_ringlube_solve(runs):
    """Every series, sector series, scalar (but the run time) and the conformability per
    order, bit for bit; and the same summary (the run time aside)."""
    cli, py = ringlube.load(runs["cli_file"]), runs["py"]
    assert set(py.series) == set(cli.series) and set(py.scalars) == set(cli.scalars)
    assert set(py.sectors) == set(cli.sectors) == set(SECTORS)
    for name in [*py.series, *py.sectors]:
        np.testing.assert_array_equal(getattr(py, name), getattr(cli, name), err_msg=name)
    for name in py.scalars:
        if name != "run_time":
            assert getattr(py, name) == getattr(cli, name), name
    assert py.conformability_by_order == cli.conformability_by_order
    assert list(cli.conformability_by_order) == [4, 2]

    def lines(text):
        return [line for line in text.splitlines() if "run time" not in line]

    assert "conformability" in runs["cli_stdout"]
    assert lines(py.summary()) == lines(runs["cli_stdout"])[1:-1]
    assert lines(cli.summary()) == lines(runs["cli_stdout"])[1:-1]


def test_two_threads_give_the_one_thread_answer_bit_for_bit():
    """`&numerics threads = 2` solves the sectors' films in two OpenMP threads: each film is
    solved from its own sector's state alone and the loads are gathered after the parallel
    loop in sector order, so every series, sector series and scalar (but the run time) is the
    one thread's bit for bit."""
    case = distorted(ringlube.Case.from_namelist(HOT_GAS))
    one = ringlube.run(case.with_numerics(threads=1))
    two = ringlube.run(case.with_numerics(threads=2))
    for name in [*one.series, *one.sectors]:
        np.testing.assert_array_equal(getattr(two, name), getattr(one, name), err_msg=name)
    for name in one.scalars:
        if name != "run_time":
            assert getattr(two, name) == getattr(one, name), name


@pytest.mark.parametrize(
    ("threads", "film"),
    [(3, {}), (9, {"cavitation": "swift_stieber", "inlet": "flooded"})],
    ids=["3 threads, starved", "9 threads, Swift-Stieber"],
)
def test_a_team_of_any_size_gives_the_one_thread_answer_bit_for_bit(threads, film):
    """With `threads` > 1 a crank step is one parallel region: thread 0 runs the step and hands
    each pass over the sectors (their inlets, films, the lift-off margin's copies, their
    friction and oil after the balance) to the team; each thread owns a range of the sectors
    and takes the next ranges' once its own are done. The answer is the one thread's bit for
    bit whatever the team's size: 3 threads on 8 sectors (ranges of 2, 3 and 3 sectors), and 9
    (more threads than sectors: a thread without a sector of its own, more threads than the
    machine's cores) with the flooded Swift-Stieber film (no film content or liner oil)."""
    case = distorted(ringlube.Case.from_namelist(HOT_GAS))
    if film:
        case = case.with_physics(**film)
    one = ringlube.run(case.with_numerics(threads=1))
    team = ringlube.run(case.with_numerics(threads=threads))
    for name in [*one.series, *one.sectors]:
        np.testing.assert_array_equal(getattr(team, name), getattr(one, name), err_msg=name)
    for name in one.scalars:
        if name != "run_time":
            assert getattr(team, name) == getattr(one, name), name


def test_the_package_lets_openmp_threads_wait_asleep():
    """Importing ringlube sets OMP_WAIT_POLICY=PASSIVE before the kernel's library loads:
    libgomp then reads it and its threads wait without spinning (GOMP_SPINCOUNT 0 in its own
    report, OMP_DISPLAY_ENV; 300000 with its default, 3e10 with ACTIVE); a value the user set
    is kept."""
    code = "import ringlube; ringlube.kernel_id()"
    for given, spin in ((None, "'0'"), ("ACTIVE", "'30000000000'")):
        env = {k: v for k, v in os.environ.items() if not k.startswith(("OMP_", "GOMP_"))}
        env["OMP_DISPLAY_ENV"] = "VERBOSE"
        if given:
            env["OMP_WAIT_POLICY"] = given
        out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True)
        assert out.returncode == 0, out.stderr
        assert f"GOMP_SPINCOUNT = {spin}" in out.stderr, out.stderr


@pytest.mark.cli
def test_python_results_equal_the_file(runs):
    """The arrays Python holds are the file's datasets and attributes (read with h5py)."""
    py = runs["py"]
    with h5py.File(runs["py"].path) as f:
        for short, spec in SECTORS.items():
            np.testing.assert_array_equal(f["cycle"][spec.stored][()], getattr(py, short), err_msg=short)
        np.testing.assert_array_equal(f["cycle/face_flow_kg_s"][()], py.face_flow)
        stored = {int(k[15:]): float(v) for k, v in f.attrs.items() if k.startswith("conformability_")}
        for name in ("conformability", "light_gap_share_pct", "face_leakage_mg_per_cycle"):
            assert f.attrs[name] == py.scalars[name.replace("_pct", "").replace("_mg_per_cycle", "")]
    assert stored == py.conformability_by_order
    back = ringlube.load(py.path)
    for name in SECTORS:
        np.testing.assert_array_equal(getattr(back, name), getattr(py, name))
    assert list(back.conformability_by_order.items()) == list(py.conformability_by_order.items())


@pytest.mark.cli
def test_summary_lists_every_order(runs):
    """The summary's conformability line gives each order, separated by ', ' (it read
    'k=4: 25.71,k=2: 1.85': the blank after the comma was trimmed)."""
    r = runs["py"]
    line = next(t for t in r.summary().splitlines() if t.strip().startswith("conformability"))
    c = r.conformability_by_order
    assert f"(k=4: {c[4]:.2f}, k=2: {c[2]:.2f}; > 1 does not conform dry)" in line
    page = r._repr_html_()
    assert "conformability_4" in page and "conformability_2" in page


def test_round_result_has_no_sectors(round_result):
    r = round_result
    assert not r.distorted and r.sectors == {}
    for name in ("sector_h0", "sector_load", "sector_angle_deg", "conformability_by_order", "face_leakage"):
        with pytest.raises(AttributeError, match=r"needs &physics bore = 'distorted'"):
            getattr(r, name)
    assert "conformability" not in r.summary()


@pytest.mark.cli
def test_compare_includes_the_distorted_bore(runs, round_result):
    t = ringlube.compare([runs["py"], round_result], labels=["distorted", "round"])
    for name in ("face_leakage", "light_gap_share", "conformability", "blowby"):
        assert name in t.names, name
    assert t.values["face_leakage"][0] == runs["py"].face_leakage and np.isnan(t.values["face_leakage"][1])
    assert t.names.index("blowby") < t.names.index("face_leakage")
    assert "face_leakage" not in ringlube.compare([round_result]).names


@pytest.mark.cli
def test_bore_figures_of_a_distorted_result(runs, tmp_path):
    from ringlube.plot_bore import POLAR_ANGLES, bore_map_figure, bore_polar_figure, face_flow_figure

    r = runs["py"]
    fig = bore_polar_figure([r])
    polar = [ax for ax in fig.axes if ax.name == "polar" and ax.get_visible()]
    assert len(polar) == len(POLAR_ANGLES) == 7
    # each panel's dots are the sectors' h0 at the crank step nearest its angle
    for ax, angle in zip(polar, POLAR_ANGLES):
        k = int(np.argmin(np.abs((r.crank_angle_deg - angle + 360) % 720 - 360)))
        np.testing.assert_array_equal(ax.lines[1].get_ydata(), r.sector_h0[k] * 1e6)
        np.testing.assert_array_equal(ax.lines[1].get_xdata(), np.deg2rad(r.sector_angle_deg))
        assert ax.get_title().startswith(f"{angle:g} deg")
    assert bore_polar_figure([r], angles=[380]).axes[0].get_title().startswith("380 deg: expansion")
    fig = bore_map_figure([r])
    np.testing.assert_array_equal(fig.axes[0].collections[0].get_array().reshape(8, -1), r.sector_h0.T * 1e6)
    assert fig.axes[0].collections[0].norm.__class__.__name__ == "LogNorm"
    fig = face_flow_figure([r])
    labels = [line.get_label() for line in fig.axes[0].lines]
    assert any("face" in x for x in labels) and any("top gap" in x for x in labels)
    assert any("blowby" in x for x in labels)
    np.testing.assert_array_equal(fig.axes[0].lines[0].get_ydata(), r.face_flow * 1e3)


def test_bore_figures_refuse_a_round_result(round_result):
    from ringlube.plot_bore import bore_map_figure, bore_polar_figure, face_flow_figure

    for make in (bore_polar_figure, bore_map_figure, face_flow_figure):
        with pytest.raises(InputError, match=r"has a round bore \(no sectors\).*bore = 'distorted'"):
            make([round_result])


@pytest.mark.cli
@pytest.mark.slow
def test_ringlube_plot_draws_the_bore(runs, round_result, tmp_path, capsys):
    from ringlube.plot import plot_results

    cli = str(runs["cli_file"])
    assert main(["plot", cli, "-o", str(tmp_path / "a"), "--angles", "0,380"]) == 0
    for kind in ("bore_polar", "bore_map", "bore_flow", "ring_pack", "friction"):
        for fmt in ("png", "pdf"):
            assert (tmp_path / "a" / f"cli_{kind}.{fmt}").stat().st_size > 1000, kind
    # a round result beside it: its figures as before, the bore's of the distorted one only
    rnd = copy.copy(round_result)
    rnd.label = "round"
    files = plot_results([runs["py"], rnd], tmp_path / "b", formats=("png",), angles=[90])
    assert [f.name for f in files if "bore" in f.name] == [
        f"distorted_vs_round_{kind}.png" for kind in ("bore_polar", "bore_map", "bore_flow")
    ]
    assert not [f for f in plot_results([rnd], tmp_path / "c", formats=("png",)) if "bore" in f.name]
    capsys.readouterr()
    rnd = tmp_path / "round.h5"
    ringlube.run(ringlube.Case.from_namelist(COLD).with_numerics(preset="fast"), output=rnd)
    assert main(["plot", str(rnd), "-o", str(tmp_path / "d"), "--angles", "0,90"]) == 2
    err = capsys.readouterr().err
    assert "--angles: no result has a distorted bore" in err and len(err.splitlines()) == 1
    assert not (tmp_path / "d").exists()
    assert main(["plot", cli, "-o", str(tmp_path / "e"), "--angles", "0,800"]) == 2
    assert "800 deg is outside the cycle" in capsys.readouterr().err


@pytest.mark.cli
def test_convergence_tables_add_the_distorted_bore(runs, round_result, monkeypatch, tmp_path):
    """`ringlube convergence` of a distorted deck adds its face leakage, light gaps and
    conformability (and the ring pack's blowby, lift and flutter) with their errors against the reference; the
    runs here are the distorted result with the face leakage and light gaps moved by the
    nodes (known errors), the kernel's ladder logic unchanged."""
    import csv

    import ringlube.convergence as conv

    base = runs["py"]

    def run(case):
        n = case.value("numerics", "nodes")
        r = copy.copy(base)
        r.scalars = {
            **base.scalars,
            "face_leakage": base.face_leakage * (1 + 1 / n),
            "light_gap_share": base.light_gap_share + 100 / n,
        }
        return r

    monkeypatch.setattr(conv, "run", run)
    reference, rows = conv.convergence_study(runs["deck"], quick=True, repeats=1, progress=False)
    ring_pack = ["blowby", "ring_lift_share", "flutter_events"]
    assert list(reference["extra"]) == [*ring_pack, "face_leakage", "light_gap_share", "conformability"]
    row = next(r for r in rows if r.setting.label == "nodes = 25")
    ref_n = conv.REFERENCE["nodes"]
    value, err = row.extra["face_leakage"]
    assert value == base.face_leakage * (1 + 1 / 25)
    assert err == pytest.approx((1 / 25 - 1 / ref_n) / (1 + 1 / ref_n), rel=1e-12)
    assert row.extra["light_gap_share"][1] == pytest.approx(100 / 25 - 100 / ref_n, rel=1e-12)
    assert row.extra["conformability"] == (base.conformability, 0.0)
    files = conv.write_report(str(runs["deck"]), reference, rows, tmp_path, "ringlube convergence x")
    md = files[0].read_text()
    assert "| face_leakage [mg] | err face_leakage | light_gap_share [%] | err light_gap_share (pts) |" in md
    assert "Reference conformability:" in md and "the same at every setting" in md
    with open(files[1]) as fh:
        table = list(csv.DictReader(fh))
    assert float(table[0]["err_face_leakage"]) == rows[0].extra["face_leakage"][1]
    for column in ("blowby_L_per_min", "face_leakage_mg", "light_gap_share_pct", "conformability"):
        assert column in table[0], column
    assert "err_light_gap_share_pts" in table[0]
    # a round deck's tables as before: none of these columns
    monkeypatch.setattr(conv, "run", lambda case: round_result)
    reference, rows = conv.convergence_study(COLD, quick=True, repeats=1, progress=False)
    md = conv.write_report(str(COLD), reference, rows, tmp_path / "round", "x")[0].read_text()
    assert reference["extra"] == {} and "face_leakage" not in md and "blowby" not in md


@pytest.mark.cli
@pytest.mark.slow
def test_study_draws_the_knee_of_a_distorted_case(runs, tmp_path, monkeypatch):
    """A study's figures of a case with a distorted bore: its chosen knee re-run with the true
    model (the design's values set), drawn as bore_LABEL_polar, _map and _flow; none for a
    round case. (The study is reduced to what the figures read.)"""
    from types import SimpleNamespace

    import ringlube.plot_bore as pb
    from ringlube.study.figures import bore_figures
    from ringlube.study.report import output_names

    drawn = []
    map_figure = pb.bore_map_figure
    monkeypatch.setattr(pb, "bore_map_figure", lambda rs: drawn.append(rs[0]) or map_figure(rs))
    knee = np.array([1.2e-3, 12.0])
    chosen = SimpleNamespace(names=["min energy_loss", "knee"], x=np.array([[1.0e-3, 8.0], knee]))
    s = SimpleNamespace(
        labels=["bent", "round"],
        cases=[str(runs["deck"]), str(COLD)],
        groups_names=[("ring", "width"), ("ring", "tension")],
    )
    cases = {"bent": SimpleNamespace(chosen=chosen), "round": SimpleNamespace(chosen=chosen)}
    files = bore_figures(SimpleNamespace(s=s, cases=cases), tmp_path)
    assert sorted(f.name for f in files) == sorted(
        f"bore_bent_{kind}.{fmt}" for kind in ("polar", "map", "flow") for fmt in ("png", "pdf")
    )
    names = output_names(SimpleNamespace(labels=["bent", "round"], objectives=["energy_loss"]))
    assert {f.name for f in files} <= set(names) and "bore_round_map.png" in names
    # the figures are of the knee: the run made here of the same design
    r = ringlube.run(ringlube.Case.from_namelist(runs["deck"]).with_ring(width=knee[0], tension=knee[1]))
    assert len(drawn) == 1 and drawn[0].label.startswith("bent knee")
    np.testing.assert_array_equal(drawn[0].sector_h0, r.sector_h0)
    assert not np.array_equal(r.sector_h0, runs["py"].sector_h0)  # (not the deck's own design)


@pytest.mark.cli
def test_sector_jumps_counts_the_crank_steps_at_which_a_sector_jumps(runs):
    """`sector_jumps`: the crank steps of the cycle at which some sector's h0 changed by more
    than a factor e^0.2 from the step before relative to the ring's (the sectors' geometric
    mean; docs/bore.md, "Two states of a light sector"), counted here from the sector series
    themselves; the file and the summary carry it."""
    r = runs["py"]
    rel = np.log(r.sector_h0 / np.exp(np.log(r.sector_h0).mean(axis=1))[:, None])
    expected = int(np.count_nonzero(np.abs(np.diff(rel, axis=0)).max(axis=1) > 0.2))
    assert expected > 0  # (this ring's faces open and close: the count is not trivially 0)
    assert r.sector_jumps == expected
    with h5py.File(runs["cli_file"]) as f:
        assert f.attrs["sector_jumps"] == expected
    lines = [line.split() for line in runs["cli_stdout"].splitlines()]
    assert ["sector", "jumps", f"{expected:.1f}"] in [line[:3] for line in lines]
