"""The ring's face profile: &ring profile = 'edge' (the crown at the face edges), 'gauge'
(drops at a gauge length from the crown point, each side its own) and 'table' (a measured
profile from a CSV file).

'gauge' and 'table' are checked against 'edge' where they describe the same face, and
against independent answers where they do not (a drop at another gauge length is an edge
crown scaled by (b/2 / g)^2; an asymmetric barrel sampled into a table; the ring mass by
quadrature).
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import quad

import ringlube
from ringlube.errors import InputError

from conftest import COLD

#: the shipped deck sets crown_height, which 'gauge' and 'table' do not use (said once per run)
pytestmark = [pytest.mark.numerics, pytest.mark.filterwarnings("ignore::ringlube.UnusedInputWarning")]
NODES = 41
WIDTH, CROWN, OFFSET = 1.004e-3, 9.31e-6, -38.3e-6
SERIES = ("h0", "friction", "hydrodynamic_load", "asperity_load", "power_loss", "lambda_min")


@pytest.fixture(scope="module")
def base():
    return ringlube.Case.from_namelist(COLD).with_numerics(nodes=NODES, dpsi_deg=2.0)


@pytest.fixture(scope="module")
def edge(base):
    return ringlube.run(base)


def edge_drop(x, crown=CROWN, offset=OFFSET, width=WIDTH):
    """The edge crown c (x + x_s)^2 / (b/2)^2 with the kernel's operations (x * x, not a
    power: the same rounding)."""
    d = x + offset
    return crown * (d * d) / ((0.5 * width) * (0.5 * width))


def gauge_drop(x, g, top, bottom, offset=OFFSET):
    d = x + offset
    return np.where(d < 0, top, bottom) * (d * d) / (g * g)


def grid_points(n=NODES, width=WIDTH):
    """The film's nodes and their midpoints, from the top edge (xi) and from the face's
    centre (x), computed as the kernel computes them."""
    dx = width / (n - 1)
    xi = np.arange(n) * dx
    xi[-1] = width
    x = -0.5 * width + np.arange(n) * dx
    x[-1] = 0.5 * width
    return xi, 0.5 * (xi[:-1] + xi[1:]), x, 0.5 * (x[:-1] + x[1:])


def write_table(path, xi, s, header="x_m,S_m"):
    rows = [header] if header else []
    rows += [f"{float(a)!r},{float(b)!r}" for a, b in zip(xi, s)]
    path.write_text("\n".join(rows) + "\n")
    return path


def sampled_table(path, drop, crown_x=-OFFSET):
    """A table of `drop` (a function of x from the face's centre) at the film's nodes, their
    midpoints and the crown point, where it is 0."""
    xi_n, xi_m, x_n, x_m = grid_points()
    xi = np.concatenate([xi_n, xi_m, [0.5 * WIDTH + crown_x]])
    s = np.concatenate([drop(x_n), drop(x_m), [0.0]])
    order = np.argsort(xi)
    return write_table(path, xi[order], s[order])


def same_film(a, b, rtol):
    """Every series of a within rtol of b's, relative to the series' largest magnitude (the
    asperity load's far tail, 1e-17 N where it peaks at 10 N, is exponentially sensitive to
    the gap: its own relative round-off is larger, its share of the load is not)."""
    for name in SERIES:
        want = getattr(b, name)
        atol = rtol * np.max(np.abs(want))
        np.testing.assert_allclose(getattr(a, name), want, rtol=0, atol=atol, err_msg=name)
    assert a.energy_loss == pytest.approx(b.energy_loss, rel=rtol)
    assert a.mixed_share == pytest.approx(b.mixed_share, rel=rtol, abs=1e-12)


def mass_grams(area_s, case):
    """rho 2 pi (r0 - a/2) (a b - int S dx), in g."""
    r0 = case.value("engine", "bore_radius")
    a = case.value("ring", "radial_depth")
    rho = case.value("ring", "density")
    return rho * 2 * np.pi * (r0 - a / 2) * (a * WIDTH - area_s) * 1e3


def test_gauge_at_half_the_width_with_the_crown_as_drops_is_the_edge_crown(base, edge):
    # S = d (x + x_s)^2 / g^2 with d = c and g = b/2 is the same expression as the edge crown,
    # evaluated with the same operations: the film is the same to the last bit; the ring mass
    # comes from another closed form (the two sides' integrals), equal to round-off
    gauge = ringlube.run(
        base.with_ring(profile="gauge", gauge_length=WIDTH / 2, gauge_drop_top=CROWN, gauge_drop_bottom=CROWN)
    )
    same_film(gauge, edge, rtol=0)
    assert gauge.ring_mass == pytest.approx(edge.ring_mass, rel=1e-14)


def test_a_drop_at_another_gauge_length_is_the_edge_crown_scaled(base):
    # a parabola through the crown point with drop d at distance g has drop d (b/2 / g)^2 at
    # b/2 from it: the same face as the edge crown c = d (b/2 / g)^2 (round-off: the scaled
    # crown height is rounded, ~1e-16, and the film's solve amplifies that by its condition,
    # below 1e-12 on these runs)
    g, d = 0.35e-3, 4.0e-6
    gauge_case = base.with_ring(profile="gauge", gauge_length=g, gauge_drop_top=d, gauge_drop_bottom=d)
    gauge = ringlube.run(gauge_case)
    edge = ringlube.run(base.with_ring(crown_height=d * (WIDTH / 2 / g) ** 2))
    same_film(gauge, edge, rtol=1e-10)
    assert gauge.ring_mass == pytest.approx(edge.ring_mass, rel=1e-14)


def test_table_sampled_from_the_edge_parabola_is_the_edge_crown(base, edge, tmp_path):
    # The table holds the edge crown at the film's nodes and midpoints (and the crown point,
    # its lowest point, 0): linear interpolation returns a table point's value exactly, so
    # the film is the edge crown's to the last bit. The ring mass integrates the table's
    # linear interpolant: the trapezoidal rule on a parabola k x^2 errs by k D^3 / 6 per
    # interval of length D, which the test adds up independently.
    path = sampled_table(tmp_path / "edge.csv", edge_drop)
    table = ringlube.run(base.with_ring(profile="table", profile_file=str(path)))
    same_film(table, edge, rtol=0)
    xi = np.loadtxt(path, delimiter=",", skiprows=1)[:, 0]
    k = CROWN / (WIDTH / 2) ** 2
    excess = k * np.sum(np.diff(xi) ** 3) / 6  # trapezoidal area above the exact one [m^2]
    area_exact = CROWN / (WIDTH / 2) ** 2 * ((WIDTH / 2 - OFFSET) ** 3 + (WIDTH / 2 + OFFSET) ** 3) / 3
    assert table.ring_mass == pytest.approx(mass_grams(area_exact + excess, base), rel=1e-13)
    assert edge.ring_mass == pytest.approx(mass_grams(area_exact, base), rel=1e-13)
    assert table.ring_mass != edge.ring_mass  # the excess is resolved (about 1e-7 of the mass)


def test_an_asymmetric_barrel_sampled_into_a_table_is_the_gauge_profile(base, tmp_path):
    # two independent evaluations of one asymmetric face: the gauge formula, and the same
    # face sampled into a table at the film's points (exact there, see above)
    g, top, bottom = 0.4e-3, 3.0e-6, 7.5e-6
    gauge_case = base.with_ring(profile="gauge", gauge_length=g, gauge_drop_top=top, gauge_drop_bottom=bottom)
    gauge = ringlube.run(gauge_case)
    path = sampled_table(tmp_path / "barrel.csv", lambda x: gauge_drop(x, g, top, bottom))
    table = ringlube.run(base.with_ring(profile="table", profile_file=str(path)))
    same_film(table, gauge, rtol=0)
    # the ring mass of the gauge profile against quadrature of its two halves
    xc = -OFFSET
    area = sum(
        quad(lambda x: float(gauge_drop(x, g, top, bottom)), a, b, epsabs=0, epsrel=1e-13)[0]
        for a, b in ((-WIDTH / 2, xc), (xc, WIDTH / 2))
    )
    assert gauge.ring_mass == pytest.approx(mass_grams(area, base), rel=1e-13)
    # the asymmetry is seen: the mirrored barrel (drops swapped) is another ring
    mirrored = ringlube.run(gauge_case.with_ring(gauge_drop_top=bottom, gauge_drop_bottom=top))
    assert abs(mirrored.energy_loss / gauge.energy_loss - 1) > 1e-3


def test_a_table_is_shifted_to_its_lowest_point_and_may_name_its_units(base, tmp_path):
    # the same face in mm and um with a header naming them, lifted by 5 um (a profilometer's
    # arbitrary zero): h0 is the gap at the face's lowest point, so the film is unchanged
    path_m = sampled_table(tmp_path / "m.csv", edge_drop)
    xs = np.loadtxt(path_m, delimiter=",", skiprows=1)
    metres = ringlube.run(base.with_ring(profile="table", profile_file=str(path_m)))
    path_mm = write_table(tmp_path / "mm.csv", xs[:, 0] * 1e3, xs[:, 1] * 1e6 + 5.0, header="x [mm], S [um]")
    other = ringlube.run(base.with_ring(profile="table", profile_file=str(path_mm)))
    # (the values are rounded once more by the unit conversion and the shift: round-off)
    same_film(other, metres, rtol=1e-9)
    assert other.ring_mass == pytest.approx(metres.ring_mass, rel=1e-12)


def table_error(base, tmp_path, text):
    path = tmp_path / "face.csv"
    path.write_text(text)
    with pytest.raises(InputError) as e:
        ringlube.run(base.with_ring(profile="table", profile_file=str(path)))
    return str(e.value)


def test_table_mistakes_are_named(base, tmp_path):
    xi, _, x, _ = grid_points()
    mm = "\n".join(f"{float(a) * 1e3!r},{float(s)!r}" for a, s in zip(xi, edge_drop(x))) + "\n"
    msg = table_error(base, tmp_path, mm)
    assert "&ring profile_file" in msg and "looks like mm" in msg and "span the face" in msg
    um = "x_m,S_m\n" + "\n".join(f"{float(a)!r},{float(s) * 1e6!r}" for a, s in zip(xi, edge_drop(x))) + "\n"
    msg = table_error(base, tmp_path, um)
    assert "drops span" in msg and "e.g." in msg
    msg = table_error(base, tmp_path, "x_m,S_m\n0,0\n0.5e-3,1e-6\n0.4e-3,2e-6\n1.004e-3,3e-6\n")
    assert "line 4" in msg and "increase strictly" in msg
    msg = table_error(base, tmp_path, "x [in], S [um]\n0,0\n1,1\n")
    assert 'unknown unit "in"' in msg and "line 1" in msg
    msg = table_error(base, tmp_path, "0,0\n0.5e-3,nan\n1.004e-3,0\n")
    assert "line 2" in msg and "finite" in msg
    msg = table_error(base, tmp_path, "0,0\n0.5e-3,1e-6\n")  # short of the bottom edge
    assert "span the face" in msg
    with pytest.raises(InputError, match=r"&ring profile_file: .*must name"):
        ringlube.run(base.with_ring(profile="table"))
    with pytest.raises(InputError, match=r"&ring profile_file: .*profile file not found"):
        ringlube.run(base.with_ring(profile="table", profile_file=str(tmp_path / "none.csv")))


def test_a_profile_file_relative_to_the_deck(tmp_path):
    # a deck's profile_file is relative to the deck's folder, and its line is named in errors
    (tmp_path / "faces").mkdir()
    sampled_table(tmp_path / "faces" / "edge.csv", edge_drop)
    deck = tmp_path / "deck.nml"
    text = COLD.read_text().replace("&calibration file = 'calibration.nml' /", "")
    text = text.replace("pressure/", str(COLD.parent / "pressure") + "/")
    ring = "density = 7800,\n profile = 'table', profile_file = 'faces/edge.csv' /"
    deck.write_text(text.replace("density = 7800 /", ring))
    case = ringlube.Case.from_namelist(deck).with_numerics(nodes=NODES)
    assert ringlube.run(case).converged
    (tmp_path / "faces" / "edge.csv").write_text("0,0\n1,1\n")
    with pytest.raises(InputError, match=r"deck\.nml:\d+: &ring profile_file: .*span the face"):
        ringlube.Case.from_namelist(deck)


def test_profile_inputs_another_profile_uses_are_said(base):
    said = ringlube.UnusedInputWarning
    with pytest.warns(said, match=r":12: &ring crown_height is set, but &ring profile = 'gauge'"):
        ringlube.run(base.with_ring(profile="gauge"))
    with pytest.warns(said, match=r"&ring gauge_length is set, but &ring profile = 'edge'"):
        ringlube.run(base.with_ring(gauge_length=0.4e-3))


def test_the_source_rings_profile_defaults_are_named_for_the_profile_in_use():
    # a case of its own engine with profile = 'gauge' gets the source ring's barrel from the
    # gauge defaults, not from crown_height: the warning names those
    _, filled = ringlube.Case({"ring": {"width": 1.2e-3, "profile": "gauge"}}).source_engine_defaults()
    assert ("ring", "gauge_drop_top") in filled and ("ring", "crown_height") not in filled
    table = ringlube.Case({"ring": {"profile": "table", "profile_file": "f.csv"}})
    own, filled = table.source_engine_defaults()
    assert not any(name.startswith(("crown_height", "gauge")) for _, name in own + filled)
