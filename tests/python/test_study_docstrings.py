"""Every public name of the study and CLI modules has a numpydoc docstring with an Example,
and the examples that can run here do."""

from __future__ import annotations

import doctest
import importlib
import inspect

import pytest

pytestmark = pytest.mark.unit

MODULES = [
    "ringlube.executor",
    "ringlube.study.variables",
    "ringlube.study.constraints",
    "ringlube.study.bounds",
    "ringlube.study.settings",
    "ringlube.study.deck",
    "ringlube.study.h5",
    "ringlube.study.state",
    "ringlube.study.state_checks",
    "ringlube.study.layout",
    "ringlube.study.store",
    "ringlube.study.runs",
    "ringlube.study.surfaces",
    "ringlube.study.optimise",
    "ringlube.study.check",
    "ringlube.study.sure",
    "ringlube.study.direct",
    "ringlube.study.problems",
    "ringlube.study.pipeline",
    "ringlube.study.plots",
    "ringlube.study.format",
    "ringlube.study.summary",
    "ringlube.study.pareto",
    "ringlube.study.figures",
    "ringlube.study.report",
    "ringlube.study.surrogate",
    "ringlube.cli",
]


@pytest.mark.parametrize("name", MODULES)
def test_public_names_are_documented(name):
    mod = importlib.import_module(name)
    assert mod.__doc__
    for public in mod.__all__:
        obj = getattr(mod, public)
        if not (inspect.isfunction(obj) or inspect.isclass(obj)):
            continue  # constants are described by a #: comment
        doc = inspect.getdoc(obj) or ""
        assert "Example" in doc, f"{name}.{public}: no Example"
        if inspect.isfunction(obj) and inspect.signature(obj).parameters:
            assert "Parameters" in doc, f"{name}.{public}: no Parameters"
        if inspect.isfunction(obj) and inspect.signature(obj).return_annotation not in (
            None,
            "None",
            inspect.Signature.empty,
        ):
            assert "Returns" in doc, f"{name}.{public}: no Returns"


@pytest.mark.parametrize("name", MODULES)
def test_examples_run(name, monkeypatch, tmp_path):
    monkeypatch.chdir(tmp_path)
    mod = importlib.import_module(name)
    result = doctest.testmod(mod, optionflags=doctest.ELLIPSIS)
    assert result.failed == 0
