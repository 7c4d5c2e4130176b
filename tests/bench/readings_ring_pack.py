"""Not a test: the readings table of docs/ring_pack.md, "The readings with the ring
pack". Every reading of docs/validation.md (film model x contact area x tension unit, the
shipped calibration, not re-fitted: Table 2 cold and hot, the four published trends on the cold
case at 5 points each) run with `&physics ring_pack` 'none' and 'gas' on the shipped decks
inputs/crf450r_4000rpm_full_cold.nml and inputs/crf450r_4000rpm_full_hot.nml, through
`ringlube.validate.compute.reading_rows` with `Case.with_physics(ring_pack=...)`. Prints the
table in markdown (each cell 'none / gas'), then the range of the blowby and of the ring's lift
share over the 'gas' cold and hot runs, and which trends each reading does not give. Nothing is
written. Run from the project folder (run time: docs/performance.md, "Run times"):

    .venv/bin/python tests/bench/readings_ring_pack.py
"""

from pathlib import Path

from ringlube import Case
from ringlube.validate.compute import reading_rows

ROOT = Path(__file__).resolve().parents[2]
DECKS = {
    "cold": ROOT / "inputs" / "crf450r_4000rpm_full_cold.nml",
    "hot": ROOT / "inputs" / "crf450r_4000rpm_full_hot.nml",
}


COLUMNS = (
    ("{:.3f}", lambda r: r["cold"].energy_loss),
    ("{:.2f}", lambda r: r["cold"].mixed_share),
    ("{:.3f}", lambda r: r["hot"].energy_loss),
    ("{:.2f}", lambda r: r["hot"].mixed_share),
    ("{}", lambda r: sum(r["verdicts"].values())),
    ("{}", lambda r: int(r["cold"].converged) + int(r["hot"].converged)),
)


def main() -> None:
    cases = {k: Case.from_namelist(p) for k, p in DECKS.items()}
    rows = {
        rp: reading_rows({k: c.with_physics(ring_pack=rp) for k, c in cases.items()})
        for rp in ("none", "gas")
    }
    print(
        "| film model | contact area | tension unit | cold energy J | cold mixed % | hot energy J "
        "| hot mixed % | trends (of 4) | conv |"
    )
    print("|---|---|---|---|---|---|---|---|---|")
    for a, b in zip(rows["none"], rows["gas"]):
        cells = [a["film"], a["area"], a["unit"]]
        cells += [f"{fmt.format(get(a))} / {fmt.format(get(b))}" for fmt, get in COLUMNS]
        print("| " + " | ".join(cells) + " |")
    gas = [r[k] for r in rows["gas"] for k in ("cold", "hot")]
    blowby = [r.blowby for r in gas]
    lift = [r.ring_lift_share for r in gas]
    print(f"\n'gas': blowby {min(blowby):.3f}-{max(blowby):.3f} L/min, ", end="")
    print(f"lift {min(lift):.2f}-{max(lift):.2f} %")
    for rp in ("none", "gas"):
        for r in rows[rp]:
            lost = [t for t, v in r["verdicts"].items() if not v]
            print(f"'{rp}' {r['film']}, {r['area']}, {r['unit']}: trends not given: {', '.join(lost) or '-'}")


if __name__ == "__main__":
    main()
