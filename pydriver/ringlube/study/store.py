"""The study file of a design study: :class:`Study` (state, lock, atomic checkpoints).

A study's state is a :class:`Study`: the settings, the samples, and per case (base deck
label, or ``scene``) a :class:`~ringlube.study.state.CaseState` of typed records.
:meth:`Study.save` rewrites the whole file atomically (a unique temporary name in the same
folder, then a rename); :meth:`Study.open` reads whatever a file holds, so a study stopped at
any point (even before its first batch was saved) resumes. The file's layout:
:mod:`ringlube.study.layout`.
"""

from __future__ import annotations

import json
import os
import tempfile
import time
from pathlib import Path

import h5py
import numpy as np

from ..errors import InputError, RinglubeError
from .h5 import put, text
from .layout import FORMAT, FORMAT_VERSION, read_case, read_check_runs, write_case, write_check_runs
from .settings import StudySettings
from .state import CaseState

__all__ = ["Study"]


class Study:
    """State of a study, checkpointed to ``path``.

    Parameters
    ----------
    settings : StudySettings
        The checked study deck.
    path : Path
        The study file (``OUT/NAME.h5``).

    Attributes
    ----------
    x : ndarray or None
        Samples (n x d), None until sampled.
    cases : dict of str to CaseState
        Per case label (and ``scene``).
    stages : set of str
        Finished stages (``sampled``, ``ran``, ``fitted``, ``optimised``, ``checked``,
        ``sure``, ``direct``).
    runs_executed : int
        True-model runs of the samples made by this process.
    check_runs : dict
        The finished true-model runs of the later stages (the check of the candidates and
        reference, the chosen designs at the other points, how sure): per ``(case key, design
        bytes)`` (:func:`ringlube.study.runs.case_key`) the design row, its results, converged
        and error message; kept in the study file (``/check_runs``) so a resume reuses them.
    checks_executed : int
        Runs of :attr:`check_runs` made by this process.

    Example
    -------
    >>> st = Study.open(read_study("inputs/study_default.nml"), Path("/tmp/x.h5"))  # doctest: +SKIP
    """

    def __init__(self, settings: StudySettings, path: str | os.PathLike):
        self.s = settings
        self.path = Path(path)
        self.runs_executed = 0
        self.check_runs: dict[tuple[str, bytes], tuple[np.ndarray, np.ndarray, bool, str]] = {}
        self.checks_executed = 0
        self.x: np.ndarray | None = None
        self.cases: dict[str, CaseState] = {}
        self.stages: set[str] = set()
        self._last_save = 0.0
        self._unsaved = False  # a save was skipped for being within 2 s of the last
        self._lock_fd: int | None = None

    # --- convenience ---------------------------------------------------------------------
    def objectives(self, label: str) -> np.ndarray:
        """The objective columns of a case's outputs (n x len(objectives)).

        Parameters
        ----------
        label : str
            Case label or ``scene``.

        Returns
        -------
        ndarray

        Example
        -------
        >>> study.objectives("cold").shape                    # doctest: +SKIP
        (1025, 3)
        """
        return self.cases[label].runs.outputs[:, self.objective_columns()]

    def objective_columns(self) -> list[int]:
        """Columns of the objectives in the outputs matrices.

        Returns
        -------
        list of int

        Example
        -------
        >>> study.objective_columns()                         # doctest: +SKIP
        [0, 1, 2]
        """
        return [self.s.outputs.index(o) for o in self.s.objectives]

    # --- locking -----------------------------------------------------------------------
    def lock(self) -> None:
        """Take the study's lock file, so two processes never work on one study.

        Raises
        ------
        RinglubeError
            Another process holds it.

        Example
        -------
        >>> study.lock(); study.unlock()                      # doctest: +SKIP
        """
        import fcntl

        lock = self.path.with_name(self.path.name + ".lock")
        fd = os.open(lock, os.O_RDWR | os.O_CREAT, 0o644)
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            os.close(fd)
            raise RinglubeError(
                f"{self.path}: another ringlube optimise is working on this "
                "study; wait for it to finish or use another --out"
            ) from None
        self._lock_fd = fd

    def unlock(self) -> None:
        """Release the lock taken by :meth:`lock` (and remove the lock file).

        Example
        -------
        >>> study.unlock()                                    # doctest: +SKIP
        """
        if self._lock_fd is not None:
            try:
                os.unlink(self.path.with_name(self.path.name + ".lock"))
            except OSError:
                pass
            os.close(self._lock_fd)
            self._lock_fd = None

    # --- reading -----------------------------------------------------------------------
    @classmethod
    def open(
        cls, settings: StudySettings, path: str | os.PathLike, lock: bool = False, restart: bool = False
    ) -> Study:
        """The study in ``path`` if there is one (checked to match ``settings``), else new.

        Parameters
        ----------
        settings : StudySettings
            The study deck as read now.
        path : path
            The study file.
        lock : bool
            Take the study's lock (:meth:`lock`) before reading; kept until :meth:`unlock`.
        restart : bool
            Remove a study file in ``path`` (after taking the lock) instead of reading it.

        Returns
        -------
        Study

        Raises
        ------
        RinglubeError
            ``lock`` and another process holds the lock.
        InputError
            The file is not a readable study file, belongs to another study, or the study
            was started on other contents of its input files or by another kernel build
            (:func:`ringlube.kernel_id`).

        Example
        -------
        >>> study = Study.open(settings, Path("out/s/s.h5"))  # doctest: +SKIP
        """
        st = cls(settings, path)
        if lock:
            st.lock()
        try:
            if restart and st.path.is_file():
                st.path.unlink()
            st._open()
        except BaseException:
            st.unlock()
            raise
        return st

    def _open(self) -> None:
        st, path = self, self.path
        if not path.exists():
            return
        if not path.is_file() or not h5py.is_hdf5(path):
            raise InputError(f"{path}: exists but is not a study file (HDF5); remove it or use another --out")
        try:
            with h5py.File(path, "r") as f:
                st._read(f)
        except InputError:
            raise
        except (OSError, KeyError, ValueError, TypeError, IndexError) as exc:
            reason = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
            raise InputError(
                f"{path}: not a readable study file ({reason}); remove it or use another --out"
            ) from None

    def _read(self, f: h5py.File) -> None:
        path, s = self.path, self.s
        if text(f.attrs.get("format", "")) != FORMAT:
            raise InputError(
                f"{path}: not a ringlube study file (no format attribute, or "
                "written by an older ringlube); remove it or use another --out"
            )
        version = int(f.attrs.get("format_version", 0))
        if version != FORMAT_VERSION:
            raise InputError(
                f"{path}: study file layout {version}, this ringlube reads "
                f"{FORMAT_VERSION}; use another --out"
            )
        if text(f.attrs["key"]) != s.key():
            raise InputError(
                f"{path}: exists and belongs to a study with {_key_changes(f, s)}; its runs cannot "
                "be reused. Use another --out folder, or start afresh with --restart "
                "(ringlube optimise; run_study(restart=True))"
            )
        started = json.loads(text(f.attrs["inputs"]))
        # (a file the study did not record when it started, a face profile or distortion file
        # before those were recorded, is not compared: the deck that names it is)
        changed = [p for p in sorted(started) if started.get(p) != s.inputs.get(p)]
        if changed:
            raise InputError(
                f"{path}: the study was started on other contents of {', '.join(changed)} "
                "(edited since); resuming would mix two models in one surface fit. "
                "Use another --out (or remove the file to start afresh)"
            )
        from .._version import kernel_id

        kernel = text(f.attrs.get("kernel_id", ""))
        if kernel != kernel_id():
            raise InputError(
                f"{path}: the study's runs were made by another ringlube kernel "
                f"({kernel or 'not recorded'}; this one is {kernel_id()}, `ringlube-solve --version`): "
                "resuming would mix two models in one surface fit. Use another --out, or start "
                "afresh with --restart (ringlube optimise; run_study(restart=True))"
            )
        self.stages = set(json.loads(text(f.attrs["stages"])))
        if "samples/x" in f:
            self.x = f["samples/x"][()]
            if self.x.shape != (s.samples, len(s.variables)):
                raise ValueError(f"samples/x has shape {self.x.shape}")
        for label in [*s.labels, "scene"]:
            if f"cases/{label}/runs" in f:
                g = f[f"cases/{label}"]
                if text(g.attrs.get("derived_key", "")) == s.derived_key(label):
                    self.cases[label] = read_case(g, s)
                elif label != "scene":  # runs kept; what was derived from them is redone
                    self.cases[label] = CaseState(read_case(g, s).runs)
                # a scene of other weights: recomputed from the cases' runs
        if "check_runs" in f and text(f["check_runs"].attrs.get("key", "")) == self.check_runs_key():
            self.check_runs = read_check_runs(f["check_runs"])
        # (none, or made with other variables, results or kernel: run again when needed)

    # --- writing -----------------------------------------------------------------------
    def save(self, force: bool = True) -> None:
        """Rewrite the study file atomically (at most every 2 s unless ``force``).

        Parameters
        ----------
        force : bool
            Save even if the last save was less than 2 s ago.

        Raises
        ------
        OSError
            The folder is not writable (the previous file is kept intact).

        Example
        -------
        >>> study.save()                                      # doctest: +SKIP
        """
        now = time.perf_counter()
        if not force and now - self._last_save < 2.0:
            self._unsaved = True
            return
        self._last_save = now
        self._unsaved = False
        fd, tmp = tempfile.mkstemp(dir=self.path.parent, prefix=self.path.name + ".", suffix=".part")
        os.close(fd)
        try:
            with h5py.File(tmp, "w") as f:
                self._write(f)
            os.replace(tmp, self.path)
        finally:
            if os.path.exists(tmp):
                os.unlink(tmp)

    def save_pending(self) -> None:
        """Save now if a save was skipped for coming within 2 s of the last and 2 s have passed.

        Called while waiting for runs, so that a run that finished right after another is on
        disk about 2 s later, not only when the next run finishes.

        Example
        -------
        >>> study.save_pending()                              # doctest: +SKIP
        """
        if self._unsaved:
            self.save(force=False)

    def _write(self, f: h5py.File) -> None:
        from .. import __version__
        from .._version import kernel_id

        s = self.s
        f.attrs["format"] = FORMAT
        f.attrs["format_version"] = FORMAT_VERSION
        f.attrs["key"] = s.key()
        f.attrs["inputs"] = json.dumps(s.inputs)
        f.attrs["settings"] = s.to_json()
        f.attrs["deck"] = s.deck_text
        f.attrs["stages"] = json.dumps(sorted(self.stages))
        f.attrs["ringlube_version"] = __version__
        f.attrs["kernel_id"] = kernel_id()
        if self.x is not None:
            d = put(f, "samples/x", self.x, s.variables, s.units)
            d.attrs["lower"] = s.lower
            d.attrs["upper"] = s.upper
        for label, c in self.cases.items():
            g = f.require_group(f"cases/{label}")
            g.attrs["derived_key"] = s.derived_key(label)
            write_case(g, c, s)
        if self.check_runs:
            g = f.create_group("check_runs")
            g.attrs["key"] = self.check_runs_key()
            write_check_runs(g, self.check_runs, s)

    def check_runs_key(self) -> str:
        """What the stored :attr:`check_runs` were made with besides their case and design:
        the variables (the design's columns), the recorded results and the kernel.

        Returns
        -------
        str
            JSON.

        Example
        -------
        >>> '"kernel"' in study.check_runs_key()             # doctest: +SKIP
        True
        """
        from .._version import kernel_id

        return json.dumps({"variables": self.s.variables, "outputs": self.s.outputs, "kernel": kernel_id()})


#: what each field of :meth:`StudySettings.key` is, in a refused resume's message
_KEY_FIELDS = {
    "cases": "base decks",
    "labels": "labels",
    "variables": "variables",
    "lower": "lower bounds",
    "upper": "upper bounds",
    "objectives": "objectives",
    "outputs": "recorded results (a constraint on a result not recorded before needs new runs)",
    "sampler": "sampler",
    "samples": "samples",
    "seed": "seed",
}


def _key_changes(f: h5py.File, s: StudySettings) -> str:
    """What differs between the study file's key and the deck's now: "other samples (64, now
    32)", "other objectives", ..."""
    try:
        was = json.loads(text(f.attrs["key"]))
    except ValueError:
        was = {}
    now = json.loads(s.key())
    parts = []
    for k, what in _KEY_FIELDS.items():
        if k in was and was.get(k) == now.get(k):
            continue
        short = not isinstance(now.get(k), list) and k in was
        parts.append(f"other {what}" + (f" ({was[k]}, now {now[k]})" if short else ""))
    return ", ".join(parts) or "other settings"
