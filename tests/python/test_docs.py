"""Generated documentation is current: docs/model.md's input and result tables
are generated from the kernel's tables; this test fails when a variable, default, range,
unit or result name changes and the doc was not regenerated."""

from __future__ import annotations

import pytest

from ringlube.docgen import update_doc
from ringlube.tables import INPUTS

from conftest import ROOT

pytestmark = pytest.mark.unit


def test_model_md_tables_are_current():
    assert update_doc(ROOT / "docs" / "model.md", write=False), (
        "docs/model.md is stale: run `.venv/bin/python -m ringlube.docgen docs/model.md`"
    )


def test_stale_doc_is_detected(tmp_path):
    doc = tmp_path / "model.md"
    doc.write_text((ROOT / "docs" / "model.md").read_text().replace("crank radius r", "crank r"))
    assert not update_doc(doc, write=False)
    assert update_doc(doc, write=True) is False and update_doc(doc, write=False)
    assert "crank radius r" in doc.read_text() and ("engine", "crank_radius") in INPUTS
