"""numpydoc docstrings: every public function and class of the package has a
docstring, with Parameters where it takes any and an Example; every Example runs."""

from __future__ import annotations

import doctest
import importlib
import inspect
import pkgutil

import pytest
from test_study_docstrings import MODULES as STUDY_MODULES

import ringlube

from conftest import ROOT

pytestmark = pytest.mark.unit

MODULES = [
    m.name.removeprefix("ringlube.")
    for m in pkgutil.walk_packages(ringlube.__path__, "ringlube.")
    if not any(part.startswith("_") for part in m.name.split("."))
]
#: the modules whose examples this file runs (the study and CLI modules' run in
#: test_study_docstrings.py, in a folder of their own: each example runs once)
EXAMPLES = [m for m in MODULES if f"ringlube.{m}" not in STUDY_MODULES]
#: the modules whose examples take over 1 s (`slow`)
SLOW_EXAMPLES = {"gas.traces"}
assert SLOW_EXAMPLES <= set(EXAMPLES), SLOW_EXAMPLES - set(EXAMPLES)


def _public(mod):
    names = getattr(mod, "__all__", [n for n in dir(mod) if not n.startswith("_")])
    for n in names:
        obj = getattr(mod, n, None)
        if (inspect.isfunction(obj) or inspect.isclass(obj)) and obj.__module__ == mod.__name__:
            yield n, obj


@pytest.mark.parametrize("name", MODULES)
def test_public_names_are_documented(name):
    mod = importlib.import_module(f"ringlube.{name}")
    missing = []
    for n, obj in _public(mod):
        doc = inspect.getdoc(obj) or ""
        takes = inspect.isfunction(obj) and len(inspect.signature(obj).parameters) > 0
        if not doc or "Example" not in doc or (takes and "Parameters" not in doc):
            missing.append(n)
    assert not missing, f"ringlube.{name}: incomplete docstrings: {missing}"


@pytest.mark.parametrize(
    "name", [pytest.param(m, marks=pytest.mark.slow) if m in SLOW_EXAMPLES else m for m in EXAMPLES]
)
def test_docstring_examples_run(name, monkeypatch):
    monkeypatch.chdir(ROOT)  # examples name the shipped inputs by relative path
    mod = importlib.import_module(f"ringlube.{name}")
    result = doctest.testmod(mod, optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    assert result.failed == 0
