"""How often runs converge, over random designs and over the corners of the inputs (a hostile
sweep; docs/performance.md, "Convergence over the design space", which gives its run time).

Seeded and reproducible. Part ``a``: 250 random designs at preset 'default' on the 4000 r/min
cold and hot decks (width 0.40-1.60 mm, tension 0-40 N/m, speed log-uniform 1000-12,000 r/min,
one of five film models, ring pack on or off). Part ``b``: 330 stratified corner runs (widths
0.3 / 1.004 / 2 mm, tensions 0 / 8 / 40 N/m, 1000 / 4000 / 12,000 r/min, 0.25-4 deg, 31-201
nodes; 33 per film model and ring pack) and 50 runs on the 12,000 r/min hot 'gas' deck.

    .venv/bin/python tests/bench/convergence_sweep.py a out/sweep_a.jsonl
    .venv/bin/python tests/bench/convergence_sweep.py b out/sweep_b.jsonl
    .venv/bin/python tests/bench/convergence_sweep.py --table out/sweep_a.jsonl out/sweep_b.jsonl

Each run goes to a worker process (one at a time), so a crash is recorded, not fatal; results
are appended line by line and a re-started sweep skips the runs already in its file.
"""

from __future__ import annotations

import argparse
import collections
import concurrent.futures as cf
import itertools
import json
import math
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
INPUTS = ROOT / "inputs"
DECKS = {
    "cold": INPUTS / "crf450r_4000rpm_full_cold.nml",
    "hot": INPUTS / "crf450r_4000rpm_full_hot.nml",
    "hot12k_gas": INPUTS / "crf450r_12000rpm_full_hot_gas.nml",
}
FILMS = {
    "ss": dict(cavitation="swift_stieber"),
    "fl_vap": dict(cavitation="jfo", inlet="flooded", cavity_pressure="vapour"),
    "fl_tg": dict(cavitation="jfo", inlet="flooded", cavity_pressure="trailing_gas"),
    "st_vap": dict(cavitation="jfo", inlet="starved", cavity_pressure="vapour"),
    "st_tg": dict(cavitation="jfo", inlet="starved", cavity_pressure="trailing_gas"),
}


def _spec(id_, deck, film, rp, ring, operating, numerics):
    return dict(id=id_, deck=deck, film=film, ring_pack=rp, ring=ring, operating=operating, numerics=numerics)


def part_a(n=250, seed=20261126):
    rng = np.random.default_rng(seed)
    out = []
    for i in range(n):
        deck = ["cold", "hot"][rng.integers(2)]
        width = float(np.round(rng.uniform(0.40e-3, 1.60e-3), 7))
        tension = float(np.round(rng.uniform(0.0, 40.0), 3))
        speed = float(np.round(np.exp(rng.uniform(np.log(1000), np.log(12000)))))
        film = list(FILMS)[rng.integers(5)]
        rp = ["none", "gas"][rng.integers(2)]
        out.append(
            _spec(f"A{i:03d}", deck, film, rp, dict(width=width, tension=tension), dict(speed_rpm=speed), {})
        )
    return out


def part_b(n=330, seed=20261127):
    rng = np.random.default_rng(seed)
    grid = list(
        itertools.product(
            ["cold", "hot"],
            [0.3e-3, 1.004e-3, 2.0e-3],
            [0.0, 8.0, 40.0],
            [1000.0, 4000.0, 12000.0],
            list(FILMS),
            ["none", "gas"],
            [0.25, 0.5, 1.0, 2.0, 4.0],
            [31, 51, 101, 201],
        )
    )
    out = []
    cells = list(itertools.product(list(FILMS), ["none", "gas"]))
    for film, rp in cells:
        sub = [g for g in grid if g[4] == film and g[5] == rp]
        for j in rng.choice(len(sub), size=n // len(cells), replace=False):
            d, w, t, sp, f, r, dp, nd = sub[j]
            out.append(
                _spec(
                    f"B{len(out):03d}",
                    d,
                    f,
                    r,
                    dict(width=w, tension=t),
                    dict(speed_rpm=sp),
                    dict(dpsi_deg=dp, nodes=nd),
                )
            )
    for film, dp, nd in itertools.product(list(FILMS), [0.25, 1.0, 4.0], [31, 201]):
        out.append(_spec(f"C{len(out):03d}", "hot12k_gas", film, "gas", {}, {}, dict(dpsi_deg=dp, nodes=nd)))
    for film, w, t in itertools.product(list(FILMS), [0.3e-3, 2.0e-3], [0.0, 40.0]):
        out.append(
            _spec(
                f"C{len(out):03d}",
                "hot12k_gas",
                film,
                "gas",
                dict(width=w, tension=t),
                {},
                dict(dpsi_deg=0.5, nodes=101),
            )
        )
    return out


def run_one(spec: dict) -> dict:
    """One run: its status, period, cycles, energy and the flags of the reported cycle."""
    import ringlube
    from ringlube.tables import FLAGS

    c = ringlube.Case.from_namelist(DECKS[spec["deck"]])
    if spec["ring"]:
        c = c.with_ring(**spec["ring"])
    if spec["operating"]:
        c = c.with_operating(**spec["operating"])
    c = c.with_physics(**FILMS[spec["film"]], ring_pack=spec["ring_pack"]).with_numerics(**spec["numerics"])
    try:
        r = ringlube.run(c)
    except ringlube.RinglubeError as exc:
        return dict(id=spec["id"], ok=False, error=str(exc).splitlines()[0])
    flags = int(np.bitwise_or.reduce(np.asarray(r.flags, dtype=np.int64)))
    finite = all(math.isfinite(float(v)) for v in r.scalars.values())
    return dict(
        id=spec["id"],
        ok=True,
        converged=bool(r.converged),
        periodic=bool(r.periodic),
        period=int(r.period),
        cycles_run=int(r.cycles_run),
        energy=float(r.energy_loss),
        finite=finite,
        flags=[n for n, b in FLAGS.items() if flags & b and n != "h0_ceiling"],
    )


def sweep(part: str, out: Path) -> None:
    specs = part_a() if part == "a" else part_b()
    done = set()
    if out.exists():
        done = {json.loads(line)["id"] for line in out.read_text().splitlines() if line.strip()}
    todo = [s for s in specs if s["id"] not in done]
    out.parent.mkdir(parents=True, exist_ok=True)
    pool = cf.ProcessPoolExecutor(max_workers=1)
    with out.open("a") as f:
        for i, s in enumerate(todo):
            try:
                rec = pool.submit(run_one, s).result()
            except cf.process.BrokenProcessPool:
                rec = dict(id=s["id"], ok=False, error="the worker process died (a crash)")
                pool = cf.ProcessPoolExecutor(max_workers=1)
            rec.update(film=s["film"], ring_pack=s["ring_pack"])
            f.write(json.dumps(rec) + "\n")
            f.flush()
            print(f"{i + 1}/{len(todo)} {s['id']} {rec.get('converged', rec.get('error'))}", flush=True)
    pool.shutdown()


def table(files: list[Path]) -> None:
    rows = collections.defaultdict(collections.Counter)
    for path in files:
        for line in path.read_text().splitlines():
            r = json.loads(line)
            key = (r["film"], r["ring_pack"])
            if not r["ok"]:
                rows[key]["error"] += 1
                continue
            status = "converged" if r["converged"] else "flagged" if r["periodic"] else "not periodic"
            rows[key][status] += 1
            rows[key][f"period {r['period']}"] += 1 if r["period"] >= 2 else 0
            rows[key]["non-finite"] += 0 if r["finite"] else 1
    cols = ["converged", "flagged", "not periodic", "error", "non-finite"] + [
        f"period {p}" for p in range(2, 13)
    ]
    cols = [c for c in cols if any(rows[k][c] for k in rows) or not c.startswith("period")]
    print("| film | ring pack | " + " | ".join(cols) + " |")
    print("|---|---|" + "---:|" * len(cols))
    for key in sorted(rows):
        print(f"| {key[0]} | {key[1]} | " + " | ".join(str(rows[key][c]) for c in cols) + " |")


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("part", nargs="?", choices=["a", "b"])
    ap.add_argument("out", nargs="?", type=Path)
    ap.add_argument("--table", nargs="+", type=Path, help="print the counts of result files")
    a = ap.parse_args()
    if a.table:
        table(a.table)
    elif a.part and a.out:
        sweep(a.part, a.out)
    else:
        ap.error("give a part and an output file, or --table FILES")
