"""How big the house is (a measurement to read, not a gate): Fortran procedure lengths and
argument counts, Python modules per package and import circles, private names imported
across modules, docs lines.

    .venv/bin/python tests/bench/sizes.py [--all] [--root TREE]

Prints markdown tables: the Fortran procedures over 80 lines and with more than 10 arguments
(all with --all), the largest of each, the Python packages' module counts, every import circle
among the package's modules (strongly connected components of the import graph, imports
inside functions included; also without those under ``if TYPE_CHECKING``, which never run),
the private names imported from another module and those imported across subpackages, and
the docs' line counts. ``--root`` measures the Python package of another tree (e.g. one
``git archive`` of an older commit unpacked).
"""

from __future__ import annotations

import ast
import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
START = re.compile(
    r"^\s*(?:(?:pure|elemental|recursive|impure|module)\s+)*"
    r"(?:(?:real|integer|logical|character)(?:\([^)]*\))?\s+)?(subroutine|function)\s+(\w+)\s*(\(([^)]*)\)?)?",
    re.IGNORECASE,
)
END = re.compile(r"^\s*end\s+(subroutine|function)\b", re.IGNORECASE)


def fortran_procedures(path: Path) -> list[tuple[str, int, int]]:
    """(name, lines, arguments) of every procedure in a Fortran file (internal ones too)."""
    out, stack = [], []
    lines = path.read_text().splitlines()
    i = 0
    while i < len(lines):
        line = lines[i].split("!")[0]
        m = START.match(line)
        if m and not END.match(line):
            header = line
            while header.rstrip().endswith("&") and i + 1 < len(lines):
                i += 1
                header = header.rstrip()[:-1] + lines[i].split("!")[0]
            args = re.search(r"\(([^)]*)\)", header[header.lower().find(m.group(2).lower()) :])
            nargs = len([a for a in args.group(1).split(",") if a.strip()]) if args else 0
            stack.append((m.group(2), i, nargs))
        elif END.match(line) and stack:
            name, start, nargs = stack.pop()
            out.append((name, i - start + 1, nargs))
        i += 1
    return out


def modules(package: Path) -> dict[str, Path]:
    """Dotted module name (relative to the package; a subpackage by its own name, the package
    itself as ``__init__``) -> file."""
    mods = {}
    for path in sorted(package.rglob("*.py")):
        parts = path.relative_to(package).with_suffix("").parts
        if parts[-1] == "__init__" and len(parts) > 1:
            parts = parts[:-1]
        mods[".".join(parts)] = path
    return mods


def _type_checking(node: ast.AST) -> bool:
    test = getattr(node, "test", None)
    return isinstance(node, ast.If) and (
        (isinstance(test, ast.Name) and test.id == "TYPE_CHECKING")
        or (isinstance(test, ast.Attribute) and test.attr == "TYPE_CHECKING")
    )


def imports(package: Path) -> list[tuple[str, str, str, bool]]:
    """(importer, imported module, name or '', under `if TYPE_CHECKING`) for every import of
    the package's own modules, wherever it sits (function bodies included)."""
    mods = modules(package)
    out = []
    for name, path in mods.items():
        is_pkg = path.name == "__init__.py"
        here = name.split(".") if is_pkg and name != "__init__" else name.split(".")[:-1]
        tree = ast.parse(path.read_text())
        typing_only = set()
        for node in ast.walk(tree):
            if _type_checking(node):
                typing_only |= {id(n) for b in node.body for n in ast.walk(b)}
        for node in ast.walk(tree):
            if not isinstance(node, ast.ImportFrom):
                continue
            if node.level >= 1:
                base = here[: len(here) - (node.level - 1)] if node.level > 1 else here
                target = ".".join(base + (node.module.split(".") if node.module else []))
            elif (node.module or "").startswith("ringlube."):
                target = node.module[len("ringlube.") :]
            elif node.module == "ringlube":
                target = ""
            else:
                continue
            for alias in node.names:
                sub = f"{target}.{alias.name}" if target else alias.name
                if sub in mods or alias.name == "_kernel":  # a module (the extension is one)
                    if sub in mods:
                        out.append((name, sub, "", id(node) in typing_only))
                elif (target or "__init__") in mods:
                    out.append((name, target or "__init__", alias.name, id(node) in typing_only))
    return out


def import_graph(package: Path, typing: bool = True) -> dict[str, set[str]]:
    """Module -> the package's modules it imports (anywhere in its body; with `typing`, the
    imports under `if TYPE_CHECKING` too)."""
    graph: dict[str, set[str]] = {m: set() for m in modules(package)}
    for a, b, _, typing_only in imports(package):
        if a != b and (typing or not typing_only):
            graph[a].add(b)
    return graph


def subpackage(module: str, package: Path) -> str:
    """The subpackage a module belongs to ('' for the package's top level)."""
    first = module.split(".")[0]
    return first if (package / first / "__init__.py").exists() else ""


def circles(graph: dict[str, set[str]]) -> list[list[str]]:
    """Strongly connected components with more than one module (Tarjan)."""
    index, low, on, stack, out = {}, {}, set(), [], []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in graph[v]:
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    sys.setrecursionlimit(10000)
    for v in graph:
        if v not in index:
            visit(v)
    return out


def private_imports(package: Path) -> tuple[int, list[tuple[str, str, str]]]:
    """Private names (``_x``, not modules) imported from another module: how many, and those
    that cross a subpackage's border (importer, module, name)."""
    n, across = 0, []
    for a, b, name, _ in imports(package):
        if name.startswith("_") and not name.startswith("__") and a != b:
            n += 1
            if subpackage(a, package) != subpackage(b, package):
                across.append((a, b, name))
    return n, across


def main(show_all: bool, root: Path = ROOT) -> None:
    procs = []
    for path in sorted((root / "fortran").rglob("*.f90")):
        procs += [(path.relative_to(root), *p) for p in fortran_procedures(path)]
    long = sorted((p for p in procs if p[2] > 80 or show_all), key=lambda p: -p[2])
    many = sorted((p for p in procs if p[3] > 10 or show_all), key=lambda p: -p[3])
    print(
        f"Fortran: {len(procs)} procedures, {sum(p[2] > 80 for p in procs)} over 80 lines, "
        f"{sum(p[3] > 10 for p in procs)} with more than 10 arguments\n"
    )
    print("| file | procedure | lines |\n|---|---|---|")
    for f, name, n, _ in long:
        print(f"| {f} | {name} | {n} |")
    print("\n| file | procedure | arguments |\n|---|---|---|")
    for f, name, _, a in many:
        print(f"| {f} | {name} | {a} |")
    package = Path(root) / "pydriver" / "ringlube"
    graph = import_graph(package)
    subs = sorted({subpackage(m, package) for m in graph} - {""})
    top = [m for m in graph if not subpackage(m, package)]
    print(f"\nPython: {len(graph)} modules\n\n| package | modules |\n|---|---|")
    print(f"| ringlube (top level) | {len(top)} |")
    for sub in subs:
        inside = [m for m in graph if subpackage(m, package) == sub]
        print(f"| ringlube.{sub} | {len(inside)} |")
    n, across = private_imports(package)
    print(f"\nprivate names imported from another module: {n}; across subpackages: {len(across)}")
    for a, b, name in sorted(across):
        print(f"- {a} imports {b}.{name}")
    found = circles(graph)
    runtime = circles(import_graph(package, typing=False))
    print(f"import circles: {len(found)} ({len(runtime)} without the imports under `if TYPE_CHECKING`)")
    for comp in found:
        print("- " + " <-> ".join(comp))
    print("\n| doc | lines |\n|---|---|")
    for path in [root / "README.md", *sorted((root / "docs").glob("*.md"))]:
        if path.exists():
            print(f"| {path.relative_to(root)} | {len(path.read_text().splitlines())} |")


if __name__ == "__main__":
    args = sys.argv[1:]
    main("--all" in args, Path(args[args.index("--root") + 1]) if "--root" in args else ROOT)
