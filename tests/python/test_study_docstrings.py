"""Every public name of the study and CLI modules has a numpydoc docstring with an Example,
and the examples that can run here do (issue 10 item 6)."""

from __future__ import annotations

import doctest
import importlib
import inspect

import pytest

MODULES = [
    "ringlube.executor",
    "ringlube.study_variables",
    "ringlube.study_constraints",
    "ringlube.study_settings",
    "ringlube.study_deck",
    "ringlube.study_h5",
    "ringlube.study_state",
    "ringlube.study_state_checks",
    "ringlube.study_layout",
    "ringlube.study_store",
    "ringlube.study_runs",
    "ringlube.study_surfaces",
    "ringlube.study_optimise",
    "ringlube.study_check",
    "ringlube.study_sure",
    "ringlube.study_direct",
    "ringlube.study",
    "ringlube.study_plots",
    "ringlube.study_format",
    "ringlube.study_summary",
    "ringlube.study_pareto",
    "ringlube.study_figures",
    "ringlube.study_report",
    "ringlube.surrogate",
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
