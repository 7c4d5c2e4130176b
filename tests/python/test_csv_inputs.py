"""The kernel's two-column CSV inputs, the pressure trace and the face profile, are read by
one reader (ringlube_csv): a bad row in either names the file, the line (blank lines,
comments and a header counted, Windows line ends dropped) and the row's text; a file with
fewer than two rows, or none at all, says which kind of file it is. The bore's distortion
reader takes the same line, header and number rules (with its own message form)."""

from __future__ import annotations

import pytest

import ringlube
from ringlube import gas
from ringlube.errors import InputError

from conftest import COLD

pytestmark = [pytest.mark.unit, pytest.mark.io]

# a header, a comment and a blank line before the first row: the fifth line is the second row
HEAD_P = "crank_deg,p_Pa\r\n# measured\r\n\r\n0,1e5\r\n"
HEAD_S = "x_m,S_m\r\n# measured\r\n\r\n0,0\r\n"


@pytest.fixture(scope="module")
def base():
    return ringlube.Case.from_namelist(COLD).with_numerics(nodes=41, dpsi_deg=2.0)


def pressure_error(tmp_path, text):
    path = tmp_path / "trace.csv"
    path.write_bytes(text.encode())
    with pytest.raises(InputError) as e:
        gas.read_csv(path)
    return str(path), str(e.value)


def profile_error(base, tmp_path, text):
    path = tmp_path / "face.csv"
    path.write_bytes(text.encode())
    with pytest.raises(InputError) as e:
        ringlube.run(base.with_ring(profile="table", profile_file=str(path)))
    return str(path), str(e.value)


@pytest.mark.parametrize(
    ("row", "why"),
    [
        ("0.5e-3;1e-6", 'expected "x, S" (two numbers: position from the top edge, drop)'),
        ("0.5e-3,1e-6,2", 'expected "x, S" (two numbers: position from the top edge, drop)'),
        ("0.5e-3,inf", "not a finite number"),
        ("0,1e-6", "positions x must increase strictly"),
    ],
)
def test_a_bad_profile_row_names_the_file_and_line(base, tmp_path, row, why):
    path, msg = profile_error(base, tmp_path, HEAD_S + row + "\r\n1.004e-3,0\r\n")
    assert f'{path}: line 5: {why}: "{row}"' in msg


@pytest.mark.parametrize(
    ("row", "why"),
    [
        ("10;2e5", 'expected "crank angle deg, pressure Pa"'),
        ("10,2e5,3", 'expected "crank angle deg, pressure Pa"'),
        ("nan,2e5", "crank angle is not a finite number"),
        ("10,1e999", "pressure is not a finite number"),
        ("800,2e5", "crank angle outside [0, 720] deg"),
        ("10,-2e5", "pressure must be positive (absolute, Pa)"),
        ("0,2e5", "crank angles must increase strictly"),
    ],
)
def test_a_bad_pressure_row_names_the_file_and_line(tmp_path, row, why):
    path, msg = pressure_error(tmp_path, HEAD_P + row + "\r\n720,1e5\r\n")
    assert f'{path}: line 5: {why}: "{row}"' in msg


def test_a_profile_header_with_an_unknown_unit_is_its_line(base, tmp_path):
    path, msg = profile_error(base, tmp_path, "# x from the top edge\nx [in], S [um]\n0,0\n1,1\n")
    assert f'{path}: line 2: unknown unit "in" in the header (m, mm or um): "x [in], S [um]"' in msg


@pytest.mark.parametrize("text", ["", "x_m,S_m\n# none\n", "x_m,S_m\n0,0\n"])
def test_a_profile_of_fewer_than_two_rows_says_so(base, tmp_path, text):
    path, msg = profile_error(base, tmp_path, text)
    assert f"{path}: profile file needs at least two rows" in msg


@pytest.mark.parametrize("text", ["", "crank_deg,p_Pa\n# none\n", "0,1e5\n"])
def test_a_trace_of_fewer_than_two_rows_says_so(tmp_path, text):
    path, msg = pressure_error(tmp_path, text)
    assert f"{path}: pressure file needs at least two rows" in msg


def test_a_missing_file_is_named_with_its_kind(base, tmp_path):
    path = tmp_path / "none.csv"
    with pytest.raises(InputError, match="none.csv: pressure file not found"):
        gas.read_csv(path)
    with pytest.raises(InputError, match="none.csv: profile file not found"):
        ringlube.run(base.with_ring(profile="table", profile_file=str(path)))


@pytest.mark.parametrize(
    ("row", "why"),
    [
        ("0.01,2,nan,0", "amplitude is not a finite number"),
        ("0.01,2,1e-6", 'expected four fields "z_m, order, amplitude_m, phase_rad"'),
        ("0,2,1e-6,0", "the rows of order 2 must increase strictly in z"),
    ],
)
def test_the_distortion_file_takes_the_same_field_rules(base, tmp_path, row, why):
    # the bore's reader (its own message form, "<path>:<line>: <why>") shares the line,
    # header and number rules of the other two
    path = tmp_path / "bore.csv"
    path.write_bytes(f"z_m,order,amplitude_m,phase_rad\r\n# measured\r\n\r\n0,2,1e-6,0\r\n{row}\r\n".encode())
    case = base.with_physics(bore="distorted").with_bore(distortion_file=str(path), sectors=8)
    with pytest.raises(InputError) as e:
        ringlube.run(case)
    assert f"{path}:5: {why}" in str(e.value)


def test_a_profile_with_a_byte_order_mark_and_no_header_reads_as_without(base, tmp_path):
    # (spreadsheets write the mark; the pressure trace, the distortion file and the deck skip it)
    x = [0.0, 0.25e-3, 0.502e-3, 0.75e-3, 1.004e-3]
    rows = "".join(f"{xi!r},{9.31e-6 * ((xi - 0.502e-3) / 0.502e-3) ** 2!r}\n" for xi in x)
    energies = []
    for name, content in (("plain", rows.encode()), ("bom", b"\xef\xbb\xbf" + rows.encode())):
        path = tmp_path / f"{name}.csv"
        path.write_bytes(content)
        r = ringlube.run(base.with_ring(profile="table", profile_file=str(path)))
        energies.append(r.energy_loss)
    assert energies[1] == energies[0]
