"""Where independent tasks run: in this process, in local processes, or on Dask.

One convention for every parallel loop in ringlube: ``executor.map(fn, tasks, on_result)``
calls ``fn(*task)`` for every task and ``on_result(i, value)`` in this process as each one
finishes (in any order), so the caller can save progress as results arrive; an optional
``on_idle()`` is called about every :data:`IDLE_S` seconds while the parallel backends wait,
for progress a save skipped as too soon after the last. An exception
raised by a task or by ``on_result`` (Ctrl-C included) cancels what is still queued and is
raised again.

Backends:

- ``serial``: a plain loop in this process (no extra dependency);
- ``processes``: a :class:`concurrent.futures.ProcessPoolExecutor` with ``workers`` processes;
- ``dask``: a Dask ``LocalCluster`` with ``workers`` single-threaded worker processes;
- ``scheduler``: an existing Dask cluster, given by its scheduler address.

Dask is imported only by the two Dask backends; without it they raise a one-line
:class:`~ringlube.RinglubeError` that says ``pip install ringlube[study]``.
"""

from __future__ import annotations

import contextlib
import logging
import os
import warnings
from collections.abc import Callable, Sequence
from typing import Any

from .errors import InputError, RinglubeError

__all__ = ["Executor", "require", "check_where", "CONNECT_TIMEOUT_S", "BACKENDS"]

#: Seconds to wait for an existing Dask scheduler to answer before giving up.
CONNECT_TIMEOUT_S = 10.0
#: Seconds between calls of ``on_idle`` while the parallel backends wait for results.
IDLE_S = 0.5
#: The backends an :class:`Executor` can use.
BACKENDS = ("serial", "processes", "dask", "scheduler")
#: Dask loggers silenced while a cluster starts, works and closes (their start-up notes,
#: port warnings and the CancelledError of an interrupted map are noise for a user).
_NOISY = (
    "distributed",
    "distributed.worker",
    "distributed.scheduler",
    "distributed.nanny",
    "distributed.core",
    "distributed.comm",
    "distributed.client",
    "tornado",
    "asyncio",
    "bokeh",
)


def _nothing() -> None:
    pass


def require(module: str, what: str) -> Any:
    """Import an optional dependency or fail with a one-line install hint.

    Parameters
    ----------
    module : str
        Module to import, e.g. ``"dask.distributed"``.
    what : str
        What needs it, for the message (e.g. ``"a Dask cluster"``).

    Returns
    -------
    module
        The imported module.

    Raises
    ------
    RinglubeError
        If the module cannot be imported; the message says ``pip install ringlube[study]``.

    Example
    -------
    >>> require("math", "a test").sqrt(4.0)
    2.0
    """
    import importlib

    try:
        return importlib.import_module(module)
    except ImportError as exc:
        raise RinglubeError(
            f"{what} needs the optional package '{module.split('.')[0]}' "
            f"({exc}); install it with: pip install ringlube[study]"
        ) from None


def check_where(scheduler: str | None, serial: bool) -> None:
    """Check where the runs are to go: a usable scheduler address, and not both a scheduler
    and ``serial``.

    Parameters
    ----------
    scheduler : str or None
        ``--scheduler``: the address of a Dask scheduler.
    serial : bool
        ``--serial``: every run in this process.

    Raises
    ------
    InputError
        An empty address, or both given.

    Example
    -------
    >>> check_where("tcp://10.0.0.1:8786", serial=True)
    Traceback (most recent call last):
    ...
    ringlube.errors.InputError: --serial and --scheduler: choose one (this process, or a Dask cluster)
    """
    if scheduler is not None and not str(scheduler).strip():
        raise InputError("--scheduler '': empty address (omit --scheduler for a local cluster)")
    if scheduler is not None and serial:
        raise InputError("--serial and --scheduler: choose one (this process, or a Dask cluster)")


def _workers(workers: int | None) -> int:
    if workers is None:
        return os.cpu_count() or 1
    if isinstance(workers, bool) or not isinstance(workers, int) or workers < 1:
        raise InputError(f"--workers {workers}: must be a whole number of at least 1")
    return workers


class Executor:
    """Runs independent tasks serially, in local processes or on Dask.

    Parameters
    ----------
    scheduler : str, optional
        Address of an existing Dask scheduler (e.g. ``tcp://10.0.0.1:8786``); selects the
        ``scheduler`` backend.
    workers : int, optional
        Worker processes for the ``processes`` and ``dask`` backends (default: one per core).
    serial : bool
        Run every task in this process (the ``serial`` backend).
    backend : str, optional
        One of :data:`BACKENDS`; by default ``scheduler`` if an address is given, else
        ``serial`` if ``serial`` is true, else ``dask``.
    connect_timeout : float, optional
        Seconds to wait for ``scheduler`` (default :data:`CONNECT_TIMEOUT_S`).

    Raises
    ------
    InputError
        ``workers`` below 1 or an unknown backend.
    RinglubeError
        The scheduler cannot be reached within ``connect_timeout`` seconds, or Dask is not
        installed.

    Example
    -------
    >>> seen = {}
    >>> with Executor(serial=True) as ex:
    ...     ex.map(pow, [(2, 3), (3, 2)], seen.__setitem__)
    >>> seen
    {0: 8, 1: 9}
    """

    def __init__(
        self,
        scheduler: str | None = None,
        workers: int | None = None,
        serial: bool = False,
        *,
        backend: str | None = None,
        connect_timeout: float | None = None,
    ):
        check_where(scheduler, serial)
        self.backend = backend or ("scheduler" if scheduler else "serial" if serial else "dask")
        if self.backend not in BACKENDS:
            raise InputError(f"unknown executor backend '{self.backend}' (known: {', '.join(BACKENDS)})")
        self.workers = _workers(workers)
        self.scheduler = scheduler
        self.client = None
        self.cluster = None
        self.pool = None
        if self.backend == "processes":
            from concurrent.futures import ProcessPoolExecutor

            self.pool = ProcessPoolExecutor(max_workers=self.workers)
        elif self.backend == "dask":
            self._start_local_cluster()
        elif self.backend == "scheduler":
            if not scheduler:
                raise InputError("the 'scheduler' backend needs a scheduler address")
            self._connect(scheduler, CONNECT_TIMEOUT_S if connect_timeout is None else connect_timeout)

    # --- Dask set-up -------------------------------------------------------------------
    def _start_local_cluster(self) -> None:
        dd = require("dask.distributed", "a Dask LocalCluster")
        import multiprocessing

        import dask
        from distributed.deploy.spec import SpecCluster

        before = set(SpecCluster._instances)
        children = set(multiprocessing.active_children())
        try:
            # A kernel call holds the GIL for its whole batch, so a worker sends no heartbeat
            # while it runs; a batch longer than the scheduler's worker-ttl (5 min by default:
            # a few designs at the 'accurate' preset on a loaded machine) would get its worker
            # removed and the batch run again, and killed again, until Dask gives it up. The
            # local cluster's workers are this machine's processes: no ttl.
            with (
                _held_interrupts(),
                _quiet(),
                warnings.catch_warnings(),
                dask.config.set({"distributed.scheduler.worker-ttl": None}),
            ):
                # the scheduler's HTTP server asks for port 8787 even without a dashboard; a
                # second study on this machine gets another port, which is not news to a user
                warnings.filterwarnings("ignore", message="Port 8787 is already in use")
                self.cluster = dd.LocalCluster(
                    n_workers=self.workers,
                    threads_per_worker=1,
                    processes=True,
                    dashboard_address=None,
                    silence_logs=logging.CRITICAL,
                )
                self.client = dd.Client(self.cluster)
        except BaseException:  # e.g. a SIGTERM mid start-up: close what started, quietly
            self.close()
            _abandon(set(SpecCluster._instances) - before, set(multiprocessing.active_children()) - children)
            raise

    def _connect(self, address: str, timeout: float) -> None:
        dd = require("dask.distributed", "--scheduler")
        try:
            with _quiet():
                _probe_scheduler(address, timeout)  # Client alone can wait forever on a non-Dask port
                self.client = dd.Client(address, timeout=timeout)
        except Exception as exc:  # OSError, TimeoutError, tornado's and Dask's own types
            reason = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
            raise RinglubeError(
                f"--scheduler {address}: cannot connect within {timeout:g} s ({reason})"
            ) from None

    # --- the one convention ------------------------------------------------------------
    def map(
        self,
        fn: Callable[..., Any],
        tasks: Sequence[tuple],
        on_result: Callable[[int, Any], None],
        on_idle: Callable[[], None] | None = None,
    ) -> None:
        """Call ``fn(*task)`` for every task and ``on_result(i, value)`` as each finishes.

        Parameters
        ----------
        fn : callable
            A module-level function (it is pickled for the process and Dask backends).
        tasks : sequence of tuple
            Positional arguments of each call.
        on_result : callable
            Called in this process with the task's index and ``fn``'s return value, in
            order of completion.
        on_idle : callable, optional
            Called with no argument in this process about every :data:`IDLE_S` seconds
            while the ``processes`` and Dask backends wait for results (the serial backend
            never waits).

        Raises
        ------
        Exception
            Whatever a task or ``on_result`` raised; tasks not yet finished are cancelled.

        Example
        -------
        >>> out = []
        >>> Executor(serial=True).map(abs, [(-1,), (2,)], lambda i, v: out.append((i, v)))
        >>> out
        [(0, 1), (1, 2)]
        """
        if self.backend == "serial":
            for i, task in enumerate(tasks):
                on_result(i, fn(*task))
        elif self.backend == "processes":
            self._map_pool(fn, tasks, on_result, on_idle or _nothing)
        else:
            self._map_dask(fn, tasks, on_result, on_idle or _nothing)

    def _map_pool(self, fn, tasks, on_result, on_idle) -> None:
        from concurrent.futures import FIRST_COMPLETED, wait

        futures = {self.pool.submit(fn, *t): i for i, t in enumerate(tasks)}
        pending = set(futures)
        try:
            while pending:
                done, pending = wait(pending, timeout=IDLE_S, return_when=FIRST_COMPLETED)
                for fut in done:
                    on_result(futures[fut], fut.result())
                on_idle()
        except BaseException:
            for fut in pending:
                fut.cancel()
            raise

    def _map_dask(self, fn, tasks, on_result, on_idle) -> None:
        from dask.distributed import wait

        futures = [self.client.submit(fn, *t, pure=False, retries=2) for t in tasks]
        index = {f.key: i for i, f in enumerate(futures)}
        pending = set(futures)
        with _quiet():  # a lost worker or a cancelled task is handled here, not logged
            try:
                while pending:
                    try:
                        done, pending = wait(pending, timeout=IDLE_S, return_when="FIRST_COMPLETED")
                    except TimeoutError:
                        done = set()
                    for fut in done:
                        on_result(index[fut.key], fut.result())
                    on_idle()
            except BaseException:
                with contextlib.suppress(Exception):
                    self.client.cancel(futures)
                raise

    # --- life cycle --------------------------------------------------------------------
    def close(self) -> None:
        """Release workers and connections (a given scheduler keeps running).

        Example
        -------
        >>> Executor(serial=True).close()
        """
        with _quiet():
            if self.pool is not None:
                self.pool.shutdown(wait=True, cancel_futures=True)
                self.pool = None
            if self.client is not None:
                with contextlib.suppress(Exception):
                    self.client.close()
                self.client = None
            if self.cluster is not None:
                with contextlib.suppress(Exception):
                    self.cluster.close()
                self.cluster = None

    def __enter__(self) -> Executor:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


@contextlib.contextmanager
def _held_interrupts():
    """Hold SIGTERM for the block (a Dask cluster's start-up, 2-4 s), then deliver it to the
    handler of before: an interrupted start-up leaves workers half started, which Dask and
    multiprocessing report with tracebacks at exit; a started cluster closes quietly. SIGINT
    is ignored for the block, so the worker processes started in it inherit an ignored SIGINT:
    a terminal's Ctrl-C reaches every process of the group, and only this one should act on
    it (each worker printed a KeyboardInterrupt traceback). A Ctrl-C during the start-up is not
    seen. Outside the main thread (no signal handlers there) a plain block.
    """
    import signal
    import threading

    if threading.current_thread() is not threading.main_thread():
        yield
        return
    got: list[int] = []
    held = (signal.SIGINT, signal.SIGTERM)
    before = {s: signal.getsignal(s) for s in held}
    for s in held:
        signal.signal(s, lambda signum, frame: got.append(signum))
    # the worker processes started now inherit an ignored SIGINT (a terminal's Ctrl-C goes to
    # every process of the group): this process handles it and closes the cluster, and the
    # workers do not each print a KeyboardInterrupt traceback. A Ctrl-C during the start-up
    # itself is then not seen (2-4 s).
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        yield
    finally:
        for s, handler in before.items():
            if handler is not None:  # None: a handler not set from Python, left alone
                signal.signal(s, handler)
        if got:
            signal.raise_signal(got[0])


def _abandon(clusters, processes) -> None:
    """Close clusters whose start was interrupted, end the worker processes they were
    spawning, and keep Dask's exit hook and its loggers from reporting on them later (its
    ``close_clusters`` asserts on workers that never started; a worker process still
    unpickling its start-up state when this process exits prints a traceback)."""
    with _quiet():
        for cluster in clusters:
            with contextlib.suppress(BaseException):
                cluster.close(timeout=5)
            cluster.shutdown_on_close = False
        for p in processes:
            with contextlib.suppress(BaseException):
                p.terminate()
                p.join(5)
    for name in _NOISY:  # what is left of them is torn down at exit: no more reports
        logging.getLogger(name).setLevel(logging.CRITICAL + 1)


def _probe_scheduler(address: str, timeout: float) -> None:
    """Ask ``address`` who it is, within ``timeout`` seconds in all (connect, handshake, reply).

    Raises
    ------
    TimeoutError
        Nothing answered in time (e.g. a socket that accepts and never speaks).
    RinglubeError
        Something answered that is not a Dask scheduler.
    """
    import asyncio

    from distributed.comm import connect

    async def identity():
        comm = await connect(address, timeout=timeout)
        try:
            await comm.write({"op": "identity", "reply": True})
            return await comm.read()
        finally:
            comm.abort()

    try:
        who = asyncio.run(asyncio.wait_for(identity(), timeout))
    except asyncio.TimeoutError:
        raise TimeoutError("timed out") from None
    if not isinstance(who, dict) or who.get("type") != "Scheduler":
        raise RinglubeError(f"the server there is not a Dask scheduler (it says it is {who!r:.60})")


@contextlib.contextmanager
def _quiet():
    """Silence Dask's and tornado's loggers (restored afterwards)."""
    loggers = [logging.getLogger(name) for name in _NOISY]
    levels = [lg.level for lg in loggers]
    for lg in loggers:
        lg.setLevel(logging.CRITICAL + 1)
    try:
        yield
    finally:
        for lg, level in zip(loggers, levels):
            lg.setLevel(level)
