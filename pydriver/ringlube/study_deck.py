"""The ``&study`` deck, read and checked.

:func:`read_study` reads a study deck into a :class:`~ringlube.study_settings.StudySettings`
and checks every value (each error names the file, ``&study`` and the variable), checks each
design variable against every base deck with the kernel's own reader, and fingerprints the
content of every input file (base decks, the calibration files they include, their pressure
traces) so that a study is never resumed on changed inputs.
"""

from __future__ import annotations

import dataclasses
import math
import os
from pathlib import Path
from typing import Any

from .case import Case
from .errors import InputError
from .study_constraints import parse_constraint
from .study_settings import StudySettings
from .study_variables import (
    DEFAULT_GROUP,
    DESIGN_RANGES,
    _fingerprint,
    _input_unit,
    _is_unknown_variable,
    _is_whole_number,
    _model_units,
    _produces,
    input_files,
    split_variable,
)

__all__ = ["read_study", "MAX_SAMPLES"]

#: Most samples a study may ask for. The study file holds every sample and is rewritten at
#: each checkpoint, and a run takes about 40 ms on one core: 10**6 samples are about
#: 11 hours of runs per case on 2 cores, already far more than a quadratic surface needs.
MAX_SAMPLES = 1_000_000
#: Largest seed (the GA repeats use ``seed + 1000 r``, which must stay below 2**32).
MAX_SEED = 2**31 - 1
_SAMPLERS = ("sobol", "lhs")
_SURROGATES = ("quadratic",)
_INT_KEYS = {
    "samples": 1,
    "population": 1,
    "generations": 1,
    "repeats": 1,
    "seed": 0,
    "folds": 2,
    "direct_population": 1,
    "direct_generations": 1,
    "batch": 1,
}


def _as_list(v) -> list:
    return list(v) if isinstance(v, (list, tuple)) else [v]


class _Checker:
    def __init__(self, path: Path):
        self.path = path

    def bad(self, var: str, why: str):
        raise InputError(f"{self.path}: &study {var}: {why}")

    def integer(self, var: str, v: Any, lo: int, hi: int | None = None, why: str = "") -> int:
        if isinstance(v, bool) or not isinstance(v, int):
            self.bad(var, f"must be a whole number, got {v!r}")
        if v < lo:
            self.bad(var, f"must be at least {lo}, got {v}")
        if hi is not None and v > hi:
            self.bad(var, f"must be at most {hi:,}, got {v:,}" + (f" ({why})" if why else ""))
        return v

    def reals(self, var: str, values: list) -> list[float]:
        out = []
        for v in values:
            if isinstance(v, bool) or not isinstance(v, (int, float)):
                self.bad(var, f"must be numbers, got {v!r}")
            if not math.isfinite(v):
                self.bad(var, f"must be finite numbers, got {v}")
            out.append(float(v))
        return out

    def words(self, var: str, values: list) -> list[str]:
        for v in values:
            if not isinstance(v, str) or not v.strip():
                self.bad(var, f"must be quoted names, got {v!r}")
        return [v.strip() for v in values]

    def plain_name(self, var: str, v: str, what: str) -> None:
        if not v or any(ch in v for ch in "/\\") or v.startswith(".") or v.strip() != v:
            self.bad(
                var,
                f"'{v}' must be a plain name (no '/', '\\', leading '.', leading or "
                f"trailing spaces): it names {what}",
            )


def read_study(path: str | os.PathLike) -> StudySettings:
    """Read and check a ``&study`` deck.

    Relative case paths are relative to the deck's folder. Each base deck is checked by
    the kernel, each design variable is checked to exist in every base deck (and its
    bounds to be accepted there), and the content of every input file is fingerprinted.

    Parameters
    ----------
    path : path
        The study deck.

    Returns
    -------
    StudySettings

    Raises
    ------
    InputError
        Naming the file, ``&study`` and the variable (or the base deck and its variable).

    Example
    -------
    >>> s = read_study("inputs/study_default.nml")     # doctest: +SKIP
    >>> s.samples, s.labels                             # doctest: +SKIP
    (1025, ['cold', 'hot'])
    """
    path = Path(path)
    if not path.is_file():
        raise InputError(f"{path}: file not found" if not path.exists() else f"{path}: not a file")
    nml = _parse(path)
    if "study" not in nml:
        raise InputError(f"{path}: no &study group")
    if not isinstance(nml["study"], dict):
        raise InputError(f"{path}: {len(nml['study'])} &study groups; a study deck has one")
    s = dict(nml["study"])
    chk = _Checker(path)
    twice = _given_twice(path.read_text(errors="replace"))
    if twice:
        chk.bad(twice, "given twice; keep one")
    known = {f.name for f in dataclasses.fields(StudySettings)} - {"deck_text", "source", "inputs", "units"}
    for k in s:
        if k not in known:
            chk.bad(k, f"unknown variable (known: {', '.join(sorted(known))})")

    if "cases" not in s:
        chk.bad("cases", "required (one or more base decks)")
    cases = [str((path.parent / c).resolve()) for c in chk.words("cases", _as_list(s["cases"]))]
    labels = chk.words("labels", _as_list(s.get("labels", [Path(c).stem for c in cases])))
    weights = chk.reals("weights", _as_list(s.get("weights", [1.0] * len(cases))))
    variables = chk.words("variables", _as_list(s.get("variables", list(DESIGN_RANGES))))
    objectives = chk.words(
        "objectives", _as_list(s.get("objectives", ["energy_loss", "mixed_share", "ring_mass"]))
    )
    ints = {k: chk.integer(k, s[k], lo) for k, lo in _INT_KEYS.items() if k in s}
    for k in ("sampler", "surrogate"):
        if k in s:
            chk.words(k, [s[k]])
    if "scene" in s and not isinstance(s["scene"], bool):
        chk.bad("scene", f"must be .true. or .false., got {s['scene']!r}")

    name = s.get("name", path.stem)
    if not isinstance(name, str):
        chk.bad("name", f"must be a quoted name, got {name!r}")
    chk.plain_name("name", name, "the study file")
    for label in labels:
        chk.plain_name("labels", label, "a group of the study file and its figures")
    if len(labels) != len(cases) or len(set(labels)) != len(labels):
        chk.bad("labels", f"one distinct label per case ({len(cases)} cases)")
    if "scene" in labels:
        chk.bad("labels", "'scene' is reserved for the weighted scene")
    if len(weights) != len(cases) or any(w <= 0 for w in weights):
        chk.bad("weights", f"one positive weight per case ({len(cases)} cases)")

    pairs = []
    for v in variables:
        group, name_ = split_variable(v)
        if not name_ or ":" in name_:
            chk.bad("variables", f"'{v}' is not 'name' or 'group:name'")
        if _is_whole_number(group, name_):
            chk.bad(
                "variables",
                f"'{v}' is a whole number (&{group} {name_}); a study samples real values: "
                "vary it with one base deck per value instead",
            )
        pairs.append((group, name_))
    if len(set(pairs)) != len(pairs):
        chk.bad("variables", "a variable is given twice")
    lower, upper = _bounds(chk, s, variables, pairs)
    if any(lo >= hi for lo, hi in zip(lower, upper)):
        chk.bad("upper", "each upper bound must exceed its lower bound")
    reference = None
    if "reference" in s:
        reference = chk.reals("reference", _as_list(s["reference"]))
        if len(reference) != len(variables):
            chk.bad("reference", f"one value per variable ({len(variables)})")

    constraints = []
    for text in chk.words("constraints", _as_list(s.get("constraints", []))):
        try:
            c = parse_constraint(text)
        except ValueError as exc:
            chk.bad("constraints", str(exc))
        if c.uses_reference and reference is None:
            chk.bad("constraints", f"'{text}' is bounded by the reference design: give &study reference")
        constraints.append(str(c))
    if len(set(constraints)) != len(constraints):
        chk.bad("constraints", "a constraint is given twice")

    units = _model_units()
    for o in objectives:
        if o not in units:
            chk.bad("objectives", f"unknown objective '{o}' (known: {', '.join(units)})")
    if not objectives or len(set(objectives)) != len(objectives):
        chk.bad("objectives", "one or more distinct objectives")
    sampler = s.get("sampler", "sobol")
    if sampler not in _SAMPLERS:
        chk.bad("sampler", f"must be one of {', '.join(map(repr, _SAMPLERS))}, got {sampler!r}")
    surrogate = s.get("surrogate", "quadratic")
    if surrogate not in _SURROGATES:
        chk.bad("surrogate", f"must be 'quadratic', got {surrogate!r}")
    if "samples" in ints:
        chk.integer(
            "samples",
            ints["samples"],
            1,
            MAX_SAMPLES,
            "the study file holds every sample; 10**6 runs are about 11 hours per case on 2 cores",
        )
    if "seed" in ints:
        chk.integer("seed", ints["seed"], 0, MAX_SEED)

    st = StudySettings(
        name=name,
        cases=cases,
        labels=labels,
        weights=weights,
        variables=variables,
        lower=lower,
        upper=upper,
        objectives=objectives,
        sampler=sampler,
        surrogate=surrogate,
        reference=reference,
        constraints=constraints,
        **({"scene": s["scene"]} if "scene" in s else {}),
        **ints,
        deck_text=path.read_text(errors="replace"),
        source=str(path),
    )
    nterms = 1 + 2 * len(variables) + len(variables) * (len(variables) - 1) // 2
    if st.samples < nterms + st.folds:
        chk.bad(
            "samples",
            f"need at least {nterms + st.folds} for a quadratic in "
            f"{len(variables)} variables with {st.folds}-fold cross-validation",
        )
    st.inputs, st.units = _check_cases(chk, st, pairs)
    from .tables import SCALARS

    for var, o in [("objectives", o) for o in objectives] + [
        ("constraints", c.name) for c in st.parsed_constraints
    ]:
        req = SCALARS[o].requires if o in SCALARS else ""
        if req and o not in st.outputs:
            need = {"jfo": "cavitation = 'jfo'", "starved": "inlet = 'starved'", "gas": "ring_pack = 'gas'"}[
                req
            ]
            for deck in cases:
                if not _produces(Case.from_namelist(deck), req):
                    chk.bad(var, f"'{o}' needs &physics {need} in every base deck ({deck} has not)")
        if o not in st.outputs:
            st.outputs.append(o)  # constrained results are recorded (and fitted) too
    return st


def _parse(path: Path):
    """The namelist file read by f90nml, or one line saying why not."""
    import contextlib
    import io

    import f90nml

    try:
        with contextlib.redirect_stdout(io.StringIO()):  # f90nml prints its state on some errors
            return f90nml.read(path)
    except Exception as exc:  # f90nml raises several types for bad syntax
        lines = str(exc).strip().splitlines()
        why = lines[0] if lines else f"{type(exc).__name__} (an unterminated string or a stray character?)"
        raise InputError(f"{path}: cannot parse namelist: {why}") from None


def _given_twice(text: str) -> str:
    """The first variable assigned twice in the ``&study`` group of ``text`` ('' if none).

    Strings and ``!`` comments are skipped; ``name(i) =`` counts per index.

    Example
    -------
    >>> _given_twice("&study samples = 16, samples = 32 /")
    'samples'
    >>> _given_twice("&study name = 'a=b', lower(1) = 1, lower(2) = 2 /")
    ''
    """
    import re

    code = re.sub(r"'(?:[^']|'')*'|\"(?:[^\"]|\"\")*\"|![^\n]*", " ", text)
    group = re.search(r"&study\b(.*?)(?:/|&end\b|$)", code, flags=re.IGNORECASE | re.DOTALL)
    seen = set()
    for m in re.finditer(r"([A-Za-z_]\w*)\s*(\([^)]*\))?\s*=", group.group(1) if group else ""):
        key = (m.group(1).lower(), (m.group(2) or "").replace(" ", ""))
        if key in seen:
            return m.group(1).lower()
        seen.add(key)
    return ""


def _bounds(
    chk: _Checker, s: dict, variables: list[str], pairs: list[tuple[str, str]]
) -> tuple[list[float], list[float]]:
    given = [k for k in ("lower", "upper") if k in s]
    if len(given) == 1:
        chk.bad(
            "lower" if "lower" not in s else "upper",
            f"required when '{given[0]}' is given (one bound per variable)",
        )
    if given:
        lower = chk.reals("lower", _as_list(s["lower"]))
        upper = chk.reals("upper", _as_list(s["upper"]))
        if not (len(lower) == len(upper) == len(variables)):
            chk.bad("lower", f"one lower and one upper bound per variable ({len(variables)})")
        return lower, upper
    missing = [v for v, (g, n) in zip(variables, pairs) if g != DEFAULT_GROUP or n not in DESIGN_RANGES]
    if missing:
        chk.bad(
            "lower",
            f"required: default ranges exist only for the ring variables "
            f"{', '.join(DESIGN_RANGES)}, not for {', '.join(missing)}",
        )
    return ([DESIGN_RANGES[n][0] for _, n in pairs], [DESIGN_RANGES[n][1] for _, n in pairs])


def _check_cases(
    chk: _Checker, st: StudySettings, pairs: list[tuple[str, str]]
) -> tuple[dict[str, str], list[str]]:
    """Kernel checks of every base deck, variable and bound; input fingerprints; units."""
    files: list[Path] = []
    units_seen: dict[str, dict[str, str]] = {}
    for label, deck in zip(st.labels, st.cases):
        case = Case.from_namelist(deck)  # the kernel checks the deck itself
        files += input_files(case, deck)
        for v, (group, name), lo, hi in zip(st.variables, pairs, st.lower, st.upper):
            try:
                case.with_(group, **{name: lo})
            except InputError as exc:
                chk.bad("variables", f"'{v}': {exc}")
            for which, value in (("lower", lo), ("upper", hi)):
                try:
                    case.with_(group, **{name: value}).validate()
                except InputError as exc:
                    msg = str(exc)
                    if _is_unknown_variable(group, name):
                        chk.bad("variables", f"'{v}' is not a variable of &{group} (base deck {deck})")
                    chk.bad(which, f"{v} = {value:g} is rejected by base deck '{label}': {msg}")
            units_seen.setdefault(v, {})[label] = _input_unit(case, group, name)
    units = []
    for v, per_case in units_seen.items():
        if len(set(per_case.values())) > 1:
            chk.bad(
                "variables",
                f"'{v}' has different units in the base decks "
                f"({', '.join(f'{k}: {u}' for k, u in per_case.items())}); "
                "one value cannot mean both",
            )
        units.append(next(iter(per_case.values())))
    return _fingerprint(list(dict.fromkeys(files))), units
