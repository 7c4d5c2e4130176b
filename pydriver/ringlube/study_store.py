"""The state of a design study and its HDF5 file (typed records, atomic checkpoints).

A study's state is a :class:`Study`: the settings, the samples, and per case (base deck
label, or ``scene``) a :class:`CaseState` of typed records: the true-model :class:`Runs`,
the fitted :class:`Surface` of each result, the GA repeats, the merged :class:`Front`, the
chosen and reference designs re-simulated (:class:`Checked`) and the :class:`Direct`
comparison. :meth:`Study.save` rewrites the whole file atomically (a unique temporary name
in the same folder, then a rename); :meth:`Study.open` reads whatever a file holds, so a
study stopped at any point (even before its first batch was saved) resumes.

Layout (format ``ringlube-study`` version 2, documented in docs/optimisation.md): every
matrix carries ``columns`` and ``units`` attributes (UTF-8 strings), e.g.
``/cases/cold/outputs`` has ``columns = energy_loss, mixed_share, ...`` and
``units = J, %, ...``.
"""

from __future__ import annotations

import dataclasses
import json
import os
import tempfile
import time
from pathlib import Path
from typing import Any

import h5py
import numpy as np

from .errors import InputError, RinglubeError
from .study_settings import StudySettings
from .study_variables import OUTPUTS, output_units

__all__ = [
    "Study",
    "CaseState",
    "Runs",
    "Surface",
    "Front",
    "Checked",
    "Direct",
    "DirectGeneration",
    "Sure",
    "FORMAT",
    "FORMAT_VERSION",
]

#: ``format`` attribute of a study file.
FORMAT = "ringlube-study"
#: Layout version (1: before column labels, typed records and failed runs).
FORMAT_VERSION = 2
_STR = h5py.string_dtype("utf-8")


@dataclasses.dataclass
class Runs:
    """True-model runs of every sample on one case.

    Attributes
    ----------
    outputs : ndarray, shape (n, len(OUTPUTS))
        Every scalar result (:data:`~ringlube.study_variables.OUTPUTS`); NaN until run or
        when the run failed.
    done, converged, failed : ndarray of bool, shape (n,)
        Run (or failed), converged, failed with an error (an invalid design).
    errors : list of str
        The error message of each failed run ("" otherwise).
    wall_s : float
        Wall time spent on these runs, over every session of the study.

    Example
    -------
    >>> r = Runs.empty(3)
    >>> r.done.any(), r.usable().sum()
    (np.False_, np.int64(0))
    """

    outputs: np.ndarray
    done: np.ndarray
    converged: np.ndarray
    failed: np.ndarray
    errors: list[str]
    wall_s: float = 0.0

    @classmethod
    def empty(cls, n: int, k: int = len(OUTPUTS)) -> Runs:
        """Runs of ``n`` samples, none done.

        Parameters
        ----------
        n : int
            Number of samples.
        k : int
            Number of results recorded per sample (the study's outputs).

        Returns
        -------
        Runs

        Example
        -------
        >>> Runs.empty(2).outputs.shape[0]
        2
        """
        return cls(
            np.full((n, k), np.nan),
            np.zeros(n, bool),
            np.zeros(n, bool),
            np.zeros(n, bool),
            [""] * n,
        )

    def usable(self) -> np.ndarray:
        """Samples that ran, converged and did not fail (those the surfaces are fitted to).

        Returns
        -------
        ndarray of bool

        Example
        -------
        >>> Runs.empty(2).usable().tolist()
        [False, False]
        """
        return self.done & self.converged & ~self.failed


@dataclasses.dataclass
class Surface:
    """A fitted quadratic surface of one result (coefficients over the scaled variables).

    Attributes
    ----------
    coef : ndarray
        Coefficients of :func:`~ringlube.surrogate.quadratic_features`.
    r2, r2_adj, cv_rmse, cv_rel : float
        Goodness of fit; k-fold cross-validated RMSE (result's unit) and relative to mean |y|.
    n : int
        Samples fitted.

    Example
    -------
    >>> Surface(np.zeros(3), 1.0, 1.0, 0.0, 0.0, 10).n
    10
    """

    coef: np.ndarray
    r2: float
    r2_adj: float
    cv_rmse: float
    cv_rel: float
    n: int


@dataclasses.dataclass
class Front:
    """The merged non-dominated set of the GA repeats on the surfaces.

    Attributes
    ----------
    x : ndarray, shape (k, d)
        Designs.
    f : ndarray, shape (k, len(objectives))
        Their objectives as the surfaces predict them.
    hv, hv_repeats, hv_ratio_mean, hv_ratio_min : float or ndarray
        Hypervolume of the merged set and of each repeat, and the repeats' ratios to it.
    ref, lo : ndarray
        Reference point and ideal corner of the normalised hypervolume.

    Example
    -------
    >>> Front(np.zeros((1, 2)), np.zeros((1, 2)), 1.0, np.ones(1), 1.0, 1.0,
    ...       np.ones(2), np.zeros(2)).x.shape
    (1, 2)
    """

    x: np.ndarray
    f: np.ndarray
    hv: float
    hv_repeats: np.ndarray
    hv_ratio_mean: float
    hv_ratio_min: float
    ref: np.ndarray
    lo: np.ndarray


@dataclasses.dataclass
class Checked:
    """Designs re-simulated with the true model, beside the surfaces' predictions.

    Attributes
    ----------
    names : list of str
        What each design is (``min energy_loss``, ``knee``, ``reference``).
    x : ndarray, shape (k, d)
        The designs.
    f_true, f_surrogate : ndarray, shape (k, len(OUTPUTS))
        Every result from the true model (NaN if it failed) and from the surfaces.
    converged : ndarray of bool
        Whether each true-model run converged.
    errors : list of str
        Error of each failed run ("" otherwise).

    Example
    -------
    >>> c = Checked(["knee"], np.zeros((1, 1)), np.ones((1, 5)), np.ones((1, 5)) * 1.5,
    ...             np.ones(1, bool), [""])
    >>> float(c.rel_error[0, 0])
    0.5
    """

    names: list[str]
    x: np.ndarray
    f_true: np.ndarray
    f_surrogate: np.ndarray
    converged: np.ndarray
    errors: list[str]

    @property
    def rel_error(self) -> np.ndarray:
        """Surrogate error relative to the true model, ``(surrogate - true) / |true|``.

        Returns
        -------
        ndarray

        Example
        -------
        >>> Checked([], np.zeros((0, 1)), np.ones((0, 5)), np.ones((0, 5)), np.ones(0, bool),
        ...         []).rel_error.shape
        (0, 5)
        """
        with np.errstate(divide="ignore", invalid="ignore"):
            return (self.f_surrogate - self.f_true) / np.abs(self.f_true)


@dataclasses.dataclass
class Direct:
    """NSGA-II on the true model and its comparison with the surrogate front.

    Attributes
    ----------
    x, f : ndarray
        The direct front (true objectives).
    runs, failed, unconverged, lifted : int
        True-model runs made, how many of them failed, did not converge, or converged with
        the ring lifted off the liner at some crank steps (never in the front).
    wall_s : float
        Wall time.
    hv_direct, hv_surrogate, igd_surrogate_to_direct, igd_direct_to_surrogate : float
        Hypervolumes (common reference) and IGDs in normalised objectives.

    Example
    -------
    >>> Direct(np.zeros((1, 1)), np.zeros((1, 1)), 8, 0.1, 0.5, 0.5, 0.0, 0.0).failed
    0
    """

    x: np.ndarray
    f: np.ndarray
    runs: int
    wall_s: float
    hv_direct: float
    hv_surrogate: float
    igd_surrogate_to_direct: float
    igd_direct_to_surrogate: float
    failed: int = 0
    unconverged: int = 0
    lifted: int = 0


@dataclasses.dataclass
class DirectGeneration:
    """One generation of the direct NSGA-II, as evaluated (its checkpoint).

    Attributes
    ----------
    x : ndarray, shape (k, d)
        The designs pymoo asked for.
    f : ndarray, shape (k, len(direct_outputs))
        Their true objectives, then the constrained results that are not objectives
        (:meth:`~ringlube.study_settings.StudySettings.direct_outputs`; NaN where the run
        failed).
    converged, failed : ndarray of bool, shape (k,)
        Whether each run converged, and whether the kernel rejected the design.
    wall_s : float
        Wall time of the generation's runs.

    Example
    -------
    >>> DirectGeneration(np.zeros((2, 1)), np.ones((2, 1)), np.ones(2, bool),
    ...                  np.zeros(2, bool), 0.1).x.shape
    (2, 1)
    """

    x: np.ndarray
    f: np.ndarray
    converged: np.ndarray
    failed: np.ndarray
    wall_s: float = 0.0


@dataclasses.dataclass
class Sure:
    """How sure the chosen designs are: extra true-model runs of them (and the reference).

    Attributes
    ----------
    names : list of str
        The designs (the chosen ones, then ``reference``).
    x : ndarray, shape (k, d)
    nominal : ndarray, shape (k, len(outputs))
        Their results as re-simulated (the study's preset, nominal inputs).
    preset : str
        The ``&numerics preset`` of the base decks.
    accurate : ndarray, shape (k, len(outputs))
        The same designs at preset ``'accurate'``.
    inputs : list of str
        Uncertain inputs varied one at a time (``group:name``).
    factors : list of float
        Each input is multiplied and divided by its factor.
    low, high : ndarray, shape (len(inputs), k, len(outputs))
        Results with the input divided / multiplied by its factor.

    Example
    -------
    >>> Sure(["knee"], np.zeros((1, 1)), np.ones((1, 2)), "fast", np.ones((1, 2)), [], [],
    ...      np.zeros((0, 1, 2)), np.zeros((0, 1, 2))).preset
    'fast'
    """

    names: list[str]
    x: np.ndarray
    nominal: np.ndarray
    preset: str
    accurate: np.ndarray
    inputs: list[str]
    factors: list[float]
    low: np.ndarray
    high: np.ndarray


@dataclasses.dataclass
class CaseState:
    """Everything a study computed for one case (or the weighted scene).

    Example
    -------
    >>> CaseState(Runs.empty(4)).front is None
    True
    """

    runs: Runs
    surfaces: dict[str, Surface] = dataclasses.field(default_factory=dict)
    repeats: dict[int, tuple[np.ndarray, np.ndarray]] = dataclasses.field(default_factory=dict)
    front: Front | None = None
    chosen: Checked | None = None
    reference: Checked | None = None
    direct: Direct | None = None
    direct_generations: list[DirectGeneration] = dataclasses.field(default_factory=list)
    sure: Sure | None = None


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
        True-model runs made by this process.

    Example
    -------
    >>> st = Study.open(read_study("inputs/study_default.nml"), Path("/tmp/x.h5"))  # doctest: +SKIP
    """

    def __init__(self, settings: StudySettings, path: str | os.PathLike):
        self.s = settings
        self.path = Path(path)
        self.runs_executed = 0
        self.x: np.ndarray | None = None
        self.cases: dict[str, CaseState] = {}
        self.stages: set[str] = set()
        self._last_save = 0.0
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
    def open(cls, settings: StudySettings, path: str | os.PathLike, lock: bool = False) -> Study:
        """The study in ``path`` if there is one (checked to match ``settings``), else new.

        Parameters
        ----------
        settings : StudySettings
            The study deck as read now.
        path : path
            The study file.
        lock : bool
            Take the study's lock (:meth:`lock`) before reading; kept until :meth:`unlock`.

        Returns
        -------
        Study

        Raises
        ------
        RinglubeError
            ``lock`` and another process holds the lock.
        InputError
            The file is not a readable study file, belongs to another study, or the study
            was started on other contents of its input files.

        Example
        -------
        >>> study = Study.open(settings, Path("out/s/s.h5"))  # doctest: +SKIP
        """
        st = cls(settings, path)
        if lock:
            st.lock()
        try:
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
        if _text(f.attrs.get("format", "")) != FORMAT:
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
        if _text(f.attrs["key"]) != s.key():
            raise InputError(
                f"{path}: exists and belongs to a study with other samples, cases, variables, "
                "objectives or recorded results (a constraint on a result not recorded before); "
                "use another --out folder"
            )
        started = json.loads(_text(f.attrs["inputs"]))
        changed = [p for p in sorted(set(started) | set(s.inputs)) if started.get(p) != s.inputs.get(p)]
        if changed:
            raise InputError(
                f"{path}: the study was started on other contents of {', '.join(changed)} "
                "(edited since); resuming would mix two models in one surface fit. "
                "Use another --out (or remove the file to start afresh)"
            )
        self.stages = set(json.loads(_text(f.attrs["stages"])))
        if "samples/x" in f:
            self.x = f["samples/x"][()]
            if self.x.shape != (s.samples, len(s.variables)):
                raise ValueError(f"samples/x has shape {self.x.shape}")
        for label in [*s.labels, "scene"]:
            if f"cases/{label}/runs" in f:
                g = f[f"cases/{label}"]
                if _text(g.attrs.get("derived_key", "")) == s.derived_key(label):
                    self.cases[label] = _read_case(g, s)
                elif label != "scene":  # runs kept; what was derived from them is redone
                    self.cases[label] = CaseState(_read_case(g, s).runs)
                # a scene of other weights: recomputed from the cases' runs

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
            return
        self._last_save = now
        fd, tmp = tempfile.mkstemp(dir=self.path.parent, prefix=self.path.name + ".", suffix=".part")
        os.close(fd)
        try:
            with h5py.File(tmp, "w") as f:
                self._write(f)
            os.replace(tmp, self.path)
        finally:
            if os.path.exists(tmp):
                os.unlink(tmp)

    def _write(self, f: h5py.File) -> None:
        from . import __version__

        s = self.s
        f.attrs["format"] = FORMAT
        f.attrs["format_version"] = FORMAT_VERSION
        f.attrs["key"] = s.key()
        f.attrs["inputs"] = json.dumps(s.inputs)
        f.attrs["settings"] = s.to_json()
        f.attrs["deck"] = s.deck_text
        f.attrs["stages"] = json.dumps(sorted(self.stages))
        f.attrs["ringlube_version"] = __version__
        if self.x is not None:
            d = _put(f, "samples/x", self.x, s.variables, s.units)
            d.attrs["lower"] = s.lower
            d.attrs["upper"] = s.upper
        for label, c in self.cases.items():
            g = f.require_group(f"cases/{label}")
            g.attrs["derived_key"] = s.derived_key(label)
            _write_case(g, c, s)


def _text(value: Any) -> str:
    if isinstance(value, (bytes, np.bytes_)):
        return bytes(value).decode(errors="replace")
    return str(value)


def _put(
    parent: h5py.Group, name: str, data: Any, columns: list[str] | None = None, units: list[str] | None = None
) -> h5py.Dataset:
    d = parent.create_dataset(name, data=np.asarray(data))
    if columns is not None:
        d.attrs.create("columns", np.array(columns, dtype=object), dtype=_STR)
    if units is not None:
        d.attrs.create("units", np.array(units, dtype=object), dtype=_STR)
    return d


def _put_strings(parent: h5py.Group, name: str, values: list[str]) -> None:
    parent.create_dataset(name, data=np.array(values, dtype=object), dtype=_STR)


def _strings(d: h5py.Dataset) -> list[str]:
    return [_text(v) for v in d[()]]


def _write_case(g: h5py.Group, c: CaseState, s: StudySettings) -> None:
    units = output_units()
    out_units = [units[o] for o in s.outputs]
    obj_units = [units[o] for o in s.objectives]
    r = g.create_group("runs")
    _put(r, "outputs", c.runs.outputs, list(s.outputs), out_units)
    for k in ("done", "converged", "failed"):
        r.create_dataset(k, data=getattr(c.runs, k))
    _put_strings(r, "errors", c.runs.errors)
    r.attrs["wall_s"] = c.runs.wall_s
    for o, sf in c.surfaces.items():
        sg = g.create_group(f"surface/{o}")
        from .surrogate import term_names

        _put(sg, "coef", sf.coef, term_names(s.variables))
        for k in ("r2", "r2_adj", "cv_rmse", "cv_rel", "n"):
            sg.attrs[k] = getattr(sf, k)
        sg.attrs["unit"] = units[o]
    for rep, (x, fv) in c.repeats.items():
        _put(g, f"repeats/r{rep}/x", x, s.variables, s.units)
        _put(g, f"repeats/r{rep}/f", fv, s.objectives, obj_units)
    if c.front is not None:
        fg = g.create_group("front")
        fr = c.front
        _put(fg, "x", fr.x, s.variables, s.units)
        _put(fg, "f", fr.f, s.objectives, obj_units)
        _put(fg, "hv_repeats", fr.hv_repeats)
        _put(fg, "ref", fr.ref, s.objectives, obj_units)
        _put(fg, "lo", fr.lo, s.objectives, obj_units)
        for k in ("hv", "hv_ratio_mean", "hv_ratio_min"):
            fg.attrs[k] = getattr(fr, k)
    for key in ("chosen", "reference"):
        ch: Checked | None = getattr(c, key)
        if ch is not None:
            cg = g.create_group(key)
            _put_strings(cg, "names", ch.names)
            _put(cg, "x", ch.x, s.variables, s.units)
            _put(cg, "f_true", ch.f_true, list(s.outputs), out_units)
            _put(cg, "f_surrogate", ch.f_surrogate, list(s.outputs), out_units)
            _put(cg, "rel_error", ch.rel_error, list(s.outputs), ["1"] * len(s.outputs))
            cg.create_dataset("converged", data=ch.converged)
            _put_strings(cg, "errors", ch.errors)
    if c.sure is not None:
        su = c.sure
        sg = g.create_group("sure")
        _put_strings(sg, "names", su.names)
        _put_strings(sg, "inputs", su.inputs)
        _put(sg, "x", su.x, s.variables, s.units)
        _put(sg, "nominal", su.nominal, list(s.outputs), out_units)
        _put(sg, "accurate", su.accurate, list(s.outputs), out_units)
        _put(sg, "factors", np.asarray(su.factors, float), su.inputs)
        _put(sg, "low", su.low, list(s.outputs), out_units)
        _put(sg, "high", su.high, list(s.outputs), out_units)
        sg.attrs["preset"] = su.preset
    for k, gen in enumerate(c.direct_generations):
        gg = g.create_group(f"direct_generations/g{k}")
        gg.attrs["key"] = s.derived_key(g.name.rsplit("/", 1)[-1], direct=True)
        gg.attrs["wall_s"] = gen.wall_s
        _put(gg, "x", gen.x, s.variables, s.units)
        _put(gg, "f", gen.f, s.direct_outputs(), [units[o] for o in s.direct_outputs()])
        gg.create_dataset("converged", data=gen.converged)
        gg.create_dataset("failed", data=gen.failed)
    if c.direct is not None:
        dg = g.create_group("direct")
        dg.attrs["key"] = s.derived_key(g.name.rsplit("/", 1)[-1], direct=True)
        _put(dg, "x", c.direct.x, s.variables, s.units)
        _put(dg, "f", c.direct.f, s.objectives, obj_units)
        for fld in dataclasses.fields(Direct):
            if fld.name not in ("x", "f"):
                dg.attrs[fld.name] = getattr(c.direct, fld.name)


def _read_case(g: h5py.Group, s: StudySettings) -> CaseState:
    r = g["runs"]
    n = s.samples
    runs = Runs(
        r["outputs"][()],
        r["done"][()].astype(bool),
        r["converged"][()].astype(bool),
        r["failed"][()].astype(bool),
        _strings(r["errors"]),
        float(r.attrs["wall_s"]),
    )
    if runs.outputs.shape != (n, len(s.outputs)) or runs.done.shape != (n,):
        raise ValueError(f"{g.name}/runs has the wrong shape")
    c = CaseState(runs)
    for o, sg in g.get("surface", {}).items():
        c.surfaces[o] = Surface(
            sg["coef"][()],
            *(float(sg.attrs[k]) for k in ("r2", "r2_adj", "cv_rmse", "cv_rel")),
            int(sg.attrs["n"]),
        )
    for name, rg in g.get("repeats", {}).items():
        c.repeats[int(name[1:])] = (rg["x"][()], rg["f"][()])
    if "front" in g:
        fg = g["front"]
        c.front = Front(
            fg["x"][()],
            fg["f"][()],
            float(fg.attrs["hv"]),
            fg["hv_repeats"][()],
            float(fg.attrs["hv_ratio_mean"]),
            float(fg.attrs["hv_ratio_min"]),
            fg["ref"][()],
            fg["lo"][()],
        )
    for key in ("chosen", "reference"):
        if key in g:
            cg = g[key]
            setattr(
                c,
                key,
                Checked(
                    _strings(cg["names"]),
                    cg["x"][()],
                    cg["f_true"][()],
                    cg["f_surrogate"][()],
                    cg["converged"][()].astype(bool),
                    _strings(cg["errors"]),
                ),
            )
    if "sure" in g:
        sg = g["sure"]
        c.sure = Sure(
            _strings(sg["names"]),
            sg["x"][()],
            sg["nominal"][()],
            _text(sg.attrs["preset"]),
            sg["accurate"][()],
            _strings(sg["inputs"]),
            [float(v) for v in sg["factors"][()]],
            sg["low"][()],
            sg["high"][()],
        )
    direct_key = s.derived_key(g.name.rsplit("/", 1)[-1], direct=True)
    if "direct" in g and _text(g["direct"].attrs.get("key", "")) == direct_key:  # else redone
        dg = g["direct"]
        kw = {
            fld.name: dg.attrs.get(fld.name, fld.default)
            for fld in dataclasses.fields(Direct)
            if fld.name not in ("x", "f")
        }
        c.direct = Direct(dg["x"][()], dg["f"][()], **kw)
    gens = g.get("direct_generations", {})
    for k in range(len(gens)):
        gg = gens[f"g{k}"]
        if _text(gg.attrs.get("key", "")) != direct_key:
            break  # checkpoints of other direct settings: redone
        c.direct_generations.append(
            DirectGeneration(
                gg["x"][()],
                gg["f"][()],
                gg["converged"][()].astype(bool),
                gg["failed"][()].astype(bool),
                float(gg.attrs["wall_s"]),
            )
        )
    return c
