"""Running the kernel from Python: one case, a batch of designs of one case, or many
cases in parallel processes."""

from __future__ import annotations

import os
from collections.abc import Iterable, Sequence
from pathlib import Path

import numpy as np

from .case import Case
from .case.kernel import kernel_case, kernel_text
from .errors import InputError, NotConvergedError, RinglubeError, error_for
from .result import CycleResult
from .tables import INT_SERIES, LINER, MODELS, SCALARS, SECTORS, SERIES

__all__ = ["run", "run_many", "run_designs", "BatchError"]


class BatchError(RinglubeError):
    """Some cases of :func:`run_many` failed.

    Attributes
    ----------
    results : list
        One entry per case: its :class:`CycleResult`, or None where it failed.
    errors : dict of int to RinglubeError
        The error of each failed case, by index.

    Examples
    --------
    >>> e = BatchError([1.0, None], {1: RinglubeError("boom")})
    >>> e.results, list(e.errors)
    ([1.0, None], [1])
    """

    def __init__(self, results: list, errors: dict[int, RinglubeError]):
        self.results, self.errors = results, errors
        first = min(errors)
        super().__init__(
            f"{len(errors)} of {len(results)} cases failed (first: case {first}: "
            f"{errors[first]}); the other results are in .results"
        )
        self.code = max(e.code for e in errors.values())


def _trace_arrays(trace) -> tuple[np.ndarray, np.ndarray]:
    """The (crank angle, pressure) pair of ``run(trace=...)`` as two 1-D float arrays of one
    length (at least 2), else an :class:`InputError` naming the argument and the lengths.

    Examples
    --------
    >>> _trace_arrays(([0.0, 720.0], [1e5, 1e5]))[1]
    array([100000., 100000.])
    >>> _trace_arrays(([0.0, 360.0, 720.0], [1e5, 1e5]))
    Traceback (most recent call last):
    ...
    ringlube.errors.InputError: trace: crank angle has 3 values but pressure 2; give one pressure per angle
    """
    try:
        psi, p = trace
    except (TypeError, ValueError):
        raise InputError("trace: expected a pair (crank angle [deg], pressure [Pa]) of arrays") from None
    arrays = []
    for what, a in (("crank angle", psi), ("pressure", p)):
        try:
            a = np.asarray(a, dtype=float)
        except (TypeError, ValueError) as exc:
            raise InputError(f"trace: {what} must be numbers: {exc}") from None
        if a.ndim != 1:
            raise InputError(f"trace: {what} must be one-dimensional, got shape {a.shape}")
        arrays.append(np.ascontiguousarray(a))
    psi, p = arrays
    if len(psi) != len(p):
        raise InputError(
            f"trace: crank angle has {len(psi)} values but pressure {len(p)}; give one pressure per angle"
        )
    if len(psi) < 2:
        raise InputError(f"trace: {len(psi)} points; a trace needs at least 2 (crank angle, pressure) points")
    return psi, p


def run(
    case: Case | str | os.PathLike,
    *,
    strict: bool = False,
    trace: tuple[np.ndarray, np.ndarray] | None = None,
    output: str | os.PathLike | None = None,
) -> CycleResult:
    """Run one engine cycle of ``case`` (a :class:`Case` or a deck path).

    Gives the same numbers as ``ringlube-solve`` on the same deck: the case is parsed by
    the same reader, in memory, once. With ``output`` the kernel writes the result file
    itself, with the writer and layout of ``ringlube-solve``.

    Parameters
    ----------
    case : Case or path
        The case, or a deck file.
    strict : bool
        Raise :class:`NotConvergedError` if the run did not converge (else check
        ``result.converged``).
    trace : (ndarray, ndarray), optional
        Crank angle [deg] and absolute gas pressure [Pa] used instead of the case's
        pressure file (checked like the file; times the case's ``pressure_scale``).
    output : path, optional
        Write the result there (HDF5, atomically: a temporary file renamed when
        complete). The path is checked before the run: not one of the run's inputs (the
        deck, its pressure or calibration file), not a folder or device, in a folder that
        exists. ``result.path`` is where it was written.

    Returns
    -------
    CycleResult

    Raises
    ------
    InputError
        Bad input (the message names file, group and variable).
    NotConvergedError
        With ``strict=True`` only.

    Examples
    --------
    >>> import ringlube
    >>> r = ringlube.run(ringlube.Case().with_numerics(nodes=31, dpsi_deg=4.0))
    >>> r.converged
    True
    """
    from . import _kernel

    if not isinstance(case, Case):
        if not isinstance(case, (str, os.PathLike)):
            raise TypeError(f"run: expected a Case or a deck path, got {type(case).__name__}")
        case = Case.from_namelist(case)
    out = b""
    if output is not None:
        if not str(output) or "\0" in str(output):
            raise InputError(f"{str(output)!r}: not a usable file name")
        out = os.fsencode(output)
    with kernel_case(case, load_trace=trace is None) as k:
        if trace is not None:
            psi, p = _trace_arrays(trace)
            code, message = _kernel.rl_set_trace(k.handle, psi, p)
            if code:
                raise error_for(code, kernel_text(message))
        series, iseries, scalars, liner, sectors, orders, conform, models, code, message = _kernel.rl_run(
            k.handle,
            out,
            k.nsteps,
            len(SERIES),
            len(INT_SERIES),
            len(SCALARS),
            len(LINER),
            k.nliner,
            k.nsectors,
            len(SECTORS),
            k.norders,
        )
        if code == INTERRUPTED:  # Ctrl-C: the kernel stopped within a crank step, wrote nothing
            raise KeyboardInterrupt
        if code:
            raise error_for(code, kernel_text(message))
        pressure_file, _, _ = _kernel.rl_get(k.handle, b"operating", b"pressure_file")
        calibration_file, _, _ = _kernel.rl_get(k.handle, b"calibration", b"file")
        deck = _kernel.rl_deck_text(k.handle, _kernel.rl_deck_length(k.handle))
    # the rows of the tables the run produced: those whose `requires` the kernel names
    made = {"", *kernel_text(models).split()}
    data = {**_columns(SERIES, series, made), **_columns(INT_SERIES, iseries, made)}
    scal = {k: float(v) for (k, s), v in zip(SCALARS.items(), scalars) if s.requires in made}
    lin = _columns(LINER, liner, made)
    # a distorted bore: each sector series (crank step x sector), the conformability per order
    sec = {k: sectors[:, :, j].copy() for j, k in enumerate(SECTORS) if SECTORS[k].requires in made}
    conf = {int(o): float(v) for o, v in zip(orders, conform)} if "conformability" in scal else None
    name = case.kernel_inputs()[1]
    result = CycleResult(
        data,
        scal,
        liner=lin,
        sectors=sec,
        conformability_by_order=conf,
        deck=deck.astype("u1").tobytes().decode("utf-8", errors="replace"),
        deck_path=name,
        pressure_file=kernel_text(pressure_file),
        label=case.name,
        calibration_file=kernel_text(calibration_file),
        path=Path(os.fsdecode(out)) if out else None,
    )
    if strict and not result.converged:
        raise NotConvergedError(
            f"{case.source or case.name}: the run did not converge "
            f"({result.cycles_run} cycles; last cycle's change {_changes(result)})"
        )
    return result


#: The kernel's code for a run stopped by SIGINT (Ctrl-C) during the call (error.f90).
INTERRUPTED = 130


def _changes(result: CycleResult) -> str:
    """What the periodicity test compares with ``cycle_tol``, as text (the summary's: starved
    the liner film, else h0; the energy; and the ring pack's)."""
    film = "liner_change" if "liner_change" in result.scalars else "cycle_change"
    names = (film, "energy_change")
    names += ("ring_pack_change",) if "ring_pack_change" in result.scalars else ()
    return ", ".join(f"{n} {result.scalars[n]:.2e}" for n in names)


def _columns(table: dict, values: np.ndarray, made: set[str]) -> dict[str, np.ndarray]:
    """The columns of `values` (one a row of `table`) that the run produced, by short name."""
    return {
        k: np.ascontiguousarray(values[:, j]) for j, (k, s) in enumerate(table.items()) if s.requires in made
    }


def run_designs(
    case: Case, variables: Sequence[str], x: np.ndarray, outputs: Sequence[str] | None = None
) -> tuple[np.ndarray, np.ndarray, list]:
    """Run many designs of one case in one kernel call (the case parsed once).

    Parameters
    ----------
    case : Case
        The base case.
    variables : sequence of str
        Variables set per design: '&ring' names ('width') or 'group:name'.
    x : ndarray, shape (n, len(variables))
        One design per row (SI units, as in a deck).
    outputs : sequence of str, optional
        Scalar results to return (short names; default: all of :data:`SCALARS`).

    Returns
    -------
    values : ndarray, shape (n, len(outputs))
        NaN where a design failed.
    converged : ndarray of bool, shape (n,)
    errors : list of (str or None)
        The error message of each failed design (bad value for the kernel), else None.

    Examples
    --------
    >>> import numpy as np, ringlube
    >>> base = ringlube.Case().with_numerics(nodes=31, dpsi_deg=4.0)
    >>> v, ok, err = run_designs(base, ["width"], np.array([[1.0e-3], [-1.0]]), ["energy_loss"])
    >>> bool(ok[0]), err[1] is not None
    (True, True)
    """
    from . import _kernel
    from .tables import INPUTS

    if isinstance(case, (str, os.PathLike)):
        case = Case.from_namelist(case)
    elif not isinstance(case, Case):
        raise TypeError(f"run_designs: expected a Case or a deck path, got {type(case).__name__}")
    outputs = list(SCALARS if outputs is None else outputs)
    unknown = [o for o in outputs if o not in SCALARS]
    if unknown:
        raise InputError(f"unknown outputs {unknown} (known: {', '.join(SCALARS)})")
    for o in outputs:  # a result the case's film model does not produce is refused, not 0.0
        m = MODELS.get(SCALARS[o].requires)
        if m and case.value(m.group, m.variable) != m.value:
            raise InputError(f"run_designs: {o} needs &{m.group} {m.variable} = '{m.value}' in the case")
    keys = []
    for v in variables:
        group, _, name = str(v).rpartition(":")
        spec = INPUTS.get((group or "ring", name))
        if spec is None or ":" in group:
            raise InputError(
                f"run_designs: '{v}' is not an input variable ('name' of &ring, or 'group:name')"
            )
        if spec.kind not in ("real", "integer") or (spec.group, spec.name) == ("operating", "pressure_file"):
            raise InputError(
                f"run_designs: &{spec.group} {spec.name} is not a number: change it on the case instead"
            )
        if f"{spec.group}:{spec.name}" in keys:
            raise InputError(f"run_designs: '{v}' is &{spec.group} {spec.name} again; give it once")
        keys.append(f"{spec.group}:{spec.name}")
    try:
        x = np.asarray(x, dtype=float)
    except (TypeError, ValueError) as exc:
        raise InputError(f"run_designs: designs must be numbers: {exc}") from None
    if x.size == 0:
        x = x.reshape(0, len(keys))
    if x.ndim != 2 or x.shape[1] != len(keys) or not keys:
        raise InputError(
            f"run_designs: x must have one row per design and one column per "
            f"variable ({len(keys)}), got shape {x.shape}"
        )
    names = list(SCALARS)
    cols = [names.index(o) for o in outputs]
    values = np.full((len(x), len(outputs)), np.nan)
    converged = np.zeros(len(x), bool)
    errors: list = [None] * len(x)
    if len(x) == 0:
        return values, converged, errors
    # (no per-batch warnings: a study warns once, when it reads its base decks)
    with kernel_case(case, warn=False) as k:
        out, codes, messages = _kernel.rl_run_batch(k.handle, " ".join(keys).encode(), x, len(SCALARS))
    if (np.asarray(codes) == INTERRUPTED).any():  # Ctrl-C: the batch stopped within a step
        raise KeyboardInterrupt
    for i, code in enumerate(codes):
        if code:
            errors[i] = kernel_text(messages[i]) or f"design {i}: error code {int(code)}"
            continue
        values[i] = out[i, cols]
        converged[i] = SCALARS["converged"].value(out[i, names.index("converged")])
    return values, converged, errors


def _run_one(args: tuple[Case, bool]):
    try:
        return run(args[0], strict=args[1])
    except RinglubeError as exc:
        return exc
    except (TypeError, ValueError, OSError) as exc:  # not a case: an error of that entry
        return RinglubeError(f"{type(exc).__name__}: {exc}")


def run_many(
    cases: Iterable[Case],
    workers: int | None = None,
    *,
    strict: bool = False,
    progress: bool = True,
    on_error: str = "raise",
) -> list:
    """Run many cases in worker processes; results in input order.

    Parameters
    ----------
    cases : iterable of Case
    workers : int, optional
        Processes (default: the number of cores); 1 runs serially in this process.
    strict : bool
        As in :func:`run`.
    progress : bool
        Show a progress bar.
    on_error : {'raise', 'return'}
        'raise': after every case has run, raise :class:`BatchError` naming the failed
        cases and holding the good results; 'return': failed entries hold their error.

    Returns
    -------
    list of CycleResult (or of errors, with ``on_error='return'``)

    Raises
    ------
    BatchError
        With ``on_error='raise'`` when any case failed.
    ValueError
        For ``workers < 1`` or an unknown ``on_error``.

    Examples
    --------
    >>> import ringlube
    >>> base = ringlube.Case().with_numerics(nodes=31, dpsi_deg=4.0)
    >>> rs = run_many([base, base.with_ring(width=-1)], workers=1, progress=False,
    ...               on_error="return")
    >>> type(rs[1]).__name__
    'InputError'
    """
    from tqdm.auto import tqdm

    if on_error not in ("raise", "return"):
        raise ValueError("on_error must be 'raise' or 'return'")
    cases: Sequence[Case] = list(cases)
    workers = (os.cpu_count() or 1) if workers is None else int(workers)
    if workers < 1:
        raise ValueError(f"workers must be at least 1, got {workers}")
    from .executor import Executor

    bar = tqdm(total=len(cases), desc="ringlube runs", unit="run", disable=not progress)
    out: list = [None] * len(cases)

    def done(i: int, value) -> None:
        out[i] = value
        bar.update()

    ex = Executor(workers=workers, backend="serial" if workers == 1 or len(cases) <= 1 else "processes")
    try:
        ex.map(_run_one, [((c, strict),) for c in cases], done)
    finally:
        ex.close()
        bar.close()
    errors = {i: r for i, r in enumerate(out) if isinstance(r, RinglubeError)}
    if errors and on_error == "raise":
        raise BatchError([None if i in errors else r for i, r in enumerate(out)], errors)
    return out
