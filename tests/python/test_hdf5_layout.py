"""The HDF5 layout ringlube-solve writes (docs/model.md "Results"), read with h5py (and with
xarray/h5netcdf where installed): dimension scale, long_name, UTF-8 strings, a deck over
64 KiB kept whole."""

from __future__ import annotations

import re
import shutil
import subprocess
from pathlib import Path

import h5py
import numpy as np
import pytest

from ringlube.tables import FLAG_BITS, INT_SERIES, SERIES

from conftest import INPUTS, ROOT

pytestmark = pytest.mark.io

MODEL_MD = (ROOT / "docs" / "model.md").read_text()


#: root attributes and /cycle datasets of the documented layout (docs/model.md "Results",
#: generated from the kernel's result table; the README points there)
#: (rows marked "only)" belong to the mass-conserving film or the starved inlet and are
#: written only by those runs)
_ALWAYS = "\n".join(line for line in MODEL_MD.splitlines() if "only) |" not in line)
ROOT_ATTRS = re.findall(r"^\| root attribute \| `([^`]+)`", _ALWAYS, flags=re.M) + [
    "deck",
    "deck_path",
    "pressure_file",
    "ringlube_version",
    "kernel_id",
]
CYCLE_DSETS = re.findall(r"^\| `/cycle` \| `([^`]+)`", _ALWAYS, flags=re.M)
STRING_ATTRS = ("deck", "deck_path", "pressure_file", "ringlube_version", "kernel_id")


def _deck(folder: Path, extra: str = "") -> Path:
    """A quick copy of the shipped cold deck (coarse numerics) in `folder`."""
    shutil.copytree(INPUTS / "pressure", folder / "pressure")
    shutil.copy(INPUTS / "calibration.nml", folder / "calibration.nml")
    text = (INPUTS / "crf450r_4000rpm_full_cold.nml").read_text()
    text = re.sub(r"&numerics[^/]*/", "&numerics nodes = 31, dpsi_deg = 5 /", text)
    deck = folder / "deck.nml"
    deck.write_text(text + extra)
    return deck


@pytest.fixture(scope="module")
def result(solver, tmp_path_factory) -> Path:
    folder = tmp_path_factory.mktemp("layout")
    out = folder / "out.h5"
    subprocess.run([solver, "-q", str(_deck(folder)), "-o", str(out)], check=True)
    return out


def test_docs_list_the_layout():
    # guards the parsing below: the generated table is where the names come from
    assert {"energy_loss_J", "deck", "ringlube_version"} <= set(ROOT_ATTRS)
    assert {"crank_angle_deg", "h0_m", "flags", "film_solves"} <= set(CYCLE_DSETS)


#: names of the layout that every result has and users' scripts read: a rename breaks them
PROMISED_ROOT = {"converged", "cycles_run", "deck", "min_film_m", "mixed_share_pct", "ring_mass_g"}
PROMISED_CYCLE = {"crank_angle_deg", "sliding_speed_m_s", "h0_m", "lambda_min"}


def test_promised_names_are_documented():
    """Every promised root attribute and /cycle dataset is in the documented layout for every
    run (test_documented_layout then finds them in a file)."""
    assert PROMISED_ROOT <= set(ROOT_ATTRS), PROMISED_ROOT - set(ROOT_ATTRS)
    assert PROMISED_CYCLE <= set(CYCLE_DSETS), PROMISED_CYCLE - set(CYCLE_DSETS)


@pytest.mark.cli
def test_documented_layout(result):
    with h5py.File(result) as f:
        assert set(ROOT_ATTRS) <= set(f.attrs)
        assert set(CYCLE_DSETS) <= set(f["cycle"])
        n = f["cycle/crank_angle_deg"].shape
        for name in CYCLE_DSETS:
            d = f["cycle"][name]
            assert d.shape == n and d.ndim == 1, name
            assert "units" in d.attrs, name
        assert f.attrs["converged"] in (0, 1)


@pytest.mark.cli
def test_crank_angle_is_the_dimension_scale_of_every_dataset(result):
    with h5py.File(result) as f:
        c = f["cycle"]
        scale = c["crank_angle_deg"]
        assert h5py.h5ds.is_scale(scale.id)
        for name, d in c.items():
            if name == "crank_angle_deg":
                continue
            attached = list(d.dims[0].values())
            assert len(attached) == 1 and attached[0] == scale, name


@pytest.mark.cli
def test_long_name_and_units_on_every_dataset(result):
    with h5py.File(result) as f:
        for name, d in f["cycle"].items():
            for key in ("units", "long_name"):
                value = d.attrs[key]
                assert isinstance(value, str), (name, key, type(value))
                assert value and "\n" not in value, (name, key)
        for spec in (*SERIES.values(), *INT_SERIES.values()):
            if not spec.requires:
                assert f["cycle"][spec.stored].attrs["units"] == spec.unit, spec.stored
        # the flags' bits are described where the data is, as the kernel's table has them
        description = f["cycle"][INT_SERIES["flags"].stored].attrs["description"]
        for bit, text in FLAG_BITS.items():
            assert f"{bit}: {text}" in description


@pytest.mark.cli
def test_string_attributes_are_utf8_str(result):
    with h5py.File(result) as f:
        for key in STRING_ATTRS:
            value = f.attrs[key]
            assert isinstance(value, str), (key, type(value))
            tid = f.attrs.get_id(key).get_type()
            assert tid.is_variable_str() and tid.get_cset() == h5py.h5t.CSET_UTF8, key
        assert f.attrs["deck_path"].endswith("deck.nml")
        assert f.attrs["pressure_file"].endswith("crf450r_4000rpm_full.csv")
        assert "&operating" in f.attrs["deck"]


@pytest.mark.cli
@pytest.mark.slow
def test_deck_over_64_kib_is_kept_whole(solver, tmp_path):
    comments = "".join(f"! comment {i:05d} {'.' * 60}\n" for i in range(1500))
    deck = _deck(tmp_path, "! non-ASCII: 20 µm, ±5 %\n" + comments)
    text = deck.read_text()
    assert len(deck.read_bytes()) > 100 * 1024
    out = tmp_path / "big.h5"
    subprocess.run([solver, "-q", str(deck), "-o", str(out)], check=True)
    with h5py.File(out) as f:
        stored = f.attrs["deck"]
    # the deck's own text comes first, then the calibration file it includes
    assert stored.startswith(text)
    assert (INPUTS / "calibration.nml").read_text().strip() in stored


@pytest.mark.cli
def test_text_that_is_not_utf8_is_still_readable(solver, tmp_path):
    deck = _deck(tmp_path)
    deck.write_bytes(b"! Stra\xdfe (Latin-1)\n" + deck.read_bytes())
    out = tmp_path / "latin.h5"
    subprocess.run([solver, "-q", str(deck), "-o", str(out)], check=True)
    with h5py.File(out) as f:
        stored = f.attrs["deck"]
    assert stored.startswith("! Stra\ufffde (Latin-1)\n")
    stored.encode("utf-8")  # no lone surrogates: printable and writable as UTF-8


@pytest.mark.cli
def test_xarray_opens_cycle_with_crank_angle_coordinate(result):
    xr = pytest.importorskip("xarray")
    pytest.importorskip("h5netcdf")
    with h5py.File(result) as f:
        angle = f["cycle/crank_angle_deg"][()]
        h0 = f["cycle/h0_m"][()]
    with xr.open_dataset(result, group="cycle", engine="h5netcdf") as ds:
        assert list(ds.dims) == ["crank_angle_deg"]
        assert "crank_angle_deg" in ds.coords
        np.testing.assert_array_equal(ds["crank_angle_deg"].values, angle)
        np.testing.assert_array_equal(ds["h0_m"].values, h0)
        assert ds["h0_m"].dims == ("crank_angle_deg",)
        assert ds["h0_m"].attrs["units"] == "m"
        assert ds["h0_m"].attrs["long_name"]
        for name in CYCLE_DSETS:
            if name != "crank_angle_deg":
                assert ds[name].dims == ("crank_angle_deg",), name


@pytest.mark.cli
def test_every_input_is_a_root_attribute(result):
    """The design inputs travel with the result (`group.name`, the effective value; a list as
    its deck text), so files can be compared without parsing their decks."""
    from ringlube import Case
    from ringlube.tables import INPUTS

    case = Case.from_namelist(result.parent / "deck.nml")
    with h5py.File(result) as f:
        a = f.attrs
        for (group, name), spec in INPUTS.items():
            key = f"{group}.{name}"
            assert key in a, key
            value, expected = a[key], case.value(group, name)
            if key == "output.file":  # where the file was written, not the deck's &output file
                expected = str(result)
            if spec.kind == "real":
                assert isinstance(value, np.floating) and value == expected, key
            elif spec.kind in ("integer", "logical"):
                assert isinstance(value, np.integer) and value == int(expected), key
            elif spec.kind.endswith("_list"):  # deck text, "v1, v2, ..."
                values = [float(v) for v in value.replace(",", " ").split()]
                assert isinstance(value, str) and values == list(np.atleast_1d(expected)), key
            else:
                assert isinstance(value, str) and value == str(expected), key
        assert a["ring.width"] == 1.004e-3 and a["operating.speed_rpm"] == 4000.0
        assert a["physics.roelands"] == 1 and a["physics.outlet"] == "reynolds"


@pytest.mark.cli
def test_units_in_every_scalar_name(result):
    """Each stored scalar's name ends in its unit (the README's words: not all SI)."""
    from ringlube.tables import SCALARS

    suffix = {"J": "_J", "%": "_pct", "g": "_g", "m": "_m", "N": "_N", "s": "_s", "W": "_W"}
    suffix.update({"kPa": "_kPa", "mm^3": "_mm3", "g/h": "_g_h", "L/min": "_l_min", "mg": "_mg_per_cycle"})
    suffix.update({"bar": "_bar", "L": "_L", "K": "_K", "Pa": "_Pa", "deg": "_deg"})
    for s in SCALARS.values():
        if s.unit != "1":
            assert s.stored.endswith(suffix[s.unit]), (s.stored, s.unit)


@pytest.mark.cli
def test_scalars_stored_and_read_by_their_kind(result):
    """The table's kind of each scalar decides how it is stored and read: 'integer' and
    'logical' as HDF5 integers (a logical 0 or 1), 'real' as floats; ``load`` gives bool,
    int and float by the same column."""
    import ringlube
    from ringlube.tables import MODELS, SCALARS

    loaded = ringlube.load(result)
    with h5py.File(result) as f:
        for k, s in SCALARS.items():
            if s.stored not in f.attrs:
                assert s.requires in MODELS, k  # only a model's results may be absent
                continue
            value = f.attrs[s.stored]
            if s.kind == "real":
                assert isinstance(value, np.floating), k
                assert isinstance(getattr(loaded, k), float), k
            else:
                assert isinstance(value, np.integer), k
                assert s.kind in ("integer", "logical"), k
                kind = bool if s.kind == "logical" else int
                assert type(getattr(loaded, k)) is kind, k
                assert s.kind == "integer" or value in (0, 1), k
