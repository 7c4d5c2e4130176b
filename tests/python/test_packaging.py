"""The installed package: example inputs shipped as package data, one version, the extras."""

from __future__ import annotations

import doctest
import importlib.metadata
import re
import subprocess
import sys
from pathlib import Path

import h5py
import pytest

import ringlube
import ringlube._version
import ringlube.examples
from ringlube.examples import copy_examples, examples_dir

from conftest import INPUTS, ROOT

pytestmark = pytest.mark.io

#: Every shipped input of the repository (what the wheel must carry).
SHIPPED = sorted(
    p.relative_to(INPUTS) for p in INPUTS.rglob("*") if p.is_file() and p.suffix in {".nml", ".csv", ".md"}
)


def test_repository_has_the_inputs_the_tests_expect():
    names = {p.as_posix() for p in SHIPPED}
    assert {
        "calibration.nml",
        "crf450r_4000rpm_full_cold.nml",
        "study_default.nml",
        "pressure/crf450r_4000rpm_full.csv",
    } <= names


def test_installed_package_holds_the_example_inputs():
    installed = Path(ringlube.__file__).resolve().parent / "examples"
    assert examples_dir() == installed, "examples must come from the installed package"
    for rel in SHIPPED:
        assert (installed / rel).read_bytes() == (INPUTS / rel).read_bytes(), rel


def test_copied_deck_runs_like_the_repository_deck(tmp_path):
    copied = copy_examples(tmp_path)
    assert sorted(p.relative_to(tmp_path) for p in copied) == SHIPPED
    deck = tmp_path / "crf450r_4000rpm_full_cold.nml"
    here = ringlube.run(ringlube.Case.from_namelist(deck).with_numerics(nodes=31, dpsi_deg=4.0))
    repo = ringlube.run(ringlube.Case.from_namelist(INPUTS / deck.name).with_numerics(nodes=31, dpsi_deg=4.0))
    # The copy finds its calibration and gas trace: same inputs, same numbers, bit for bit.
    assert here.energy_loss == repo.energy_loss
    assert here.mixed_share == repo.mixed_share
    assert here.energy_loss > 0


def test_copy_examples_never_overwrites_unless_asked(tmp_path):
    copy_examples(tmp_path)
    edited = tmp_path / "crf450r_4000rpm_full_cold.nml"
    edited.write_text("&ring width = 1.2e-3 /\n")
    with pytest.raises(FileExistsError, match="already exists"):
        copy_examples(tmp_path)
    assert edited.read_text() == "&ring width = 1.2e-3 /\n"
    copy_examples(tmp_path, overwrite=True)
    assert edited.read_bytes() == (INPUTS / edited.name).read_bytes()


def test_examples_docstrings_run():
    failed, attempted = doctest.testmod(ringlube.examples)
    assert attempted > 0 and failed == 0


def _cmake_version() -> str:
    text = (ROOT / "CMakeLists.txt").read_text()
    found = re.findall(r"^\s*project\s*\(\s*ringlube\s+VERSION\s+([0-9][0-9.]*)", text, re.M)
    assert len(found) == 1, "CMakeLists.txt must write the version exactly once"
    return found[0]


@pytest.mark.cli
def test_one_version_everywhere(solver, tmp_path):
    version = _cmake_version()
    assert importlib.metadata.version("ringlube") == version
    assert ringlube._version.__version__ == version
    assert ringlube.__version__ == version
    printed = subprocess.run([solver, "--version"], capture_output=True, text=True, check=True)
    kernel = ringlube.kernel_id()
    assert printed.stdout.split() == ["ringlube-solve", version, "(kernel", kernel + ")"]
    # ... and the kernel writes the same version into every result.
    copy_examples(tmp_path)
    out = tmp_path / "cold.h5"
    subprocess.run(
        [solver, "-q", str(tmp_path / "crf450r_4000rpm_full_cold.nml"), "-o", str(out)], check=True
    )
    with h5py.File(out, "r") as f:
        written = f.attrs["ringlube_version"]
        written_kernel = f.attrs["kernel_id"]
    assert (written.decode() if isinstance(written, bytes) else str(written)) == version
    assert (written_kernel.decode() if isinstance(written_kernel, bytes) else str(written_kernel)) == kernel


def test_kernel_id_follows_the_sources(tmp_path):
    """fortran/kernel_id.cmake hashes the kernel's sources and build settings: the same inputs
    give the same id, a changed source or compiler flag another, and an unchanged id leaves
    the generated file alone (so nothing recompiles)."""
    import shutil

    cmake = shutil.which("cmake")
    if cmake is None:
        pytest.skip("cmake not on PATH")
    a, b = tmp_path / "a.f90", tmp_path / "b.f90"
    a.write_text("module a\nend module a\n")
    b.write_text("module b\nend module b\n")
    out = tmp_path / "kernel_id.f90"

    def kernel_id(extra="GNU 12 -O3"):
        subprocess.run(
            [
                cmake,
                f"-DSOURCES={a}|{b}",
                f"-DEXTRA={extra}",
                f"-DOUT={out}",
                "-P",
                str(ROOT / "fortran" / "kernel_id.cmake"),
            ],
            check=True,
        )
        found = re.findall(r"kernel_id = '([0-9a-f]{12})'", out.read_text())
        assert len(found) == 1
        return found[0]

    first = kernel_id()
    stamp = out.stat().st_mtime_ns
    assert kernel_id() == first and out.stat().st_mtime_ns == stamp
    assert kernel_id("GNU 12 -O2") != first
    b.write_text("module b\n! a comment\nend module b\n")
    assert kernel_id() != first


def test_pyproject_does_not_repeat_the_version():
    tomllib = pytest.importorskip("tomllib")  # Python 3.11+

    with open(ROOT / "pyproject.toml", "rb") as f:
        project = tomllib.load(f)["project"]
    assert "version" not in project and "version" in project["dynamic"]


def test_a_single_run_needs_no_study_extra():
    """Dask and pymoo belong to the `study` extra: importing the package and the
    command line, and running a case, must not load them."""
    code = (
        "import sys, ringlube, ringlube.cli; from ringlube.examples import examples_dir; "
        "c = ringlube.Case.from_namelist(examples_dir() / 'crf450r_4000rpm_full_cold.nml'); "
        "ringlube.run(c.with_numerics(nodes=31, dpsi_deg=4.0)); "
        "print(sorted(m for m in ('dask', 'distributed', 'pymoo') if m in sys.modules))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip().splitlines()[-1] == "[]"
