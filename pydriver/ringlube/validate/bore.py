"""The bore-distortion section of ``docs/validation.md``, computed and rendered.

:func:`bore_validation` runs the shipped distorted decks (``inputs/crf450r_*_distorted.nml``)
and the same decks on a round bore over the tension and a narrow and a wide ring;
:func:`render_bore` turns the runs into the section's Markdown (the published criteria it is
compared with are text; every number from a run or from the closed-form limit).
"""

from __future__ import annotations

import os
from pathlib import Path

from ..case import Case
from ..solve import run_many

__all__ = [
    "BORE_DECKS",
    "BORE_TENSIONS",
    "BORE_WIDTHS",
    "bore_validation",
    "conformability_limit",
    "render_bore",
]

#: The shipped distorted decks (in inputs/) and the engine each is: the CRF450R at 4000 and
#: 12,000 r/min and the own 86 x 86 mm engine of docs/own_engine.md at 3000 r/min.
BORE_DECKS = (
    ("CRF450R", "crf450r_4000rpm_full_hot_distorted.nml"),
    ("CRF450R", "crf450r_12000rpm_full_hot_distorted.nml"),
    ("86 x 86", "own86_3000rpm_full_distorted.nml"),
)
#: Tensions [N] swept at the deck's width at every speed (the bore study's range, 8-26 N).
BORE_TENSIONS = (8.0, 11.0, 14.0, 18.0, 26.0)
#: Narrow and wide rings [m] (the study's range) at the lowest and highest tension, first deck.
BORE_WIDTHS = (0.54e-3, 1.34e-3)


def round_bore(case: Case) -> Case:
    """The case on a round bore: ``&physics bore = 'round'`` and no ``&bore`` group."""
    groups = case.to_dict()
    groups.pop("bore", None)
    groups.setdefault("physics", {})["bore"] = "round"
    return Case(groups, name=f"{case.name}_round")


def conformability_limit(case: Case, width: float, tension: float) -> dict[int, float]:
    """The classical conformability limit [m] per order of the case's ``&bore`` (docs/bore.md):
    q r0^4 / (E I (k^2 - 1)^2), q = p_e b the tension's line load, I = b d^3 / 12, the tension
    read as the case reads it (N: p_e = F_T / (b r0); N/m: p_e = F / b).

    Parameters
    ----------
    case : Case
        A case with a ``&bore`` group (its orders), its engine, ring and surface.
    width : float
        Ring width b [m].
    tension : float
        Tension in the case's reading.

    Returns
    -------
    dict
        {order k: limit [m]}.

    Examples
    --------
    >>> from ringlube import Case
    >>> c = Case.from_namelist("inputs/crf450r_4000rpm_full_hot_distorted.nml")  # doctest: +SKIP
    >>> round(conformability_limit(c, 1.004e-3, 8.0)[4] * 1e6, 2)  # doctest: +SKIP
    5.4
    """
    r0 = case.value("engine", "bore_radius")
    e = case.value("surface", "e_ring")
    d = case.value("ring", "radial_depth")
    q = tension / r0 if case.value("ring", "tension_unit") == "N" else tension
    ei = e * width * d**3 / 12.0
    return {int(k): q * r0**4 / (ei * (k * k - 1) ** 2) for k in case.value("bore", "order")}


def bore_validation(root: str | os.PathLike = ".", adjust=None) -> dict:
    """Run the bore section: each deck of :data:`BORE_DECKS` as shipped and on a round bore,
    over :data:`BORE_TENSIONS` at the deck's width, and (first deck) the widths of
    :data:`BORE_WIDTHS` at the lowest and highest tension.

    Parameters
    ----------
    root : path
        Project folder (with ``inputs/``).
    adjust : callable, optional
        Applied to each distorted deck before anything is run (a test makes them coarse).

    Returns
    -------
    dict
        'bases': {(engine, speed): distorted Case}; 'rows': [(engine, speed, bore, width m,
        tension N, result or error)] in table order.

    Examples
    --------
    >>> bore = bore_validation(".")  # doctest: +SKIP
    >>> bore["rows"][0][:5]  # doctest: +SKIP
    ('CRF450R', 4000, 'round', 0.001004, 8.0)
    """
    bases, keys, cases = {}, [], []
    for i, (engine, name) in enumerate(BORE_DECKS):
        base = Case.from_namelist(Path(root) / "inputs" / name)
        base = adjust(base) if adjust else base
        speed = int(round(base.value("operating", "speed_rpm")))
        bases[engine, speed] = base
        w0 = base.value("ring", "width")
        rings = [(w0, t) for t in BORE_TENSIONS]
        if i == 0:
            rings += [(w, t) for w in BORE_WIDTHS for t in (BORE_TENSIONS[0], BORE_TENSIONS[-1])]
        for bore in ("round", "distorted"):
            for w, t in rings:
                case = base.with_ring(width=w, tension=t)
                keys.append((engine, speed, bore, w, t))
                cases.append(round_bore(case) if bore == "round" else case)
    results = run_many(cases, workers=1, progress=False, on_error="return")
    return {"bases": bases, "rows": [(*k, r) for k, r in zip(keys, results)]}


def _ok(r) -> bool:
    return hasattr(r, "energy_loss")


def _ring(w: float, t: float) -> str:
    return f"{w * 1e3:.4g} mm, {t:g} N"


def _row(engine, speed, bore, w, t, r) -> str:
    if not _ok(r):
        return (
            f"| {engine} | {speed} | {bore} | {_ring(w, t)} | failed: {str(r).splitlines()[0]} |" + " |" * 11
        )
    s, d = r.scalars, bore == "distorted"

    def b(name: str, fmt: str) -> str:
        return format(s[name], fmt) if d else "-"

    # (a step held at the ceiling is flagged but no failure: a run without a period says so)
    why = f"{r.flagged_steps:.0f} flagged" if s["periodic"] else "no period"
    conv = "yes" if r.converged else f"no ({why})"
    return (
        f"| {engine} | {speed} | {bore} | {_ring(w, t)} | {b('conformability', '.2f')} | {r.energy_loss:.3f} "
        f"| {r.friction_power:.1f} | {s['blowby']:.2f} | {b('face_leakage', '.3g')} "
        f"| {s['oil_to_chamber']:.3g} | {b('light_gap_share', '.2f')} | {b('sector_jumps', '.0f')} "
        f"| {b('radial_collapse_share', '.2f')} | {s['flutter_events']:.0f} | {conv} |"
    )


def _nondominated(rows: list, names: tuple[str, ...]) -> list[float]:
    """Tensions of ``rows`` [(tension, result)] that no other row beats in every one of
    ``names`` (all minimised; energy_loss included by the caller's names)."""

    def v(r, n):
        return r.energy_loss if n == "energy_loss" else r.scalars[n]

    out = []
    for t, r in rows:
        beaten = any(
            all(v(o, n) <= v(r, n) for n in names) and any(v(o, n) < v(r, n) for n in names)
            for _, o in rows
            if o is not r
        )
        if not beaten:
            out.append(t)
    return out


def _span(values: list[float], fmt: str) -> str:
    """'least-most' of ``values`` as written with ``fmt``, one number where they read alike."""
    low, high = format(min(values), fmt), format(max(values), fmt)
    return low if low == high else f"{low}-{high}"


def _speed_verdict(engine: str, speed: int, base: Case, sweep: dict) -> list[str]:
    """What the tension sweep at one speed says (sweep: {bore: [(tension, result)]})."""
    rnd, dis = sweep["round"], sweep["distorted"]
    if not (rnd and dis) or not all(_ok(r) for _, r in rnd + dis):
        return [f"- **{engine}, {speed} r/min**: a run failed; no verdict."]
    (t0, r0), (t1, r1) = rnd[0], rnd[-1]
    (_, d0), (_, d1) = dis[0], dis[-1]
    w = base.value("ring", "width")
    lim = conformability_limit(base, w, 1.0)  # the limit per N of tension (linear in it)
    amps = dict(zip(base.value("bore", "order"), base.value("bore", "amplitude")))
    t_conform = max(amps[k] / lim[k] for k in amps)
    closed = [t for t, r in dis if r.scalars["light_gap_share"] == 0.0]
    leak = [r.scalars["face_leakage"] for _, r in dis]
    falls = all(a >= b for a, b in zip(leak, leak[1:])) and leak[0] > leak[-1]
    collapse = all(r.scalars["radial_collapse_share"] > 0 for _, r in dis)
    objectives = ("energy_loss", "blowby", "face_leakage", "light_gap_share")
    gaps = f"none from {min(closed):g} N" if closed else "open at every tension"
    md = [
        f"- **{engine}, {speed} r/min, {w * 1e3:.4g} mm ring, {t0:g} to {t1:g} N.** Energy "
        f"{r1.energy_loss / r0.energy_loss - 1:+.0%} on the round bore, "
        f"{d1.energy_loss / d0.energy_loss - 1:+.0%} on the distorted one; blowby "
        f"{r0.blowby:.2f} to {r1.blowby:.2f} L/min round ({r1.blowby / r0.blowby - 1:+.1%}), "
        f"{d0.blowby:.2f} to {d1.blowby:.2f} distorted ({d1.blowby / d0.blowby - 1:+.1%}); face "
        f"leakage {leak[0]:.3g} to {leak[-1]:.3g} mg per cycle "
        f"({'falling with tension' if falls else 'not falling monotonically with tension'}); light "
        f"gaps {d0.scalars['light_gap_share']:.2f} to {d1.scalars['light_gap_share']:.2f} % of the "
        f"sector-steps, {gaps}; the ring conforms dry from {t_conform:.1f} N (closed form). The "
        "tensions no other tension of the sweep beats in every objective: round "
        f"{', '.join(f'{t:g}' for t in _nondominated(rnd, ('energy_loss', 'blowby')))} N (energy, "
        "blowby), distorted "
        f"{', '.join(f'{t:g}' for t in _nondominated(dis, objectives))} N (energy, blowby, face "
        "leakage, light gaps)."
    ]
    if collapse:
        shares = _span([r.scalars["radial_collapse_share"] for _, r in dis], ".2f")
        md.append(
            f"  At every tension the ring is pushed off the liner on the distorted bore (radial "
            f"collapse {shares} % of the cycle) with its "
            "faces open to the gas: the blowby is the collapse's, which the tension does not "
            "prevent (the gas on the face is tens of bar, the tension's p_e a few hundred kPa); on "
            "the round bore a collapsed ring has no path past its face."
        )
    elif max(leak) < 0.01 * max(r.scalars["blowby_mass"] for _, r in dis):
        md.append(
            "  The light gaps pass almost no gas (face leakage under 1 % of the blowby at every "
            "tension): they open on the low-pressure strokes, and the gas behind the ring makes "
            "it conform while there is gas to pass (gas-assisted conformability), so what tension "
            "buys here is conformity (the light gaps, the oil path) and not blowby."
        )
    return md


def render_bore(bore: dict) -> list[str]:
    """The section's Markdown lines from :func:`bore_validation`'s runs.

    Parameters
    ----------
    bore : dict
        What :func:`bore_validation` returned.

    Returns
    -------
    list of str
        The lines, from the heading "## Bore distortion and conformability" on.

    Examples
    --------
    >>> render_bore(bore_validation("."))[0]  # doctest: +SKIP
    '## Bore distortion and conformability'
    """
    bases, rows = bore["bases"], bore["rows"]
    first = next(iter(bases.values()))
    amps = dict(zip(first.value("bore", "order"), first.value("bore", "amplitude")))
    amp_text = ", ".join(f"order {k}: {a * 1e6:g} um" for k, a in amps.items())
    m = first.value("bore", "sectors")
    md = [
        "## Bore distortion and conformability",
        "",
        "The distorted bore (`&physics bore = 'distorted'`, [bore.md](bore.md)) against what ring "
        "makers and engine builders publish, then what it says to a ring engineer about tension and "
        "width. The runs: the shipped distorted decks "
        + ", ".join(f"`inputs/{name}`" for _, name in BORE_DECKS)
        + " (full load with the ring pack's gas and the starved film; the bore of the first, "
        f"{amp_text}, {m} sectors, preset '{first.value('numerics', 'preset')}'; each deck's header "
        "says where its bore and engine come from) and the same decks on a round bore (`bore = "
        "'round'`, no `&bore`). **The tension is read in N** (tangential force F_T, p_e = F_T / "
        "(b r0)): the physical reading, the one that gives a ring the stiffness-to-load ratio a "
        "conformability limit needs. The CRF450R's calibration was fitted on a round bore without "
        "the ring pack; it is taken over here, not fitted. The own 86 x 86 mm engine "
        "(docs/own_engine.md) is uncalibrated.",
        "",
        "### The conformability limit",
        "",
        "A thin closed ring under a uniform radial line load q = p_e b follows a single order-k "
        "distortion fully when A_k <= q r0^4 / (E I (k^2 - 1)^2), I = b d^3 / 12 (b width, d radial "
        "depth). The kernel reports `conformability` = the largest A_k over this limit; its dry-ring "
        "solve reproduces the limit within 5 % for k = 2, 3, 4 (`ctest -R bore`). The limits of the "
        "rings run below (closed form) and the kernel's `conformability` of the same ring on the "
        "distorted bore:",
        "",
        "| engine | speed r/min | ring | p_e kPa | "
        + " | ".join(f"limit k={k} um" for k in amps)
        + " | largest A_k / limit | kernel's conformability |",
        "|---|---|---|---|" + "---|" * len(amps) + "---|---|",
    ]
    for engine, speed, b, w, t, r in rows:
        if b != "distorted":
            continue
        base = bases[engine, speed]
        r0 = base.value("engine", "bore_radius")
        lim = conformability_limit(base, w, t)
        q = t / r0 if base.value("ring", "tension_unit") == "N" else t
        worst = max(amps[k] / lim[k] for k in amps)
        kernel = f"{r.scalars['conformability']:.4f}" if _ok(r) else "failed"
        md.append(
            f"| {engine} | {speed} | {_ring(w, t)} | {q / w / 1e3:.0f} | "
            + " | ".join(f"{lim[k] * 1e6:.3g}" for k in amps)
            + f" | {worst:.4f} | {kernel} |"
        )
    md += [
        "",
        "How the published criteria differ, and what the model assumes instead:",
        "",
        '- **The classical in-plane criterion.** SAE 2002-01-3131 ("Development of Conformability '
        "Model of Piston Rings with Consideration of Their Three-Dimensional Torsional Distortions "
        'and Fourier Series Representation of Cylinder Bore Geometry", abstract: '
        "<https://www.sae.org/publications/technical-papers/content/2002-01-3131/>) describes it as "
        'the criterion that "was developed almost sixty years ago and considers only '
        "two-dimensional deformation of the ring in its plane by the force of piston ring "
        'elasticity", and defines conformability as the limit of bore distortion at which the '
        "ring-bore clearance is kept at zero by the ring's elastic deformation: what "
        "`conformability` measures. It adds the ring's twist, which the model's ring does not have.",
        '- **Tomanik** ("Piston Ring Conformability in a Distorted Bore", SAE 960356, 1996; '
        "abstract: <https://saemobilus.sae.org/papers/piston-ring-conformability-a-distorted-bore-960356>): "
        'the simple equations "do not consider the ring end gap and ovality, gas pressure acting on '
        'it, nor the actual bore shape, but only the maximum amplitude for a given term"; he '
        "measured the non-contact areas in distorted bores and proposed a semi-empirical limit. The "
        "model's limit is one of the simple equations (end gap neglected, no free-shape ovality, one "
        "order at a time); in operation the model goes further: all orders together, with the film "
        "and the gas behind the ring in each sector's load.",
        "- **Dunaevsky, GOETZE and Tomanik bounds**: Bardzimashvili, Kelly and Romelashvili "
        '("Distortion Inside a Piston Bore", Michigan State University, 2004; '
        "<https://vdocuments.us/distortion-inside-a-piston-bore.html>) compare these per-order bounds "
        "with a full-profile ring model on finite-element bore data and find the GOETZE bounds more "
        "accurate than Dunaevsky's at high orders. We have not obtained Dunaevsky's paper nor the "
        "GOETZE handbook, so we do not know which equals the model's limit; all are per-order bounds "
        "of the in-plane kind. **Müller**'s criterion is the classical in-plane one of the ring "
        "makers' literature; we found no text of it and compare with it only through the criterion "
        "above.",
        "",
        "### Bore distortion of production engines: what the decks assume",
        "",
        '- Bird and Gartside ("Measurement of Bore Distortion in a Firing Engine", SAE 2002-01-0485; '
        "abstract: <https://saemobilus.sae.org/content/2002-01-0485>) measured a firing 2.0 L in-line "
        "four with siamesed bores up to 6000 r/min: up to 86 um of distortion, the head bolts giving "
        "a fourth order, the thermal load a dominant second order.",
        "- Production form limits of assembled bores: out-of-roundness 0.020-0.025 mm (a GM 4.3 L V6, "
        "a Ford 2.0 L), a deviation from the cylinder of 0.013 mm when new (a Mercedes-Benz 5.6 L "
        "V8), roundness 0.01 mm or less (Yanmar TNV diesels): the workshop manuals' cylinder-block "
        "specifications. A two-point out-of-roundness of an oval bore is 4 A_2 (A_2 = 5-6.3 um); a "
        "cylindricity zone of 13 um holds a single order up to 2 A_k = 13 um.",
        f"- What the decks assume: {amp_text}, phases 0 (the orders add at theta = 0): each order at "
        "a new bore's form tolerance, a cold assembled bore, not a firing one, which Bird and Gartside "
        "show can be ten times more distorted. We found no per-order amplitude of a production engine; "
        "replace the lists with your bore's measured orders (`&bore order`, `amplitude`, `phase`, or "
        "`distortion_file` along the stroke).",
        '- Selmani, Delprete and Bisha ("Simulation of the cylinder bore distortion and effect on the '
        "sealing capacity of the ringpack\", SN Applied Sciences, 2019) ran Ricardo's RINGPAK on a "
        "bore's distortion orders: orders 1 and 2 hardly differed from the round bore, orders 3 and 4 "
        "gave high blowby although smaller, order 0 the most. The model agrees on order 1 by "
        "construction (it moves the ring's centre only) and on order 2 by the limits above (far "
        "above real amplitudes); it does not reproduce order 0: a larger bore moves the ring's mean "
        "position but does not open its end gap (`&ring_pack top_gap_area` is an input).",
        "",
        "### Tension and width on the round and the distorted bore",
        "",
        "Blowby includes the face leakage (gas through open faces, towards the crankcase); light "
        "gaps: the share of sector-steps whose film carries less than 1 % of the mean load; sector "
        "jumps: the crank steps at which a sector's film changes state (its h0 by more than a factor "
        "e^0.2; near a sector's lift-off the face leakage then depends on the state the ring came "
        "from, [bore.md](bore.md#two-states-of-a-light-sector)); 'collapse': the share of the cycle "
        "the ring is pushed off the liner to its back clearance "
        "(its faces open to the gas); 'converged' says why not (a flagged step, or no period within "
        "`max_cycles`; such a row is the last cycle's):",
        "",
        "| engine | speed r/min | bore | ring | conformability | energy J/cycle | friction W | blowby L/min "
        "| face leakage mg/cycle | oil to chamber mm^3/cycle | light gaps % | sector jumps | collapse % "
        "| flutter | converged |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    md += [_row(*row) for row in rows]
    md += ["", "### Where the tension optimum lands, and why", ""]
    for (engine, speed), base in bases.items():
        w0 = base.value("ring", "width")
        sweep = {
            b: [(t, r) for e, s, bb, w, t, r in rows if (e, s, bb, w) == (engine, speed, b, w0)]
            for b in ("round", "distorted")
        }
        md += _speed_verdict(engine, speed, base, sweep)
    md += [
        "",
        "Where the non-dominated tensions of the distorted bore reach above the lowest, the "
        "distortion has made sealing depend on tension: a study with `light_gap_share` or "
        "`face_leakage` among its objectives keeps rings of higher tension on its front, where on "
        "the round bore it drives tension to its lower bound. What would make tension pay more and "
        "the model does not have: an oil-control ring and a second ring whose scraping depends on the "
        "top ring's conformity, the bore as distorted in operation, ring rotation and wear, and the "
        "end gap and free shape of Tomanik's corrections.",
        "",
        "### The bore study",
        "",
        "`inputs/study_bore.nml`: width (0.54-1.34 mm), tension (8-26 N) and crown height (6-13 um) "
        "of the top ring on these decks at 4000 and 12,000 r/min, objectives `energy_loss`, "
        "`blowby`, `oil_to_chamber` and `light_gap_share`, the chosen designs re-checked by the true "
        "model (docs/optimisation.md). It is not run here: `ringlube optimise "
        "inputs/study_bore.nml` runs it, its answer in `out/crf450r_bore/report.md`; its answer, "
        'its run time and where tension trades on these decks are in docs/bore.md ("In a '
        'study"). A study fits its surfaces to converged samples only (it '
        "stops on a condition where fewer than 13 of the 64 samples converge) and chooses among "
        "converged designs, so rings that collapse and do not converge (the rows above marked "
        "'no') are outside what it can choose.",
        "",
    ]
    return md
