"""The HDF5 layout of a study file: its format, and a case's state written and read.

Layout (format ``ringlube-study`` version 2, documented in docs/optimisation.md): every
matrix carries ``columns`` and ``units`` attributes (UTF-8 strings), e.g.
``/cases/cold/outputs`` has ``columns = energy_loss, mixed_share, ...`` and
``units = J, %, ...``.
"""

from __future__ import annotations

import dataclasses

import h5py
import numpy as np

from .study_h5 import put, put_strings, strings, text
from .study_settings import StudySettings
from .study_state import CaseState, Checked, Direct, DirectGeneration, Front, Runs, Sure, Surface
from .study_variables import output_units

__all__ = ["FORMAT", "FORMAT_VERSION"]

#: ``format`` attribute of a study file.
FORMAT = "ringlube-study"
#: Layout version (1: before column labels, typed records and failed runs).
FORMAT_VERSION = 2


def write_case(g: h5py.Group, c: CaseState, s: StudySettings) -> None:
    units = output_units()
    out_units = [units[o] for o in s.outputs]
    obj_units = [units[o] for o in s.objectives]
    r = g.create_group("runs")
    put(r, "outputs", c.runs.outputs, list(s.outputs), out_units)
    for k in ("done", "converged", "failed"):
        r.create_dataset(k, data=getattr(c.runs, k))
    put_strings(r, "errors", c.runs.errors)
    r.attrs["wall_s"] = c.runs.wall_s
    for o, sf in c.surfaces.items():
        sg = g.create_group(f"surface/{o}")
        from .surrogate import term_names

        put(sg, "coef", sf.coef, term_names(s.variables))
        for k in ("r2", "r2_adj", "cv_rmse", "cv_rel", "n"):
            sg.attrs[k] = getattr(sf, k)
        sg.attrs["unit"] = units[o]
    for rep, (x, fv) in c.repeats.items():
        put(g, f"repeats/r{rep}/x", x, s.variables, s.units)
        put(g, f"repeats/r{rep}/f", fv, s.objectives, obj_units)
    if c.front is not None:
        fg = g.create_group("front")
        fr = c.front
        put(fg, "x", fr.x, s.variables, s.units)
        put(fg, "f", fr.f, s.objectives, obj_units)
        put(fg, "hv_repeats", fr.hv_repeats)
        put(fg, "ref", fr.ref, s.objectives, obj_units)
        put(fg, "lo", fr.lo, s.objectives, obj_units)
        for k in ("hv", "hv_ratio_mean", "hv_ratio_min"):
            fg.attrs[k] = getattr(fr, k)
    for key in ("chosen", "reference"):
        ch: Checked | None = getattr(c, key)
        if ch is not None:
            cg = g.create_group(key)
            put_strings(cg, "names", ch.names)
            put(cg, "x", ch.x, s.variables, s.units)
            put(cg, "f_true", ch.f_true, list(s.outputs), out_units)
            put(cg, "f_surrogate", ch.f_surrogate, list(s.outputs), out_units)
            put(cg, "rel_error", ch.rel_error, list(s.outputs), ["1"] * len(s.outputs))
            cg.create_dataset("converged", data=ch.converged)
            put_strings(cg, "errors", ch.errors)
    if c.sure is not None:
        su = c.sure
        sg = g.create_group("sure")
        put_strings(sg, "names", su.names)
        put_strings(sg, "inputs", su.inputs)
        put(sg, "x", su.x, s.variables, s.units)
        put(sg, "nominal", su.nominal, list(s.outputs), out_units)
        put(sg, "accurate", su.accurate, list(s.outputs), out_units)
        put(sg, "factors", np.asarray(su.factors, float), su.inputs)
        put(sg, "low", su.low, list(s.outputs), out_units)
        put(sg, "high", su.high, list(s.outputs), out_units)
        sg.attrs["preset"] = su.preset
    for k, gen in enumerate(c.direct_generations):
        gg = g.create_group(f"direct_generations/g{k}")
        gg.attrs["key"] = s.derived_key(g.name.rsplit("/", 1)[-1], direct=True)
        gg.attrs["wall_s"] = gen.wall_s
        put(gg, "x", gen.x, s.variables, s.units)
        put(gg, "f", gen.f, s.direct_outputs(), [units[o] for o in s.direct_outputs()])
        gg.create_dataset("converged", data=gen.converged)
        gg.create_dataset("failed", data=gen.failed)
    if c.direct is not None:
        dg = g.create_group("direct")
        dg.attrs["key"] = s.derived_key(g.name.rsplit("/", 1)[-1], direct=True)
        put(dg, "x", c.direct.x, s.variables, s.units)
        put(dg, "f", c.direct.f, s.objectives, obj_units)
        for fld in dataclasses.fields(Direct):
            if fld.name not in ("x", "f"):
                dg.attrs[fld.name] = getattr(c.direct, fld.name)


def read_case(g: h5py.Group, s: StudySettings) -> CaseState:
    r = g["runs"]
    n = s.samples
    runs = Runs(
        r["outputs"][()],
        r["done"][()].astype(bool),
        r["converged"][()].astype(bool),
        r["failed"][()].astype(bool),
        strings(r["errors"]),
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
                    strings(cg["names"]),
                    cg["x"][()],
                    cg["f_true"][()],
                    cg["f_surrogate"][()],
                    cg["converged"][()].astype(bool),
                    strings(cg["errors"]),
                ),
            )
    if "sure" in g:
        sg = g["sure"]
        c.sure = Sure(
            strings(sg["names"]),
            sg["x"][()],
            sg["nominal"][()],
            text(sg.attrs["preset"]),
            sg["accurate"][()],
            strings(sg["inputs"]),
            [float(v) for v in sg["factors"][()]],
            sg["low"][()],
            sg["high"][()],
        )
    direct_key = s.derived_key(g.name.rsplit("/", 1)[-1], direct=True)
    if "direct" in g and text(g["direct"].attrs.get("key", "")) == direct_key:  # else redone
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
        if text(gg.attrs.get("key", "")) != direct_key:
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
