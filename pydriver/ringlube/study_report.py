"""Text summary of a finished design study."""

from __future__ import annotations

import json

import numpy as np

from .study import STUDY_OPTIMUM, UNITS_SCALE, Study

__all__ = ["summary"]


def _design(variables, x) -> str:
    return ", ".join(f"{v} {x[i] * UNITS_SCALE.get(v, 1):.4g}" for i, v in enumerate(variables))


def summary(study: Study) -> str:
    s = study.s
    lines = [f"study '{s.name}': {s.samples} samples ({s.sampler}) x {len(s.labels)} cases; "
             f"runs executed now: {study.runs_executed}"]
    for label, c in study.cases.items():
        lines.append(f"[{label}]")
        if "wall_s_runs" in c:
            lines.append(f"  true-model runs: {int(np.sum(c['done']))} done, "
                         f"{int(np.sum(~c['converged'].astype(bool)))} not converged")
        for o in s.objectives:
            sf = c.get("surface", {}).get(o)
            if sf:
                lines.append(f"  surface {o:12s} R2 {sf['r2']:.4f}  adj {sf['r2_adj']:.4f}  "
                             f"{s.folds}-fold CV rmse {sf['cv_rmse']:.4g} ({sf['cv_rel']:.2%})")
        fr = c.get("front")
        if fr:
            lines.append(f"  Pareto set: {len(fr['f'])} designs from {s.repeats} NSGA-II repeats; "
                         f"hypervolume of a single repeat / merged: mean {fr['hv_ratio_mean']:.3f}, "
                         f"min {fr['hv_ratio_min']:.3f}")
        ch = c.get("chosen")
        if ch:
            names = json.loads(ch["names"])
            for n, x, ft, err in zip(names, ch["x"], ch["f_true"], ch["rel_error"]):
                lines.append(f"  {n:18s} {_design(s.variables, x)} -> "
                             + ", ".join(f"{o} {v:.4g}" for o, v in zip(s.objectives, ft))
                             + "  (surrogate error " + ", ".join(f"{e:+.1%}" for e in err) + ")")
        so = c.get("study_optimum")
        if so:
            lines.append(f"  study's optimum   {_design(s.variables, [STUDY_OPTIMUM[v] for v in s.variables])} -> "
                         + ", ".join(f"{o} {v:.4g}" for o, v in zip(s.objectives, so["f_true"][0])))
        d = c.get("direct")
        if d:
            lines.append(f"  direct NSGA-II: {d['runs']} true-model runs in {d['wall_s']:.1f} s; "
                         f"hypervolume direct {d['hv_direct']:.3f} vs surrogate front "
                         f"{d['hv_surrogate']:.3f} (common reference); IGD surrogate->direct "
                         f"{d['igd_surrogate_to_direct']:.3f}, direct->surrogate {d['igd_direct_to_surrogate']:.3f} "
                         "(normalised objectives)")
    return "\n".join(lines)
