"""Validation against the source study (``ringlube validate``, docs/validation.md).

Every run the report needs, as numbers (:mod:`ringlube.validate.compute`), their Markdown
(:mod:`ringlube.validate.render`) and the report with its figures written
(:mod:`ringlube.validate.report`).
"""

from .compute import ValidationData, compute_validation
from .render import render_validation
from .report import validate

__all__ = ["validate", "compute_validation", "render_validation", "ValidationData"]
