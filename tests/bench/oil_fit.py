"""The kernel's viscosity law put through an oil's kinematic viscosities at 40 and 100 degC
(a data sheet's, or an SAE J300 grade's) against the Walther equation of ASTM D341 through
the same two points, at other temperatures (the table of docs/model.md, "Viscosity").

Usage::

    .venv/bin/python tests/bench/oil_fit.py

Prints a markdown table: kinematic viscosity [mm^2/s] of both, and their difference.
"""

from __future__ import annotations

import ringlube
from ringlube import oil

TEMPERATURES_C = (20, 60, 80, 120, 150)


def main() -> None:
    oils = [("source study (eta0 0.05 Pa s, beta 0.04 1/K)", ringlube.Case())]
    grades = ("0W-20", "5W-30", "5W-40", "15W-40")
    oils += [(f"grade {g}", ringlube.Case({"lubricant": {"grade": g}})) for g in grades]
    head = " | ".join(f"{t} °C" for t in TEMPERATURES_C)
    print(f"| oil | kv40 | kv100 | {head} |")
    print("|---|---|---|" + "---|" * len(TEMPERATURES_C))
    for name, case in oils:
        kv40, kv100 = oil.kinematic_viscosity(case, [313.15, 373.15])
        t = [tc + 273.15 for tc in TEMPERATURES_C]
        roelands = oil.kinematic_viscosity(case, t)
        walther = oil.walther(kv40, kv100, t)
        cells = " | ".join(f"{r:.2f} / {w:.2f} ({r / w - 1:+.1%})" for r, w in zip(roelands, walther))
        print(f"| {name} | {kv40:.2f} | {kv100:.2f} | {cells} |")


if __name__ == "__main__":
    main()
