"""How sure a study's answer is: the chosen designs re-run at the ``'accurate'`` preset and
with each uncertain input (:data:`UNCERTAIN`) multiplied and divided by its factor."""

from __future__ import annotations

import numpy as np

from ..case import Case
from ..executor import Executor
from . import runs
from .runs import _bases
from .state_checks import Sure
from .store import Study

__all__ = ["how_sure", "UNCERTAIN"]

#: The uncertain inputs of :func:`how_sure`, each multiplied and divided by its factor:
#: the liner film the lower rings leave (unmeasured; only with a starved inlet), the
#: roughness parameter and the gas-pressure scale (both calibrated at best).
UNCERTAIN = {
    ("lubricant", "supply_film"): 2.0,
    ("surface", "zeta_kappa_sigma"): 1.5,
    ("operating", "pressure_scale"): 1.1,
}


def _uncertain_inputs(study: Study, label: str) -> list[tuple[str, str, float]]:
    """The :data:`UNCERTAIN` inputs that apply to a case: ``supply_film`` only when every
    base deck of the case has a starved inlet; none that is a design variable."""
    s = study.s
    decks = [d for lb, d in zip(s.labels, s.cases) if lb == label or label not in s.labels]
    bases = [Case.from_namelist(d) for d in decks]
    out = []
    for (group, name), factor in UNCERTAIN.items():
        if (group, name) in s.groups_names:
            continue
        if name == "supply_film" and not all(b.value("physics", "inlet") == "starved" for b in bases):
            continue
        out.append((group, name, factor))
    return out


def _varied(base: Case, group: str, name: str, factor: float) -> Case:
    """``base`` with ``&group name`` multiplied by ``factor`` (calibrated values included)."""
    case = base.inline_calibration()
    return case.with_(group, **{name: float(case.value(group, name)) * factor})


def how_sure(study: Study, ex: Executor) -> None:
    """Extra true-model runs of the chosen designs (and the reference): at the
    ``'accurate'`` preset, and with each :data:`UNCERTAIN` input multiplied and divided by
    its factor, one at a time. Stored as :class:`~ringlube.study.state.Sure` per case.

    Costs (chosen designs + reference) x (1 + 2 x inputs) runs per base deck.

    Parameters
    ----------
    study : Study
        With the chosen designs re-simulated.
    ex : Executor

    Example
    -------
    >>> how_sure(study, Executor(serial=True)); study.cases["cold"].sure.inputs   # doctest: +SKIP
    ['surface:zeta_kappa_sigma', 'operating:pressure_scale']
    """
    s = study.s
    bases = dict(zip(s.labels, _bases(s)))
    w = dict(zip(s.labels, s.scene_weights()))
    plans = {}  # label -> (names, xs, nominal, inputs)
    jobs = []
    for label, c in study.cases.items():
        checked = [ch for ch in (c.chosen, c.reference) if ch is not None]
        names = [n for ch in checked for n in ch.names]
        xs = np.vstack([ch.x for ch in checked])
        nominal = np.vstack([ch.f_true for ch in checked])
        inputs = _uncertain_inputs(study, label)
        plans[label] = (names, xs, nominal, inputs)
        variants = [("accurate", None)] + [
            (f"{g}:{n}:{side}", (g, n, f if side == "high" else 1.0 / f))
            for g, n, f in inputs
            for side in ("low", "high")
        ]
        for vname, change in variants:
            for bl in [label] if label in bases else s.labels:
                base = bases[bl]
                case = base.with_("numerics", preset="accurate") if change is None else _varied(base, *change)
                jobs.append(((label, vname, bl), case, xs))
    results = {key: r[0] for key, r in runs.run_in_batches(study, ex, jobs).items()}

    def value(label, vname):
        if label in bases:
            return results[(label, vname, label)]
        return sum(w[bl] * results[(label, vname, bl)] for bl in s.labels)

    presets = {str(b.value("numerics", "preset")) for b in bases.values()}
    for label, (names, xs, nominal, inputs) in plans.items():
        k = len(names)
        shape = (len(inputs), k, len(s.outputs))
        study.cases[label].sure = Sure(
            names,
            xs,
            nominal,
            ", ".join(sorted(presets)),
            value(label, "accurate"),
            [f"{g}:{n}" for g, n, _ in inputs],
            [f for _, _, f in inputs],
            np.array([value(label, f"{g}:{n}:low") for g, n, _ in inputs]).reshape(shape),
            np.array([value(label, f"{g}:{n}:high") for g, n, _ in inputs]).reshape(shape),
        )
