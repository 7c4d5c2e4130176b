"""How big the house is (a measurement to read, not a gate): Fortran procedure lengths and
argument counts, Python modules per package and import circles, private names imported
across modules, docs lines.

    .venv/bin/python tests/bench/sizes.py [--all]

Prints markdown tables: the Fortran procedures over 80 lines and with more than 10 arguments
(all with --all), the largest of each, the Python packages' module counts, every import circle
among the package's modules (strongly connected components of the import graph, imports
inside functions included) and the docs' line counts.
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


def import_graph(package: Path) -> dict[str, set[str]]:
    """Module -> the package's modules it imports (anywhere in its body)."""
    mods = {p.stem: p for p in package.glob("*.py")}
    for sub in package.iterdir():
        if sub.is_dir() and (sub / "__init__.py").exists():
            for p in sub.glob("*.py"):
                mods[f"{sub.name}.{p.stem}"] = p
    graph: dict[str, set[str]] = {}
    for name, path in mods.items():
        here = name.rsplit(".", 1)[0] if "." in name else ""
        deps = set()
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.ImportFrom) and node.level >= 1:
                base = node.module or ""
                if node.level == 2 or not here:
                    prefix = ""
                else:
                    prefix = here + "."
                target = (prefix + base) if base else here
                for alias in node.names:
                    for cand in (f"{target}.{alias.name}" if target else alias.name, target):
                        if cand in mods and cand != name:
                            deps.add(cand)
                            break
            elif isinstance(node, ast.ImportFrom) and (node.module or "").startswith("ringlube."):
                cand = node.module[len("ringlube.") :]
                if cand in mods and cand != name:
                    deps.add(cand)
        graph[name] = deps
    return graph


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


def private_imports(package: Path) -> int:
    """`from .x import _name` across modules."""
    n = 0
    for path in package.rglob("*.py"):
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.ImportFrom) and node.level >= 1:
                n += sum(1 for a in node.names if a.name.startswith("_") and not a.name.startswith("__"))
    return n


def main(show_all: bool) -> None:
    procs = []
    for path in sorted((ROOT / "fortran").rglob("*.f90")):
        procs += [(path.relative_to(ROOT), *p) for p in fortran_procedures(path)]
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
    package = ROOT / "pydriver" / "ringlube"
    graph = import_graph(package)
    subs = sorted({m.split(".")[0] for m in graph if "." in m})
    print(
        f"\nPython: {len(graph)} modules ({sum('.' not in m for m in graph)} at the top"
        + "".join(f", {sum(m.startswith(s + '.') for m in graph)} in {s}" for s in subs)
        + f"); private names imported across modules: {private_imports(package)}"
    )
    found = circles(graph)
    print(f"import circles: {len(found)}")
    for comp in found:
        print("- " + " <-> ".join(comp))
    print("\n| doc | lines |\n|---|---|")
    for path in [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]:
        print(f"| {path.relative_to(ROOT)} | {len(path.read_text().splitlines())} |")


if __name__ == "__main__":
    main("--all" in sys.argv)
