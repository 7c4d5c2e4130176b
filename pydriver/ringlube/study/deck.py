"""The ``&study`` deck, read and checked.

:func:`read_study` reads a study deck into a :class:`~ringlube.study.settings.StudySettings`
and checks every value (each error names the file, ``&study`` and the variable), checks each
design variable against every base deck with the kernel's own reader, and fingerprints the
content of every input file (base decks, the calibration files they include, their pressure
traces) so that a study is never resumed on changed inputs.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

from ..case import Case
from ..errors import InputError, input_file
from .constraints import parse_constraint
from .settings import StudySettings
from .table import MAX_SAMPLES, STUDY, study_values
from .variables import (
    DEFAULT_GROUP,
    DESIGN_RANGES,
    _fingerprint,
    _input_unit,
    _is_unknown_variable,
    _is_whole_number,
    _model_units,
    _produces,
    _text_input,
    input_files,
    split_variable,
)

__all__ = ["read_study", "MAX_SAMPLES"]


def _given(s: dict, name: str) -> Any:
    """The value of ``&study name``: the deck's, else the table's default."""
    return s[name] if name in s else STUDY[name].default


class _Checker:
    """Errors naming the deck, the line of the variable (when the deck gives it), ``&study``
    and the variable."""

    def __init__(self, path: Path, lines: dict[str, int]):
        self.path = path
        self.lines = lines

    def bad(self, var: str, why: str):
        where = f"{self.path}:{self.lines[var]}" if var in self.lines else str(self.path)
        raise InputError(f"{where}: &study {var}: {why}")

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
    path = input_file(path)
    text = path.read_bytes().decode("utf-8", "surrogateescape")
    s, lines = study_values(path, text)  # the kernel's scanner, typed by the &study table
    chk = _Checker(path, lines)
    for row in STUDY.values():
        if row.required and row.name not in s:
            chk.bad(row.name, "required (one or more base decks)")
    cases = [str((path.parent / c).resolve()) for c in s["cases"]]
    labels = s.get("labels", [Path(c).stem for c in cases])
    weights = s.get("weights", [1.0] * len(cases))
    variables = s.get("variables", list(DESIGN_RANGES))
    objectives = list(_given(s, "objectives"))
    ints = {k: s[k] for k, row in STUDY.items() if row.kind == "integer" and k in s}

    name = s.get("name", path.stem)
    chk.plain_name("name", name, "the study file")
    for label in labels:
        chk.plain_name("labels", label, "a group of the study file and its figures")
    if len(labels) != len(cases) or len(set(labels)) != len(labels):
        chk.bad("labels", f"one distinct label per case ({len(cases)} cases)")
    if "scene" in labels:
        chk.bad("labels", "'scene' is reserved for the weighted scene")
    if len(weights) != len(cases) or any(w <= 0 for w in weights):
        chk.bad("weights", f"one positive weight per case ({len(cases)} cases)")
    if not all(w / max(weights) > 0 for w in weights):
        chk.bad("weights", f"{min(weights):g} is 0 beside {max(weights):g} in floating point")

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
        if _text_input(group, name_):
            chk.bad(
                "variables",
                f"'{v}' is not a number (&{group} {name_} takes {_text_input(group, name_)}); "
                "a study samples real values: vary it with one base deck per value instead",
            )
        pairs.append((group, name_))
    if len(set(pairs)) != len(pairs):
        chk.bad("variables", "a variable is given twice")
    lower, upper = _bounds(chk, s, variables, pairs)
    if any(lo >= hi for lo, hi in zip(lower, upper)):
        chk.bad("upper", "each upper bound must exceed its lower bound")
    reference = s.get("reference")
    if reference is not None:
        if len(reference) != len(variables):
            chk.bad("reference", f"one value per variable ({len(variables)})")

    constraints = []
    for text in _given(s, "constraints"):
        try:
            c = parse_constraint(text)
        except ValueError as exc:
            chk.bad("constraints", str(exc))
        if c.uses_reference and reference is None:
            chk.bad("constraints", f"'{text}' is bounded by the reference design: give &study reference")
        scene = _given(s, "scene") and len(labels) > 1
        if c.at is not None and c.at not in labels and not (c.at == "scene" and scene):
            chk.bad(
                "constraints",
                f"'{text}': at '{c.at}' is not a case label ({', '.join(labels)})"
                + (" nor the scene" if scene else "; 'at scene' needs scene = .true. and two cases or more"),
            )
        constraints.append(str(c))
    if len(set(constraints)) != len(constraints):
        chk.bad("constraints", "a constraint is given twice")

    units = _model_units()
    for o in objectives:
        if o not in units:
            chk.bad("objectives", f"unknown objective '{o}' (known: {', '.join(units)})")
    weighting = _given(s, "weighting")
    if not objectives or len(set(objectives)) != len(objectives):
        chk.bad("objectives", "one or more distinct objectives")
    sampler, surrogate = _given(s, "sampler"), _given(s, "surrogate")

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
        weighting=weighting,
        **ints,
        deck_text=path.read_text(errors="replace"),  # as stored in study files so far
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
    if weighting == "time":
        if ("operating", "speed_rpm") in pairs:
            chk.bad(
                "weighting",
                "'time' weighs results per cycle by each case's cycles per second: "
                "operating:speed_rpm cannot be a design variable then",
            )
        speeds = [float(Case.from_namelist(deck).value("operating", "speed_rpm")) for deck in cases]
        st.cycle_rates = [n / 120 for n in speeds]
    from ..tables import MODELS, SCALARS

    for var, o in [("objectives", o) for o in objectives] + [
        ("constraints", c.name) for c in st.parsed_constraints
    ]:
        req = SCALARS[o].requires if o in SCALARS else ""
        if req and o not in st.outputs:
            m = MODELS[req]  # the kernel's table: which input selects the model
            need = f"&{m.group} {m.variable} = '{m.value}'"
            for deck in cases:
                if not _produces(Case.from_namelist(deck), req):
                    chk.bad(var, f"'{o}' needs {need} in every base deck ({deck} has not)")
        if o not in st.outputs:
            st.outputs.append(o)  # constrained results are recorded (and fitted) too
    # the branch-risk margins of every design (lift_margin is one of every study's outputs;
    # seal_margin where every base deck makes it): a design near a change of state is marked in
    # the report (docs/model.md, "Branch risk")
    from ..tables import MARGINS

    for o in MARGINS:
        req = SCALARS[o].requires
        if o not in st.outputs and all(_produces(Case.from_namelist(d), req) for d in cases):
            st.outputs.append(o)
    return st


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
        lower, upper = s["lower"], s["upper"]
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
        if not Path(deck).is_file():  # (a base deck's own errors name its own file and line)
            chk.bad("cases", f"base deck '{label}': {deck}: file not found")
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
