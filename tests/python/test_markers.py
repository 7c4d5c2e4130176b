"""The pytest markers are the ctest labels, and every collected test carries its labels."""

from __future__ import annotations

import re

import pytest

from conftest import ROOT

pytestmark = pytest.mark.unit


def _ctest_labels() -> set[str]:
    """The labels of the Fortran test programs (their `! ctest labels:` line) and of the
    other ctests (`LABELS` in tests/fortran/tests.cmake)."""
    sources = (ROOT / "tests" / "fortran").glob("test_*.f90")
    found = [m for p in sources for m in re.findall(r"^! ctest labels: ([a-z_;]+)$", p.read_text(), re.M)]
    found += re.findall(r'LABELS "([a-z_;]+)"', (ROOT / "tests" / "fortran" / "tests.cmake").read_text())
    return {label for labels in found for label in labels.split(";")}


def _markers() -> set[str]:
    # (tomllib is Python 3.11+): the lines of `markers = [...]` in [tool.pytest.ini_options]
    block = (ROOT / "pyproject.toml").read_text().split("\nmarkers = [", 1)[1].split("]", 1)[0]
    return set(re.findall(r'^\s*"(\w+):', block, flags=re.M))


def test_markers_are_the_ctest_labels():
    assert _ctest_labels() == _markers()


def test_every_collected_test_has_its_labels(request):
    """Every test collected with this one has a label of what it checks (`unit` or
    `numerics` or `cli` or `io`), `cli` if it runs ringlube-solve (the `solver` fixture) and
    `known_limitation` if it is a strict xfail: a new test without its marks fails here."""
    kinds = {"unit", "numerics", "cli", "io"}
    wrong = []
    for item in request.session.items:
        marks = {m.name for m in item.iter_markers()}
        xfail = item.get_closest_marker("xfail")
        if (
            not marks & kinds
            or ("solver" in getattr(item, "fixturenames", ()) and "cli" not in marks)
            or ((xfail is not None and xfail.kwargs.get("strict", False)) != ("known_limitation" in marks))
        ):
            wrong.append(item.nodeid)
    assert not wrong, wrong
