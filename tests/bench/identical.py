"""Is every result bit-identical to another build's? (A refactor changes no number.)

Runs every shipped case deck (``inputs/*.nml`` but the ``&study`` decks) and three
variants of the cold 4000 r/min deck through ``&physics`` (the mass-conserving film
flooded, starved, and with the trailing-gas cavity pressure) with two builds of
``ringlube-solve``: this tree's (``build/ringlube-solve``) and a base build, by default
one of ``HEAD`` made from ``git archive`` in a temporary folder. It compares every HDF5
dataset (values bit for bit, dtype, shape and attributes), every group and every root
attribute except the run time, and the exit status. Exit status 0 when everything is
identical, 1 otherwise.

Usage::

    python3 tests/bench/identical.py                     # base: HEAD, built here
    python3 tests/bench/identical.py --base-commit HEAD~1
    python3 tests/bench/identical.py --base-solver /path/to/ringlube-solve
    python3 tests/bench/identical.py --allow-new   # a change that adds results
    python3 tests/bench/identical.py --moves       # and how far each differing case's answers moved

A benchmark-style script (not run by the tests): it needs the kernel built (``make``) and
h5py.
"""

from __future__ import annotations

import argparse
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import h5py
import numpy as np

ROOT = Path(__file__).resolve().parents[2]
INPUTS = ROOT / "inputs"
#: root attributes that differ between two runs of the same build (run time) or between two
#: builds by definition (the kernel id, a hash of the sources)
#: (output.file: where each build wrote its file, its own folder)
SKIP_ATTRS = {"run_time_s", "kernel_id", "output.file"}
#: (name, deck, &physics settings added to the deck's own)
VARIANTS = [
    ("jfo_flooded", "crf450r_4000rpm_full_cold.nml", "cavitation = 'jfo'"),
    ("jfo_starved", "crf450r_4000rpm_full_cold.nml", "cavitation = 'jfo', inlet = 'starved'"),
    ("trailing_gas", "crf450r_4000rpm_full_cold.nml", "cavitation = 'jfo', cavity_pressure = 'trailing_gas'"),
    (
        "starved_trailing_gas_hot",
        "crf450r_4000rpm_full_hot.nml",
        "cavitation = 'jfo', inlet = 'starved', cavity_pressure = 'trailing_gas'",
    ),
    ("starved_half_hot", "crf450r_3000rpm_half_hot.nml", "cavitation = 'jfo', inlet = 'starved'"),
    ("gas_jfo_flooded", "crf450r_4000rpm_full_hot_gas.nml", "cavitation = 'jfo'"),
    ("gas_starved", "crf450r_4000rpm_full_hot_gas.nml", "cavitation = 'jfo', inlet = 'starved'"),
    # a distorted bore (order 4 beyond its conformability limit, 8 sectors): the sectors' films
    (
        "distorted_starved",
        "crf450r_4000rpm_full_cold.nml",
        "cavitation = 'jfo', inlet = 'starved', bore = 'distorted'",
    ),
]
#: groups added to a variant's deck
EXTRA = {"distorted_starved": "&bore order = 4, amplitude = 10e-6, sectors = 8 /\n"}


def case_decks() -> list[tuple[str, str, str]]:
    """The shipped case decks (not the &study decks) and the variants."""
    decks = [
        (p.stem, p.name, "")
        for p in sorted(INPUTS.glob("*.nml"))
        if "&study" not in p.read_text() and not p.name.startswith("calibration")
    ]
    return decks + VARIANTS


def build_base(commit: str, folder: Path) -> tuple[Path, str]:
    """``ringlube-solve`` of `commit`, built in `folder` (git archive + CMake)."""
    sha = subprocess.run(
        ["git", "-C", str(ROOT), "rev-parse", commit], check=True, capture_output=True, text=True
    ).stdout.strip()
    src = folder / "src"
    src.mkdir()
    archive = subprocess.run(["git", "-C", str(ROOT), "archive", sha], check=True, capture_output=True)
    subprocess.run(["tar", "-x", "-C", str(src)], input=archive.stdout, check=True)
    build = folder / "build"
    subprocess.run(
        [
            "cmake",
            "-S",
            str(src),
            "-B",
            str(build),
            "-G",
            "Ninja",
            "-DCMAKE_BUILD_TYPE=Release",
            "-DRINGLUBE_TESTS=OFF",
        ],
        check=True,
        capture_output=True,
    )
    target = ["--target", "ringlube-solve"]
    subprocess.run(["cmake", "--build", str(build), *target], check=True, capture_output=True)
    return build / "ringlube-solve", sha[:12]


def write_deck(folder: Path, deck: str, physics: str, extra: str = "") -> Path:
    """A copy of the shipped `deck` (with its calibration file and traces) in `folder`,
    with `physics` added to its &physics group and the groups `extra` at its end."""
    if not (folder / "pressure").exists():
        shutil.copytree(INPUTS / "pressure", folder / "pressure")
        shutil.copy(INPUTS / "calibration.nml", folder / "calibration.nml")
    text = (INPUTS / deck).read_text()
    if physics:
        # the group itself, at the start of a line (a comment may name it too)
        text, n = re.subn(r"^(\s*)&physics\b", rf"\1&physics {physics},", text, count=1, flags=re.M)
        assert n == 1, deck
    text += extra
    path = folder / f"{Path(deck).stem}{'_' + re.sub(r'[^a-z]+', '_', physics) if physics else ''}.nml"
    path.write_text(text)
    return path


def items(f: h5py.File) -> dict[str, object]:
    """Every group, dataset and attribute of a file by path ('/cycle/h0_m', '/cycle/h0_m@units');
    object references (the dimension scales' lists) as the names they point to."""
    out: dict[str, object] = {}

    def plain(v):
        if isinstance(v, h5py.Reference):
            return ("ref", f[v].name if v else None)
        if isinstance(v, np.void):  # a compound (REFERENCE_LIST: dataset, index)
            return tuple(plain(x) for x in v.tolist())
        if isinstance(v, np.ndarray) and (v.dtype.kind in "OV"):
            return ("array", v.shape, tuple(plain(x) for x in v.flat))
        if isinstance(v, tuple):
            return tuple(plain(x) for x in v)
        return v

    def attrs(path: str, obj) -> None:
        for k, v in obj.attrs.items():
            if path == "/" and k in SKIP_ATTRS:
                continue
            out[f"{path}@{k}"] = plain(v)

    def visit(name: str, obj) -> None:
        path = "/" + name
        out[path] = obj[()] if isinstance(obj, h5py.Dataset) else "group"
        attrs(path, obj)

    attrs("/", f)
    f.visititems(visit)
    return out


def same(a, b) -> bool:
    """Bit for bit: same type, shape and bytes (a NaN equals the same NaN); references
    (made plain by `items`) by what they point to."""
    if isinstance(a, tuple) or isinstance(b, tuple):
        return a == b
    a, b = np.asarray(a), np.asarray(b)
    return a.dtype == b.dtype and a.shape == b.shape and a.tobytes() == b.tobytes()


def compare(a: Path, b: Path, allow_new: bool = False) -> tuple[int, list[str], list[str]]:
    """Number of items compared, the paths that differ (or exist in one file only) and, with
    `allow_new`, the paths only `b` has (not counted as differences)."""
    with h5py.File(a) as fa, h5py.File(b) as fb:
        ia, ib = items(fa), items(fb)
    new = sorted(set(ib) - set(ia)) if allow_new else []
    if new:
        # a new dataset on a dimension scale adds itself to the scale's REFERENCE_LIST: the
        # list is compared without the new datasets' entries
        for k in set(ia) & set(ib):
            if k.endswith("@REFERENCE_LIST") and isinstance(ib[k], tuple) and ib[k][0] == "array":
                kept = tuple(e for e in ib[k][2] if not (e and e[0] and e[0][1] in new))
                ib[k] = ("array", (len(kept),), kept)
    differ = sorted((set(ia) ^ set(ib)) - set(new))
    differ += [k for k in sorted(set(ia) & set(ib)) if not same(ia[k], ib[k])]
    return len(set(ia) & set(ib)) if allow_new else len(set(ia) | set(ib)), differ, new


#: the answers --moves reports (root attributes), relative to the base's (the mixed share in points)
MOVES = ("energy_loss_J", "blowby_l_min", "oil_to_chamber_mm3", "mixed_share_pct")


def moves(a: Path, b: Path) -> str:
    """The base's (a) and the new (b) cycles computed and period, and each of MOVES's change
    from a to b in units of the base's cycle_tol (relative; the mixed share in points over
    100 cycle_tol)."""
    with h5py.File(a) as fa, h5py.File(b) as fb:
        ra, rb = dict(fa.attrs), dict(fb.attrs)
    tol = float(ra.get("numerics.cycle_tol", 1e-3))
    text = [
        f"cycles computed {float(ra['cycles_computed']):.2f} -> {float(rb['cycles_computed']):.2f}, "
        f"period {int(ra['period'])} -> {int(rb['period'])}"
    ]
    for k in MOVES:
        if k not in ra or k not in rb:
            continue
        x, y = float(ra[k]), float(rb[k])
        if k == "mixed_share_pct":
            text.append(f"{k} {(y - x) / (100 * tol):+.3f} tol")
        elif x != 0:
            text.append(f"{k} {(y / x - 1) / tol:+.3f} tol")
    return "; ".join(text)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    here = str(ROOT / "build" / "ringlube-solve")
    parser.add_argument("--solver", default=here, help="the build under test")
    parser.add_argument("--base-solver", help="an existing base build (instead of building --base-commit)")
    parser.add_argument("--base-commit", default="HEAD", help="the commit to build as the base")
    parser.add_argument(
        "--moves",
        action="store_true",
        help="for each case that differs: its cycles and how far its answers moved, in cycle_tol",
    )
    parser.add_argument(
        "--allow-new",
        action="store_true",
        help="items only the new build writes (added results) are listed, not counted as differences",
    )
    args = parser.parse_args(argv)
    with tempfile.TemporaryDirectory(prefix="ringlube_identical_") as tmp:
        tmp = Path(tmp)
        if args.base_solver:
            base, label = Path(args.base_solver), args.base_solver
        else:
            print(f"building {args.base_commit} ...", flush=True)
            (tmp / "base").mkdir()
            base, label = build_base(args.base_commit, tmp / "base")
        print(f"base: {label}\nnew:  {args.solver}\n")
        print(f"{'case':<34} {'exit':>9} {'items':>6}  identical")
        bad = 0
        added: set[str] = set()
        for name, deck, physics in case_decks():
            path = write_deck(tmp, deck, physics, EXTRA.get(name, ""))
            runs = []
            for tag, solver in (("base", base), ("new", args.solver)):
                out = tmp / f"{name}.{tag}.h5"
                cmd = [str(solver), "-q", str(path), "-o", str(out)]
                runs.append((subprocess.run(cmd, capture_output=True).returncode, out))
            (rc_a, out_a), (rc_b, out_b) = runs
            if out_a.exists() and out_b.exists():
                n, differ, new = compare(out_a, out_b, args.allow_new)
            else:
                n, differ, new = 0, ["(no file)"], []
            added.update(new)
            ok = rc_a == rc_b and not differ
            bad += not ok
            print(f"{name:<34} {rc_a:>4}/{rc_b:<4} {n:>6}  {'yes' if ok else 'NO: ' + ', '.join(differ[:6])}")
            if args.moves and not ok and out_a.exists() and out_b.exists():
                print(f"{'':<34} {moves(out_a, out_b)}")
        verdict = "all identical" if not bad else f"{bad} case(s) differ"
        print(f"\n{verdict} (root attributes but {sorted(SKIP_ATTRS)})")
        if added:
            print(f"only in the new files ({len(added)}): {', '.join(sorted(added))}")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
