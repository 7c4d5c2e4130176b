"""The pytest markers are the ctest labels, and every test module has its labels."""

from __future__ import annotations

import re

from conftest import MODULE_LABELS, ROOT, SLOW


def _ctest_labels() -> set[str]:
    text = (ROOT / "tests" / "fortran" / "tests.cmake").read_text()
    found = re.findall(r'LABELS "([a-z_;]+)"', text)
    found += re.findall(r'set\(ringlube_labels_\w+ "([^"]+)"\)', text)
    return {label for labels in found for label in labels.split(";")}


def _markers() -> set[str]:
    # (tomllib is Python 3.11+): the lines of `markers = [...]` in [tool.pytest.ini_options]
    block = (ROOT / "pyproject.toml").read_text().split("\nmarkers = [", 1)[1].split("]", 1)[0]
    return set(re.findall(r'^\s*"(\w+):', block, flags=re.M))


def test_markers_are_the_ctest_labels():
    assert _ctest_labels() == _markers()
    assert {label for labels in MODULE_LABELS.values() for label in labels} <= _markers()


def test_every_test_module_has_labels():
    modules = {p.stem for p in (ROOT / "tests" / "python").glob("test_*.py")}
    assert modules == set(MODULE_LABELS), modules ^ set(MODULE_LABELS)


def test_slow_tests_exist():
    """Every name of conftest.SLOW is a test function (a renamed test would lose its label)."""
    text = "".join(p.read_text() for p in (ROOT / "tests" / "python").glob("test_*.py"))
    missing = [n for n in SLOW if f"def {n.split('[')[0]}(" not in text]
    assert not missing, missing
