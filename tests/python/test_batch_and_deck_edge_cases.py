"""Edge cases of the batch call and of deck reading (each reproduced before
its fix): data loss, interpreter crashes and wrong answers in the batch call, silent
name errors, quadratic deck reading, and misleading messages."""

from __future__ import annotations

import shutil
import subprocess
import time

import h5py
import numpy as np
import pytest

import ringlube
from ringlube import BatchError, Case, InputError

from conftest import COLD, INPUTS

pytestmark = [pytest.mark.unit, pytest.mark.io]

FAST = {"preset": "fast"}


@pytest.fixture()
def deck_dir(tmp_path):
    """A copy of the cold deck with its calibration file and trace."""
    shutil.copytree(INPUTS / "pressure", tmp_path / "pressure")
    shutil.copy(INPUTS / "calibration.nml", tmp_path / "calibration.nml")
    deck = tmp_path / "deck.nml"
    deck.write_text(COLD.read_text().replace("preset = 'default'", "preset = 'fast'"))
    return tmp_path


def test_python_never_overwrites_the_calibration_file(deck_dir):
    """F01: writing a result onto the deck's calibration file replaced it with HDF5."""
    cal = deck_dir / "calibration.nml"
    before = cal.read_bytes()
    with pytest.raises(InputError, match=r"calibration file .* refusing to overwrite an input"):
        ringlube.run(deck_dir / "deck.nml", output=cal)
    assert cal.read_bytes() == before


@pytest.mark.parametrize(
    "variables, x, match",
    [
        (["width"], np.array([1e-3, 1.2e-3]), "one row per design and one column per variable"),
        (["width", "tension"], np.array([[1e-3]]), "one column per variable"),
        (["width,tension"], np.array([[1e-3]]), "is not an input variable"),
        (["ring:width:x"], np.array([[1e-3]]), "is not an input variable"),
        (["operating:pressure_file"], np.array([[1.0]]), "is not a number"),
        (["width"], np.array([["1mm"]]), "designs must be numbers"),
    ],
    ids=["1d", "too_few_columns", "comma_name", "colon_name", "path", "string"],
)
def test_run_designs_refuses_bad_shapes_and_names(variables, x, match):
    """F02 (1-D x ended the interpreter), F03 (a missing column was silently dropped), F05,
    F13: one clear InputError each, and the interpreter lives on."""
    base = Case().with_numerics(**FAST)
    with pytest.raises(InputError, match=match):
        ringlube.run_designs(base, variables, x, ["energy_loss"])
    assert ringlube.run(base).converged


def test_run_designs_integer_and_pressure_scale_like_run():
    """F04 (pressure_scale was ignored by the batch) and F14 (integers refused)."""
    base = Case.from_namelist(COLD).with_numerics(**FAST)
    v, ok, err = ringlube.run_designs(
        base, ["operating:pressure_scale", "numerics:nodes"], np.array([[1.1, 41.0]]), ["energy_loss"]
    )
    direct = ringlube.run(base.with_operating(pressure_scale=1.1).with_numerics(nodes=41))
    assert err == [None] and v[0, 0] == direct.energy_loss
    v, ok, err = ringlube.run_designs(base, ["numerics:nodes"], np.array([[41.5]]), ["energy_loss"])
    assert "&numerics nodes" in err[0] and "integer" in err[0]


@pytest.mark.parametrize("name", ["width = 2e-3, tension", "a\nb", "wid th"])
def test_case_variable_names_are_checked(name):
    """F06: a name with '=' or a newline silently set other variables."""
    with pytest.raises(InputError, match="not a variable name"):
        Case().set("ring", **{name: 1.0})


def test_case_key_must_be_group_and_name():
    """F22: case['ring', 'width', 'junk'] = v silently ignored 'junk'."""
    c = Case()
    with pytest.raises(KeyError):
        c["ring", "width", "junk"] = 1e-3


def test_implausible_trace_is_refused(tmp_path):
    """F08: a 1e300 Pa trace ran to about 1e290 J with only converged = False."""
    psi = np.linspace(0, 720, 9)
    case = Case().with_numerics(**FAST)
    with pytest.raises(InputError, match=r"pressure must be positive and at most 1e8 Pa"):
        ringlube.run(case, trace=(psi, np.full(9, 1e300)))


def test_implausible_viscosity_at_the_liner_temperature_is_refused():
    """F09: theta0 = 700 K (inside its range) gave 2.2e131 J."""
    with pytest.raises(InputError, match=r"&lubricant eta0: .* outside the plausible"):
        Case().with_("lubricant", theta0=700.0).validate()


@pytest.mark.cli
def test_long_quoted_string_reads_in_linear_time(tmp_path, solver):
    """F10: a 320k-character quoted value took 24 s (one character at a time)."""
    deck = tmp_path / "long.nml"
    deck.write_text("&operating pressure_file = '" + "x" * 400_000 + "' /\n")
    t = time.perf_counter()
    p = subprocess.run([solver, str(deck)], capture_output=True, text=True, timeout=60)
    assert p.returncode == 2 and "pressure file not found" in p.stderr
    assert time.perf_counter() - t < 30  # generous: the old reader needed minutes


def test_utf8_bom_deck_is_read(tmp_path):
    """F19: a deck saved with a byte-order mark was 'text outside a namelist group'."""
    deck = tmp_path / "bom.nml"
    deck.write_bytes(b"\xef\xbb\xbf&ring width = 1.0e-3 /\n&numerics preset = 'fast' /\n")
    assert Case.from_namelist(deck)["ring", "width"] == 1.0e-3
    assert ringlube.run(deck).converged


@pytest.mark.cli
def test_a_deck_must_be_a_regular_file(solver, tmp_path):
    """F20: as root, `ringlube-solve /dev/null` ran on defaults and wrote /dev/result.h5."""
    p = subprocess.run([solver, "/dev/null"], capture_output=True, text=True)
    assert p.returncode == 2 and "not a regular file" in p.stderr
    with pytest.raises(InputError, match="not a regular file"):
        Case.from_namelist(tmp_path)


def test_run_many_keeps_results_whatever_a_case_raises():
    """F12: a non-RinglubeError from one entry (None in the list) lost every good result."""
    base = Case().with_numerics(**FAST)
    with pytest.raises(BatchError) as info:
        ringlube.run_many([base, None], workers=1, progress=False)
    assert info.value.results[0].converged and list(info.value.errors) == [1]


def test_load_refuses_inconsistent_files(tmp_path):
    """F16: a file whose series lengths disagree loaded, and writing it back failed."""
    path = ringlube.run(Case().with_numerics(**FAST), output=tmp_path / "r.h5").path
    with h5py.File(path, "a") as f:
        del f["cycle/h0_m"]
        f["cycle/h0_m"] = np.zeros(3)
    with pytest.raises(InputError, match="not a readable ringlube result"):
        ringlube.load(path)


def test_to_namelist_into_a_missing_folder_is_an_input_error(tmp_path):
    """F24: a raw FileNotFoundError / IsADirectoryError."""
    with pytest.raises(InputError, match="cannot write the deck"):
        Case().to_namelist(tmp_path / "missing" / "x.nml")
    with pytest.raises(InputError, match="cannot write the deck"):
        Case().to_namelist(tmp_path)
