"""Speed against accuracy: a case over a ladder of numerical settings and physics switches.

Each setting is changed one at a time from a converged reference (the finest settings),
and a few combined presets are run too; every run reports its kernel time and its error
in energy loss, mixed share and minimum film against the reference, and which state it took
(lifted off the liner or not; sealed or blown with 'trailing_gas'), with its margins, so that
a setting on the other branch shows. The reference's own
error is estimated by Richardson extrapolation from its halvings in N and in the crank
step (both second order where the solution is smooth). Output: a Markdown table, a CSV
and a plot of error against time with the Pareto front of settings. A deck with the ring
pack adds its blowby, ring lift share and flutter events, one with a distorted bore its face
leakage, light gaps and conformability (:data:`OPTIONAL`), each with its error against the
reference.

    ringlube convergence DECK [--out DIR] [--quick]
"""

from __future__ import annotations

import csv
import dataclasses
import os
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from .case import Case
from .outputs import atomic_path, check_output, save_figure, write_text
from .solve import run

__all__ = [
    "Setting",
    "Row",
    "REFERENCE",
    "PRESETS",
    "OPTIONAL",
    "ladder",
    "measure",
    "convergence_study",
    "state_text",
]

#: The reference numerics (finest settings of the ladder).
REFERENCE = {
    "nodes": 801,
    "dpsi_deg": 0.125,
    "pressure_tol": 1e-8,
    "load_tol": 1e-6,
    "h0_update": "safeguarded",
}
#: The presets of &numerics preset (the kernel's table).
from .tables import PRESETS  # noqa: E402

#: Results of the optional models the tables add when the reference run has them, and how
#: their error is measured: 'rel' relative to the reference, 'pts' in percentage points,
#: 'abs' the difference in the result's unit (flutter events per cycle).
#: (The conformability comes from the inputs alone: the same at every setting.)
OPTIONAL = (
    ("blowby", "rel"),
    ("ring_lift_share", "pts"),
    ("flutter_events", "abs"),
    ("face_leakage", "rel"),
    ("light_gap_share", "pts"),
    ("conformability", "rel"),
)


@dataclasses.dataclass(frozen=True)
class Setting:
    """One point of the ladder: a label and the changes from the reference.

    Examples
    --------
    >>> Setting("nodes", "nodes = 51", {"nodes": 51}).numerics
    {'nodes': 51}
    """

    kind: str
    label: str
    numerics: dict
    physics: dict = dataclasses.field(default_factory=dict)


@dataclasses.dataclass
class Row:
    """One measured setting: times, results and errors against the reference.

    Examples
    --------
    >>> Row.__dataclass_fields__["err_energy"].type
    'float'
    """

    setting: Setting
    time_ms: float  # kernel time per run (best of the repeats)
    ms_per_cycle: float  # per cycle of crank steps computed (warm-up included)
    energy: float
    mixed: float
    min_film: float
    err_energy: float  # relative
    err_mixed: float  # percentage points
    err_min_film: float  # relative
    converged: bool
    film_solves: int
    #: the results of :data:`OPTIONAL` the reference has: name -> (value, error)
    extra: dict = dataclasses.field(default_factory=dict)
    #: which state the run took: lifted off or not, sealed or blown (:func:`state_text`)
    state: str = ""


def state_text(r) -> str:
    """Which branch a run took (docs/model.md, "Branch risk"): lifted off the liner or not,
    and with ``cavity_pressure = 'trailing_gas'`` sealed or blown, each with its margin; a
    margin below its threshold (:data:`ringlube.tables.MARGINS`) is marked ``(!)``.

    Parameters
    ----------
    r : CycleResult
        A run (its ``liner_lift_share``, ``lift_margin`` and, if made, ``seal_margin``).

    Returns
    -------
    str

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> state_text(SimpleNamespace(liner_lift_share=0.0, lift_margin=0.039, scalars={}))
    'on the liner (lift margin +0.0390)'
    >>> state_text(SimpleNamespace(liner_lift_share=26.7, lift_margin=-0.0037, scalars={}))
    'lifted 26.7 % (lift margin -0.0037 (!))'
    """
    from .tables import MARGINS

    def margin(name: str, value: float) -> str:
        risky = abs(value) < MARGINS[name].threshold
        return f"{name.replace('_', ' ')} {value:+.4f}{' (!)' if risky else ''}"

    lift = r.liner_lift_share
    out = f"lifted {lift:.3g} %" if lift > 0 else "on the liner"
    out += f" ({margin('lift_margin', r.lift_margin)})"
    if "seal_margin" in r.scalars:
        seal = r.seal_margin
        out += f", {'sealed' if seal > 0 else 'blown'} ({margin('seal_margin', seal)})"
    return out


def _extra(r, ref) -> dict:
    """The results of :data:`OPTIONAL` that the reference run ``ref`` has, in run ``r``,
    with their errors against the reference (relative, or in percentage points; NaN for a
    relative error against a reference of 0 that ``r`` does not match).

    Examples
    --------
    >>> class R:
    ...     scalars = {"face_leakage": 2.2, "light_gap_share": 11.0}
    >>> class Ref:
    ...     scalars = {"face_leakage": 2.0, "light_gap_share": 10.0}
    >>> {k: (round(v, 6), round(e, 6)) for k, (v, e) in _extra(R, Ref).items()}
    {'face_leakage': (2.2, 0.1), 'light_gap_share': (11.0, 1.0)}
    """
    out = {}
    for name, kind in OPTIONAL:
        if name not in ref.scalars:
            continue
        v, v0 = float(r.scalars.get(name, np.nan)), float(ref.scalars[name])
        if kind in ("pts", "abs"):
            err = abs(v - v0)
        elif v0 != 0:
            err = abs(v - v0) / abs(v0)
        else:
            err = 0.0 if v == v0 else float("nan")
        out[name] = (v, err)
    return out


def _csv_name(name: str, unit: str) -> str:
    """A CSV column of a result with its unit ('%' as pct, '/' as _per_, none for '1').

    Examples
    --------
    >>> _csv_name("light_gap_share", "%"), _csv_name("blowby", "L/min"), _csv_name("conformability", "1")
    ('light_gap_share_pct', 'blowby_L_per_min', 'conformability')
    """
    tag = {"%": "pct", "1": ""}.get(unit, unit.replace("/", "_per_"))
    return f"{name}_{tag}" if tag else name


def ladder(quick: bool = False) -> list[Setting]:
    """The settings to run, each a change from :data:`REFERENCE`.

    Parameters
    ----------
    quick : bool
        Shorter ladders (no 801/1601 nodes, no 0.125 deg).

    Returns
    -------
    list of Setting

    Examples
    --------
    >>> ladder(quick=True)[0].label
    'nodes = 25'
    """
    out: list[Setting] = []
    nodes = (25, 51, 101, 201, 401) if quick else (25, 51, 101, 201, 401, 801, 1601)
    steps = (2.0, 1.0, 0.5, 0.25) if quick else (2.0, 1.0, 0.5, 0.25, 0.125)
    for n in nodes:
        out.append(Setting("nodes", f"nodes = {n}", {"nodes": n}))
    for d in steps:
        out.append(Setting("crank step", f"dpsi_deg = {d}", {"dpsi_deg": d}))
    for t in (1e-3, 1e-4, 1e-5, 1e-6):
        out.append(Setting("pressure_tol", f"pressure_tol = {t:g}", {"pressure_tol": t}))
    for t in (1e-2, 3e-3, 1e-3, 1e-4, 1e-5):
        out.append(Setting("load_tol", f"load_tol = {t:g}", {"load_tol": t}))
    for upd in ("safeguarded", "damped"):
        out.append(
            Setting("h0 update", f"h0_update = '{upd}' (load_tol 1e-3)", {"h0_update": upd, "load_tol": 1e-3})
        )
    out.append(Setting("physics", "gt_functions = 'fit'", {}, {"gt_functions": "fit"}))
    out.append(Setting("physics", "roelands = .false.", {}, {"roelands": False}))
    out.append(Setting("physics", "squeeze = .false.", {}, {"squeeze": False}))
    out.append(Setting("physics", "asperity_contact = .false.", {}, {"asperity_contact": False}))
    out.append(Setting("physics", "contact_area = 'lumped'", {}, {"contact_area": "lumped"}))
    out.append(Setting("physics", "outlet = 'ambient'", {}, {"outlet": "ambient"}))
    for name, p in PRESETS.items():
        out.append(Setting("preset", f"preset = '{name}'", dict(p)))
        out.append(
            Setting(
                "preset+fit",
                f"preset = '{name}', gt 'fit', no Roelands",
                dict(p),
                {"gt_functions": "fit", "roelands": False},
            )
        )
    return out


def _case_for(base: Case, s: Setting) -> Case:
    c = base.with_("numerics", **{**REFERENCE, **s.numerics})
    if s.physics:
        c = c.with_("physics", **s.physics)
    return c


def measure(case: Case, repeats: int = 3, after_run=None):
    """Run a case ``repeats`` times (the kernel is deterministic) and keep the best time.

    Parameters
    ----------
    case : Case
    repeats : int
    after_run : callable, optional
        Called with no argument after each run (progress).

    Returns
    -------
    CycleResult
        The run with the shortest kernel time.

    Examples
    --------
    >>> from ringlube import Case
    >>> measure(Case().with_numerics(preset="fast"), 2).converged
    True
    """
    best = None
    for _ in range(repeats):
        r = run(case)
        if after_run is not None:
            after_run()
        if best is None or r.run_time < best.run_time:
            best = r
    return best


def convergence_study(
    deck: str | os.PathLike, quick: bool = False, repeats: int = 3, progress: bool = True
) -> tuple[dict, list[Row]]:
    """Run the ladder on a deck; returns (reference summary, rows).

    Parameters
    ----------
    deck : path
    quick : bool
        Shorter ladders.
    repeats : int
        Timing repeats per setting (best kept).
    progress : bool
        Show a progress bar (on stderr) before the first run: one step per run, the
        setting being run beside it (a starved reference run alone can take minutes).

    Returns
    -------
    (dict, list of Row)

    Examples
    --------
    >>> ref, rows = convergence_study("inputs/crf450r_4000rpm_full_cold.nml")  # doctest: +SKIP
    """
    from tqdm.auto import tqdm

    base = Case.from_namelist(deck).inline_calibration()
    base._nml.get("numerics", {}).pop("preset", None)
    settings = ladder(quick)
    bar = tqdm(
        total=5 + len(settings) * repeats,
        desc=f"convergence {Path(deck).name}",
        unit="run",
        mininterval=0.0,  # every run is shown: a run takes from 10 ms to minutes
        disable=not progress,
    )

    def step(case: Case, what: str = ""):
        if what:
            bar.set_postfix_str(what, refresh=True)
        r = run(case)
        bar.update()
        return r

    ref_case = base.with_("numerics", **REFERENCE)
    ref = step(ref_case, f"reference: nodes {REFERENCE['nodes']}, dpsi {REFERENCE['dpsi_deg']} deg")

    # Richardson: the observed order from three levels (reference, 1/2 and 1/4 of its
    # resolution) in N and in the crank step, then the extrapolated error of the reference
    def richardson(levels):
        e0, e1, e2 = (r.energy_loss for r in levels)  # finest first
        d1, d2 = e1 - e0, e2 - e1
        p = float(np.log2(abs(d2 / d1))) if d1 != 0 and d2 != 0 else float("nan")
        err = d1 / (2**p - 1) if np.isfinite(p) and p > 0 else float("nan")
        return p, err

    n0 = REFERENCE["nodes"]
    p_n, rich_n = richardson(
        [
            ref,
            step(ref_case.with_numerics(nodes=(n0 - 1) // 2 + 1), "Richardson levels"),
            step(ref_case.with_numerics(nodes=(n0 - 1) // 4 + 1)),
        ]
    )
    d0 = REFERENCE["dpsi_deg"]
    p_t, rich_t = richardson(
        [ref, step(ref_case.with_numerics(dpsi_deg=2 * d0)), step(ref_case.with_numerics(dpsi_deg=4 * d0))]
    )
    reference = {
        "energy": ref.energy_loss,
        "mixed": ref.mixed_share,
        "min_film": ref.min_film,
        "time_ms": ref.run_time * 1e3,
        "order_n": p_n,
        "order_t": p_t,
        "richardson_energy": ref.energy_loss - rich_n - rich_t,
        "est_err_n": abs(rich_n) / ref.energy_loss,
        "est_err_t": abs(rich_t) / ref.energy_loss,
        "extra": {k: v for k, (v, _) in _extra(ref, ref).items()},
        "state": state_text(ref),
    }
    rows: list[Row] = []
    for s in settings:
        case = _case_for(base, s)
        bar.set_postfix_str(f"{s.kind} {s.label}", refresh=True)
        r = measure(case, repeats, after_run=bar.update)
        rows.append(
            Row(
                setting=s,
                time_ms=r.run_time * 1e3,
                ms_per_cycle=r.run_time * 1e3 / max(r.cycles_computed, 1e-9),
                energy=r.energy_loss,
                mixed=r.mixed_share,
                min_film=r.min_film,
                err_energy=abs(r.energy_loss - ref.energy_loss) / ref.energy_loss,
                err_mixed=abs(r.mixed_share - ref.mixed_share),
                err_min_film=abs(r.min_film - ref.min_film) / ref.min_film,
                converged=r.converged,
                film_solves=int(r.film_solves.sum()),
                extra=_extra(r, ref),
                state=state_text(r),
            )
        )
    bar.close()
    return reference, rows


def pareto(rows: Sequence[Row]) -> list[Row]:
    """Rows not beaten in both time and energy error by another row."""
    front = []
    for r in sorted(rows, key=lambda r: (r.time_ms, r.err_energy)):
        if not front or r.err_energy < front[-1].err_energy:
            front.append(r)
    return front


def write_report(
    deck: str, reference: dict, rows: Sequence[Row], outdir: str | os.PathLike, command: str
) -> list[Path]:
    """Markdown table, CSV and error-vs-time plot."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from .tables import SCALARS

    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    stem = Path(deck).stem
    front = {id(r) for r in pareto(rows)}
    extra = list(reference.get("extra", {}))  # (the optional results the reference has)
    kinds = dict(OPTIONAL)

    def err_text(name: str, e: float) -> str:
        if not np.isfinite(e):
            return "-"
        return {"pts": f"{e:.3f}", "abs": f"{e:.3g}"}.get(kinds[name], f"{e:.2e}")

    def err_head(name: str) -> str:
        return {"pts": f"err {name} (pts)", "abs": f"err {name} (difference)"}.get(kinds[name], f"err {name}")

    ref_extra = reference.get("extra", {})
    extra_text = "".join(
        f" Reference {k.replace('_', ' ')}: {v:.5g} {SCALARS[k].unit}." for k, v in ref_extra.items()
    )
    if "conformability" in extra:
        extra_text += " (The conformability comes from the inputs: the same at every setting.)"
    md = [
        f"### `{stem}`",
        "",
        f"Command: `{command}`",
        "",
        f"Reference (nodes {REFERENCE['nodes']}, dpsi {REFERENCE['dpsi_deg']} deg, pressure_tol "
        f"{REFERENCE['pressure_tol']:g}, load_tol {REFERENCE['load_tol']:g}): energy "
        f"{reference['energy']:.5f} J, mixed share {reference['mixed']:.3f} %, min film "
        f"{reference['min_film'] * 1e6:.4f} um, {reference['time_ms']:.0f} ms. Observed order of the "
        f"energy from three levels: {reference['order_n']:.2f} in N, {reference['order_t']:.2f} in the "
        f"crank step; Richardson estimate of the reference's own energy error: "
        f"{reference['est_err_n']:.1e} (N), {reference['est_err_t']:.1e} (crank step)."
        + extra_text
        + f" The reference's state: {reference.get('state', '')}; a setting whose state differs "
        "took the other branch (margins marked (!) are below their thresholds: docs/model.md, "
        '"Branch risk").',
        "",
        "| kind | setting | ms/run | ms/cycle | film solves | energy J | err energy | err mixed (pts) "
        "| err min film |"
        + "".join(f" {k} [{SCALARS[k].unit}] | {err_head(k)} |" for k in extra)
        + " converged | state | front |",
        "|---|---|---|---|---|---|---|---|---|" + "---|---|" * len(extra) + "---|---|---|",
    ]
    for r in rows:
        md.append(
            f"| {r.setting.kind} | {r.setting.label} | {r.time_ms:.1f} | {r.ms_per_cycle:.1f} | "
            f"{r.film_solves} | {r.energy:.5f} | {r.err_energy:.2e} | {r.err_mixed:.3f} | "
            f"{r.err_min_film:.2e} |"
            + "".join(f" {r.extra[k][0]:.5g} | {err_text(k, r.extra[k][1])} |" for k in extra)
            + f" {'yes' if r.converged else 'NO'} | {r.state} | {'*' if id(r) in front else ''} |"
        )
    md_path = outdir / f"convergence_{stem}.md"
    csv_path = outdir / f"convergence_{stem}.csv"
    png = outdir / f"convergence_{stem}.png"
    for p in (md_path, csv_path, png):
        check_output(p, [deck])
    write_text(md_path, "\n".join(md) + "\n", [deck])
    with atomic_path(csv_path, [deck]) as tmp, open(tmp, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(
            [
                "kind",
                "setting",
                "ms_per_run",
                "ms_per_cycle",
                "film_solves",
                "energy_J",
                "err_energy",
                "err_mixed_pts",
                "err_min_film",
                *(_csv_name(k, SCALARS[k].unit) for k in extra),
                *(f"err_{k}_pts" if kinds[k] == "pts" else f"err_{k}" for k in extra),
                "converged",
                "state",
            ]
        )
        for r in rows:
            w.writerow(
                [
                    r.setting.kind,
                    r.setting.label,
                    f"{r.time_ms:.3f}",
                    f"{r.ms_per_cycle:.3f}",
                    r.film_solves,
                    r.energy,
                    r.err_energy,
                    r.err_mixed,
                    r.err_min_film,
                    *(r.extra[k][0] for k in extra),
                    *(r.extra[k][1] for k in extra),
                    int(r.converged),
                    r.state,
                ]
            )
    fig, ax = plt.subplots(figsize=(7.5, 5), layout="constrained")
    kinds = sorted({r.setting.kind for r in rows})
    for k in kinds:
        sel = [r for r in rows if r.setting.kind == k]
        ax.scatter([r.time_ms for r in sel], [max(r.err_energy, 1e-9) for r in sel], label=k, s=22)
    fr = pareto(rows)
    ax.plot(
        [r.time_ms for r in fr], [max(r.err_energy, 1e-9) for r in fr], "k--", lw=0.8, label="Pareto front"
    )
    for r in rows:
        if r.setting.kind == "preset":
            ax.annotate(
                r.setting.label.split("'")[1],
                (r.time_ms, max(r.err_energy, 1e-9)),
                fontsize=8,
                xytext=(4, 4),
                textcoords="offset points",
            )
    ax.axhline(5e-3, color="tab:red", lw=0.8, ls=":")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("kernel time per run [ms]")
    ax.set_ylabel("relative error in energy loss vs reference")
    ax.set_title(stem, fontsize=9)
    ax.legend(fontsize=7)
    save_figure(fig, png, [deck], dpi=150)
    plt.close(fig)
    return [md_path, csv_path, png]
