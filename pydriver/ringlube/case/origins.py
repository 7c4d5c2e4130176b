"""Where the inputs of a case come from: deck, calibration file, Python, numerics preset or
the kernel's default (:meth:`~ringlube.case.Case.origins`,
:meth:`~ringlube.case.Case.effective_inputs`), and the source engine's defaults filling part of
a case's own engine (:class:`SourceEngineDefaultWarning`).

The methods are those of :class:`ringlube.case.Case` (through :class:`_InputOrigins`).
"""

from __future__ import annotations

import os
import warnings
from typing import Any, NamedTuple

from ..errors import InputError, error_for
from .items import items
from .kernel import kernel_case, kernel_text

__all__ = ["EffectiveInput", "SOURCE_ENGINE_INPUTS", "SourceEngineDefaultWarning"]

#: Inputs whose defaults describe the source study's engine (Honda CRF450R: crank, conrod,
#: 96 mm bore) and its optimum top ring (face width, crown, tension, and a radial depth sized
#: for that bore). A case that sets some of these but not all gets the rest from that engine,
#: and :class:`SourceEngineDefaultWarning` says so. Not counted: the ring's density and
#: ``tension_unit`` (a material and a convention, not the engine), the operating point,
#: lubricant and surfaces (the study's, but not engine geometry; see docs/own_engine.md).
SOURCE_ENGINE_INPUTS: tuple[tuple[str, str], ...] = (
    ("engine", "crank_radius"),
    ("engine", "conrod_length"),
    ("engine", "bore_radius"),
    ("ring", "width"),
    ("ring", "crown_height"),
    ("ring", "crown_offset"),
    ("ring", "tension"),
    ("ring", "radial_depth"),
)
#: The face-profile inputs among them, by ``&ring profile``: a case's own profile's count
#: (their defaults are the source ring's crown, as a drop at its half width for 'gauge'; a
#: table is the case's own).
PROFILE_INPUTS: dict[str, tuple[tuple[str, str], ...]] = {
    "edge": (("ring", "crown_height"),),
    "gauge": (("ring", "gauge_length"), ("ring", "gauge_drop_top"), ("ring", "gauge_drop_bottom")),
    "table": (),
}


class SourceEngineDefaultWarning(UserWarning):
    """The source engine's (CRF450R) defaults fill engine-geometry or ring inputs of a case
    that sets some of its own (see :data:`SOURCE_ENGINE_INPUTS`).

    Examples
    --------
    >>> import warnings
    >>> from ringlube import Case
    >>> with warnings.catch_warnings(record=True) as w:
    ...     warnings.simplefilter("always")
    ...     Case({"engine": {"bore_radius": 43e-3}}).with_numerics(dpsi_deg=2.0).validate()
    360
    >>> w[0].category.__name__, str(w[0].message).split(":")[0]
    ('SourceEngineDefaultWarning', "case 'case'")
    """


class EffectiveInput(NamedTuple):
    """One input as the kernel uses it, and where its value came from.

    ``origin`` is 'deck', 'calibration file', 'Python' (changed on the Case), "preset 'NAME'"
    (set by the numerics preset) or 'default' (the kernel's table).

    Examples
    --------
    >>> EffectiveInput("ring", "width", 1e-3, "m", "deck").origin
    'deck'
    """

    group: str
    name: str
    value: Any
    unit: str
    origin: str


def _names(keys: list[tuple[str, str]]) -> str:
    """'&engine a, b; &ring c' from [(group, name), ...]."""
    by_group: dict[str, list[str]] = {}
    for group, name in keys:
        by_group.setdefault(group, []).append(name)
    return "; ".join(f"&{g} {', '.join(n)}" for g, n in by_group.items())


class _InputOrigins:
    """Methods of :class:`~ringlube.case.Case`: where each input's value comes from."""

    # where the values come from -------------------------------------------------------
    def _calibration_keys(self) -> set[tuple[str, str]]:
        path = self.get("calibration", "file")
        if not path:
            return set()
        try:
            with open(path, "rb") as fh:
                text = fh.read().decode("utf-8", "surrogateescape")
            return {(i.group, i.name) for i in items(text, str(path), lists=True)}
        except (OSError, InputError):  # the kernel reports an unreadable calibration file
            return set()

    def origins(self) -> dict[tuple[str, str], str]:
        """Where each input's value comes from: 'deck', 'calibration file', 'Python',
        "preset 'NAME'" or 'default', for every input of the kernel's table.

        Examples
        --------
        >>> from ringlube import Case
        >>> o = Case.from_namelist("inputs/crf450r_4000rpm_full_cold.nml").with_ring(width=1.1e-3).origins()
        >>> o["ring", "width"], o["ring", "crown_height"], o["surface", "zeta_kappa_sigma"]
        ('Python', 'deck', 'calibration file')
        >>> o["numerics", "nodes"], o["lubricant", "supply_film"]
        ("preset 'default'", 'default')
        """
        from ..tables import INPUTS, PRESETS

        calibration = self._calibration_keys()
        preset = str(self.get("numerics", "preset", "default")).lower()
        preset_values = PRESETS.get(preset, PRESETS["default"])
        out = {}
        for group, name in INPUTS:
            key = (group, name)
            if key in self._changed:
                out[key] = "Python"
            elif name in self._nml.get(group, {}):
                out[key] = "deck"
            elif key in calibration:
                out[key] = "calibration file"
            elif group == "numerics" and name in preset_values:
                out[key] = f"preset '{preset}'"
            else:
                out[key] = "default"
        return out

    def effective_inputs(self) -> list[EffectiveInput]:
        """Every input of the kernel's table as the kernel reads this case, with its unit and
        where it came from (see :meth:`origins`).

        Returns
        -------
        list of EffectiveInput

        Raises
        ------
        InputError
            If the kernel rejects the case.

        Examples
        --------
        >>> from ringlube import Case
        >>> rows = Case.from_namelist("inputs/crf450r_4000rpm_full_cold.nml").effective_inputs()
        >>> [r for r in rows if r.name == "crown_offset"][0]
        EffectiveInput(group='ring', name='crown_offset', value=-3.83e-05, unit='m', origin='deck')
        """
        from ..tables import INPUTS

        origins = self.origins()
        return [
            EffectiveInput(group, name, self._effective(spec), spec.unit, origins[group, name])
            for (group, name), spec in INPUTS.items()
        ]

    def _effective(self, spec) -> Any:
        """The effective value of the input ``spec`` (an :class:`~ringlube.tables.InputSpec`)
        as the kernel reads this case. One kernel handle reads every input's text on first
        use; the texts are kept until the case, the working directory its relative paths
        mean, or a file it names (calibration, pressure trace) changes."""
        from ..tables import typed_value

        key = (self.kernel_inputs(), _files_seen(self))
        seen = getattr(self, "_effective_texts", None)
        if seen is None or seen[0] != key:
            seen = (key, _kernel_texts(self))
            self._effective_texts = seen
        code, text = seen[1][spec.group, spec.name]
        if code:
            raise error_for(code, text)
        return typed_value(spec.kind, text)

    def source_engine_defaults(self) -> tuple[list[tuple[str, str]], list[tuple[str, str]]]:
        """(inputs of :data:`SOURCE_ENGINE_INPUTS` this case sets, those left to the source
        engine's defaults); a warning is due when both are non-empty.

        Examples
        --------
        >>> from ringlube import Case
        >>> own, filled = Case({"engine": {"bore_radius": 43e-3}}).source_engine_defaults()
        >>> own, filled[:2]
        ([('engine', 'bore_radius')], [('engine', 'crank_radius'), ('engine', 'conrod_length')])
        """
        calibration = self._calibration_keys() if self.get("calibration", "file") else set()
        profile = PROFILE_INPUTS.get(str(self.get("ring", "profile") or "edge"), ())
        # (the crown height's place taken by the case's own profile's inputs)
        crown = ("ring", "crown_height")
        inputs = [k for key in SOURCE_ENGINE_INPUTS for k in (profile if key == crown else [key])]
        own, filled = [], []
        for group, name in inputs:
            is_set = name in self._nml.get(group, {}) or (group, name) in calibration
            (own if is_set else filled).append((group, name))
        return own, filled

    def warn_source_defaults(self, stacklevel: int = 2) -> str:
        """Warn (:class:`SourceEngineDefaultWarning`) if the source engine's defaults fill
        some engine-geometry or ring inputs of this case while it sets others; returns the
        message ('' when none is due).

        Parameters
        ----------
        stacklevel : int
            As for :func:`warnings.warn`.

        Examples
        --------
        >>> from ringlube import Case
        >>> Case().warn_source_defaults()   # nothing set: the source engine, knowingly
        ''
        """
        own, filled = self.source_engine_defaults()
        if not (own and filled):
            return ""
        where = self.source or f"case {self.name!r}"
        message = (
            f"{where}: the source engine's (CRF450R) defaults fill {_names(filled)} "
            f"while the case sets {_names(own)}; set them for your engine (docs/own_engine.md)"
        )
        warnings.warn(message, SourceEngineDefaultWarning, stacklevel=stacklevel + 1)
        return message


def _kernel_texts(case: Any) -> dict[tuple[str, str], tuple[int, str]]:
    """Every input of ``case`` as the kernel reads it, through one handle: (0, value as
    text), or (error code, message) where the kernel refuses to give it."""
    from .. import _kernel
    from ..tables import INPUTS

    texts = {}
    with kernel_case(case, load_trace=False, warn=False) as k:
        for group, name in INPUTS:
            text, code, message = _kernel.rl_get(k.handle, group.encode(), name.encode())
            texts[group, name] = (int(code), kernel_text(message)) if code else (0, kernel_text(text))
    return texts


def _files_seen(case: Any) -> tuple:
    """What the kernel reads of the files a case names, as they are now: the calibration
    file's and the face profile's bytes, whether the pressure file is there and what it is
    (None: missing). A kept reading of the case holds only while these do not change."""
    cal, trace = case.get("calibration", "file"), case.get("operating", "pressure_file")
    cal_bytes, profile_bytes = (_bytes(p) for p in (cal, case.get("ring", "profile_file")))
    try:
        mode = os.stat(trace).st_mode if trace else None
    except (OSError, TypeError, ValueError):
        mode = None
    return cal_bytes, mode, profile_bytes


def _bytes(path: Any) -> bytes | None:
    """The bytes of a file (None: no file, or not readable)."""
    try:
        with open(path, "rb") as fh:
            return fh.read()
    except (OSError, TypeError, ValueError):
        return None
