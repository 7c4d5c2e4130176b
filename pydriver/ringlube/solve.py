"""Running the kernel from Python: one case, or many in parallel processes."""

from __future__ import annotations

import os
from concurrent.futures import ProcessPoolExecutor
from typing import Iterable, Sequence

import numpy as np

from .case import Case
from .errors import NotConvergedError, error_for
from .result import SERIES, CycleResult

__all__ = ["run", "run_many"]


def run(case: Case | str | os.PathLike, *, strict: bool = False) -> CycleResult:
    """Run one engine cycle of ``case`` (a :class:`Case` or a deck path).

    Gives the same numbers as ``ringlube-solve`` on the same deck. With ``strict=True``
    a run that did not converge raises :class:`NotConvergedError`; otherwise check
    ``result.converged``. Bad input raises :class:`InputError`.
    """
    from . import _kernel

    if not isinstance(case, Case):
        case = Case.from_namelist(case)
    deck_file = case.deck_file()
    with deck_file as deck:
        nsteps, code, message = _kernel.rl_count_steps(deck)
        if code:
            raise error_for(code, case.describe_message(message, deck))
        series, flags, iters, scalars, code, message = _kernel.rl_run_deck(deck, nsteps)
        if code:
            raise error_for(code, case.describe_message(message, deck))
    arrays = {attr: np.ascontiguousarray(series[:, j]) for j, (_, attr, _) in enumerate(SERIES)}
    result = CycleResult(
        **arrays,
        flags=np.asarray(flags),
        film_solves=np.asarray(iters),
        energy_loss=float(scalars[0]),
        mixed_share=float(scalars[1]),
        ring_mass=float(scalars[2]),
        min_film=float(scalars[3]),
        max_friction=float(scalars[4]),
        converged=bool(scalars[5]),
        cycles_run=int(scalars[6]),
        cycle_change=float(scalars[7]),
        sigma=float(scalars[8]),
        run_time=float(scalars[9]),
        deck=deck_file.text,
        label=case.name,
        reynolds_solves=int(scalars[12]),
        cycles_computed=float(scalars[13]),
    )
    if strict and not result.converged:
        raise NotConvergedError(f"{case.source or case.name}: the run did not converge "
                                f"({result.cycles_run} cycles, change {result.cycle_change:.2e})")
    return result


def _run_one(args: tuple[Case, bool]) -> CycleResult:
    return run(args[0], strict=args[1])


def run_many(cases: Iterable[Case], workers: int | None = None, *, strict: bool = False,
             progress: bool = True) -> list[CycleResult]:
    """Run many cases in worker processes; results in input order.

    ``workers`` defaults to the number of cores; ``workers=1`` runs serially in this
    process. The kernel keeps no state between runs, so results equal serial runs.
    """
    from tqdm.auto import tqdm

    cases: Sequence[Case] = list(cases)
    workers = workers or os.cpu_count() or 1
    bar = tqdm(total=len(cases), desc="ringlube runs", unit="run", disable=not progress)
    try:
        if workers == 1 or len(cases) <= 1:
            out = []
            for c in cases:
                out.append(run(c, strict=strict))
                bar.update()
            return out
        with ProcessPoolExecutor(max_workers=workers) as pool:
            out = []
            chunk = max(1, min(16, len(cases) // (4 * workers)))
            for r in pool.map(_run_one, [(c, strict) for c in cases], chunksize=chunk):
                out.append(r)
                bar.update()
            return out
    finally:
        bar.close()
