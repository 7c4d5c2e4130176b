"""The HDF5 layout of a study file: its format, and a case's state composed of its records.

Layout (format ``ringlube-study`` version 2, documented in docs/optimisation.md): every
matrix carries ``columns`` and ``units`` attributes (UTF-8 strings), e.g.
``/cases/cold/outputs`` has ``columns = energy_loss, mixed_share, ...`` and
``units = J, %, ...``. A case group holds one group per record, each written and read by the
record itself (``to_h5``/``from_h5`` of :mod:`ringlube.study.state`,
:mod:`ringlube.study.state_checks` and :class:`~ringlube.study.surrogate.QuadraticSurface`):
``runs``, ``surface/RESULT``, ``repeats/rK/{x,f}``, ``front``, ``candidates``, ``chosen``,
``reference``, ``dominating``, ``sure``, ``direct_generations/gK`` and ``direct`` (the last two with the
``key`` of the direct settings they were computed with). Beside the cases, ``/check_runs``
holds the finished true-model runs of the later stages (:func:`write_check_runs`).
"""

from __future__ import annotations

import h5py
import numpy as np

from .h5 import put, put_strings, strings, text
from .settings import StudySettings
from .state import CaseState, Front, Runs
from .state_checks import Checked, Direct, DirectGeneration, Dominating, Sure
from .surrogate import QuadraticSurface
from .variables import output_units

__all__ = ["FORMAT", "FORMAT_VERSION", "write_case", "read_case", "write_check_runs", "read_check_runs"]

#: ``format`` attribute of a study file.
FORMAT = "ringlube-study"
#: Layout version (1: before column labels, typed records and failed runs).
FORMAT_VERSION = 2


def write_case(g: h5py.Group, c: CaseState, s: StudySettings) -> None:
    """Write a case's state into its (empty) group ``/cases/LABEL``, record by record.

    Parameters
    ----------
    g : h5py.Group
        The case's group; its name ends with the case label.
    c : CaseState
    s : StudySettings

    Example
    -------
    >>> write_case(f.require_group("cases/cold"), study.cases["cold"], study.s)  # doctest: +SKIP
    """
    units = output_units()
    c.runs.to_h5(g.create_group("runs"), s)
    for o, sf in c.surfaces.items():
        sf.to_h5(g.create_group(f"surface/{o}"), s.variables, units[o])
    obj_units = [units[o] for o in s.objectives]
    for rep, (x, fv) in c.repeats.items():
        put(g, f"repeats/r{rep}/x", x, s.variables, s.units)
        put(g, f"repeats/r{rep}/f", fv, s.objectives, obj_units)
    if c.front is not None:
        c.front.to_h5(g.create_group("front"), s)
    for key in ("candidates", "chosen", "reference"):
        ch: Checked | None = getattr(c, key)
        if ch is not None:
            ch.to_h5(g.create_group(key), s)
    if c.dominating is not None:
        c.dominating.to_h5(g.create_group("dominating"), s)
    if c.sure is not None:
        c.sure.to_h5(g.create_group("sure"), s)
    direct_key = s.derived_key(g.name.rsplit("/", 1)[-1], direct=True)
    for k, gen in enumerate(c.direct_generations):
        gg = g.create_group(f"direct_generations/g{k}")
        gg.attrs["key"] = direct_key
        gen.to_h5(gg, s)
    if c.direct is not None:
        dg = g.create_group("direct")
        dg.attrs["key"] = direct_key
        c.direct.to_h5(dg, s)


def read_case(g: h5py.Group, s: StudySettings) -> CaseState:
    """A case's state as :func:`write_case` wrote it (direct results of other settings dropped).

    Parameters
    ----------
    g : h5py.Group
        The case's group ``/cases/LABEL``.
    s : StudySettings
        The study's settings now.

    Returns
    -------
    CaseState

    Raises
    ------
    ValueError
        The runs do not match the settings' samples and results.

    Example
    -------
    >>> c = read_case(f["cases/cold"], study.s)                    # doctest: +SKIP
    """
    runs = Runs.from_h5(g["runs"])
    if runs.outputs.shape != (s.samples, len(s.outputs)) or runs.done.shape != (s.samples,):
        raise ValueError(f"{g.name}/runs has the wrong shape")
    c = CaseState(runs)
    for o, sg in g.get("surface", {}).items():
        c.surfaces[o] = QuadraticSurface.from_h5(sg, s.lower, s.upper)
    for name, rg in g.get("repeats", {}).items():
        c.repeats[int(name[1:])] = (rg["x"][()], rg["f"][()])
    if "front" in g:
        c.front = Front.from_h5(g["front"])
    for key in ("candidates", "chosen", "reference"):
        if key in g:
            setattr(c, key, Checked.from_h5(g[key]))
    if "dominating" in g:  # (absent in files written before it: computed again from the runs)
        c.dominating = Dominating.from_h5(g["dominating"])
    if "sure" in g:
        c.sure = Sure.from_h5(g["sure"])
    direct_key = s.derived_key(g.name.rsplit("/", 1)[-1], direct=True)
    if "direct" in g and text(g["direct"].attrs.get("key", "")) == direct_key:  # else redone
        c.direct = Direct.from_h5(g["direct"])
    gens = g.get("direct_generations", {})
    for k in range(len(gens)):
        gg = gens[f"g{k}"]
        if text(gg.attrs.get("key", "")) != direct_key:
            break  # checkpoints of other direct settings: redone
        c.direct_generations.append(DirectGeneration.from_h5(gg))
    return c


def write_check_runs(
    g: h5py.Group, runs: dict[tuple[str, bytes], tuple[np.ndarray, np.ndarray, bool, str]], s: StudySettings
) -> None:
    """Write the finished runs of the later stages (the check, the chosen designs at the other
    points, how sure) into the empty group ``/check_runs``: one row per run, ``case`` (the key
    of the deck run, :func:`ringlube.study.runs.case_key`), ``x`` (the design), ``outputs``,
    ``converged`` and ``errors``.

    Parameters
    ----------
    g : h5py.Group
    runs : dict
        :attr:`ringlube.study.store.Study.check_runs`.
    s : StudySettings

    Example
    -------
    >>> write_check_runs(f.create_group("check_runs"), study.check_runs, study.s)  # doctest: +SKIP
    """
    units = output_units()
    rows = list(runs.items())
    put_strings(g, "case", [k[0] for k, _ in rows])
    x = np.array([r[0] for _, r in rows], float).reshape(len(rows), len(s.variables))
    put(g, "x", x, s.variables, s.units)
    put(
        g,
        "outputs",
        np.array([r[1] for _, r in rows], float).reshape(len(rows), len(s.outputs)),
        list(s.outputs),
        [units[o] for o in s.outputs],
    )
    g.create_dataset("converged", data=np.array([r[2] for _, r in rows], bool))
    put_strings(g, "errors", [r[3] for _, r in rows])


def read_check_runs(g: h5py.Group) -> dict[tuple[str, bytes], tuple[np.ndarray, np.ndarray, bool, str]]:
    """The runs :func:`write_check_runs` wrote into ``g``.

    Parameters
    ----------
    g : h5py.Group

    Returns
    -------
    dict

    Raises
    ------
    ValueError
        The datasets do not have one row per run.

    Example
    -------
    >>> len(read_check_runs(f["check_runs"]))                      # doctest: +SKIP
    120
    """
    cases, errors = strings(g["case"]), strings(g["errors"])
    x, outputs, converged = g["x"][()], g["outputs"][()], g["converged"][()].astype(bool)
    if not (len(cases) == len(errors) == len(x) == len(outputs) == len(converged)):
        raise ValueError(f"{g.name} has datasets of different lengths")
    return {
        (c, np.ascontiguousarray(xi, float).tobytes()): (xi, fi, bool(ok), e)
        for c, xi, fi, ok, e in zip(cases, x, outputs, converged, errors)
    }
