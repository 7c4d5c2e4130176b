"""film_copy (fortran/src/film_state.f90) names every component of film_type and of the
solvers' workspaces it holds, and so does its test (tests/fortran/test_film_copy.f90: `fill`
sets each, `compare` compares each): a component added to one of these types without a line
in the copy would leave the copy's value behind, which the Fortran test cannot see unless it
sets that component."""

from __future__ import annotations

import re

import pytest

from conftest import ROOT

pytestmark = pytest.mark.unit

SRC = ROOT / "fortran" / "src"
TEST = ROOT / "tests" / "fortran" / "test_film_copy.f90"


def _strip(text: str) -> str:
    """Fortran source without comments, with continuation lines joined."""
    lines = [line.split("!")[0].rstrip() for line in text.splitlines()]
    return re.sub(r"&\s*\n\s*&?", " ", "\n".join(lines))


def _split(decl: str) -> list[str]:
    """The entities of a declaration's entity list (commas outside parentheses)."""
    parts, depth, cur = [], 0, ""
    for ch in decl:
        depth += ch in "(["
        depth -= ch in ")]"
        if ch == "," and depth == 0:
            parts.append(cur)
            cur = ""
        else:
            cur += ch
    return [*parts, cur]


def _types() -> dict[str, list[tuple[str, str | None, bool]]]:
    """Every derived type of the kernel: its components as (name, type name if derived,
    allocatable)."""
    types = {}
    for path in SRC.glob("*.f90"):
        text = _strip(path.read_text())
        for m in re.finditer(r"^\s*type\s*::\s*(\w+)\s*\n(.*?)^\s*end type", text, re.M | re.S | re.I):
            comps = []
            for line in m.group(2).splitlines():
                if "::" not in line:
                    continue
                spec, decl = line.split("::", 1)
                derived = re.match(r"\s*type\((\w+)\)", spec, re.I)
                alloc = "allocatable" in spec.lower()
                for ent in _split(decl):
                    name = re.match(r"\s*(\w+)", ent).group(1)
                    comps.append((name.lower(), derived.group(1).lower() if derived else None, alloc))
            types[m.group(1).lower()] = comps
    return types


def _leaves(types, name: str, prefix: str = "") -> list[str]:
    """The paths of the non-derived components under type `name` (a%b%c)."""
    out = []
    for comp, derived, _ in types[name]:
        if derived:
            out += _leaves(types, derived, f"{prefix}{comp}%")
        else:
            out.append(prefix + comp)
    return out


def _body(text: str, kind: str, name: str) -> str:
    m = re.search(rf"^\s*(pure )?{kind} {name}\b.*?^\s*end {kind} {name}", text, re.M | re.S | re.I)
    assert m, f"no {kind} {name}"
    return m.group(0).lower()


def test_the_types_are_read():
    types = _types()
    assert ("jfo_scratch", "jfo_scratch", False) in types["film_type"]
    assert "jfo_scratch%ev%ju" in _leaves(types, "film_type")
    assert "contact%circumference" in _leaves(types, "film_type")


def test_film_copy_names_every_component():
    types = _types()
    text = _strip((SRC / "film_state.f90").read_text())
    film_copy = _body(text, "subroutine", "film_copy")
    # a derived component without allocatable parts may be assigned whole; the others part
    # by part, in film_copy or in its helper for that type
    helpers = {"jfo_system": "copy_system", "jfo_scratch": "copy_scratch"}

    def has_alloc(t):
        return any(a or (d and has_alloc(d)) for _, d, a in types[t])

    missing = []
    for comp, derived, _ in types["film_type"]:
        if derived in helpers:
            body = _body(text, "subroutine", helpers[derived])
            assert f"dst%{comp}" in film_copy
            leaves = _leaves(types, derived)
            missing += [f"{comp}%{leaf}" for leaf in leaves if f"dst%{leaf}" not in body]
        elif derived and has_alloc(derived):
            leaves = [f"{comp}%{leaf}" for leaf in _leaves(types, derived)]
            missing += [leaf for leaf in leaves if f"dst%{leaf}" not in film_copy]
        elif f"dst%{comp} " not in film_copy and f"dst%{comp}," not in film_copy:
            missing.append(comp)
    assert not missing, f"film_copy does not copy {missing}"


def test_the_fortran_test_sets_and_compares_every_component():
    types = _types()
    text = _strip(TEST.read_text())
    fill = _body(text, "subroutine", "fill")
    compare = _body(text, "subroutine", "compare")
    leaves = _leaves(types, "film_type")
    assert len(leaves) > 100
    unset = [p for p in leaves if not re.search(rf"\bf%{p}\b", fill)]
    assert not unset, f"fill does not set {unset}"
    uncompared = [p for p in leaves if not re.search(rf"\ba%{p}\b", compare)]
    assert not uncompared, f"compare does not compare {uncompared}"
