"""Design optimisation (SPEC section 12): sample -> run -> fit -> NSGA-II -> check.

A study deck (namelist group ``&study``) names the base decks (one per condition or
operating point, with weights), the design variables and their ranges, the objectives,
the sampler and sample count, the surrogate, the GA settings and the seed. Everything
the study computes goes into one HDF5 file, rewritten atomically at every checkpoint,
so an interrupted study started again with the same command resumes and re-runs
nothing that finished. Runs go to Dask: a LocalCluster with one worker per core by
default, or an existing cluster (``--scheduler ADDRESS``).
"""

from __future__ import annotations

import dataclasses
import json
import os
import time
from pathlib import Path
from typing import Callable

import f90nml
import h5py
import numpy as np

from .case import Case
from .errors import InputError

__all__ = ["StudySettings", "Study", "read_study", "run_study"]

OBJECTIVES = {"energy_loss": "J/cycle", "mixed_share": "%", "ring_mass": "g",
              "max_friction": "N", "min_film": "m"}
UNITS_SCALE = {"width": 1e3, "crown_height": 1e6, "crown_offset": 1e6, "tension": 1.0}
UNITS_LABEL = {"width": "width [mm]", "crown_height": "crown height [um]",
               "crown_offset": "crown offset [um]", "tension": "tension"}
#: The study's published optimum (Table 2), for the plots and the closing comparison.
STUDY_OPTIMUM = {"width": 1.0e-3, "crown_height": 9.31e-6, "crown_offset": -38.3e-6, "tension": 8.0}


@dataclasses.dataclass
class StudySettings:
    name: str
    cases: list[str]
    labels: list[str]
    weights: list[float]
    variables: list[str]
    lower: list[float]
    upper: list[float]
    objectives: list[str]
    sampler: str = "sobol"
    samples: int = 10001
    surrogate: str = "quadratic"
    population: int = 200
    generations: int = 200
    repeats: int = 20
    seed: int = 1
    scene: bool = False
    folds: int = 5
    direct_population: int = 40
    direct_generations: int = 25
    batch: int = 16
    deck_text: str = ""
    source: str = ""

    def key(self) -> str:
        """What must match for a study file to be resumed (not the GA/direct settings)."""
        d = dataclasses.asdict(self)
        return json.dumps({k: d[k] for k in ("cases", "labels", "variables", "lower", "upper",
                                              "objectives", "sampler", "samples", "seed")})


def _as_list(v) -> list:
    return list(v) if isinstance(v, (list, tuple)) else [v]


def read_study(path: str | os.PathLike) -> StudySettings:
    """Read a ``&study`` deck; relative case paths are relative to the deck's folder."""
    path = Path(path)
    if not path.is_file():
        raise InputError(f"{path}: file not found")
    try:
        nml = f90nml.read(path)
    except Exception as exc:
        raise InputError(f"{path}: cannot parse namelist: {exc}") from exc
    if "study" not in nml:
        raise InputError(f"{path}: no &study group")
    s = dict(nml["study"])
    known = {f.name for f in dataclasses.fields(StudySettings)} - {"deck_text", "source"}
    for k in s:
        if k not in known:
            raise InputError(f"{path}: &study {k}: unknown variable")

    def need(k):
        if k not in s:
            raise InputError(f"{path}: &study {k}: required")
        return s[k]

    cases = [str((path.parent / c).resolve()) for c in _as_list(need("cases"))]
    labels = [str(v) for v in _as_list(s.get("labels", [Path(c).stem for c in cases]))]
    weights = [float(v) for v in _as_list(s.get("weights", [1.0] * len(cases)))]
    variables = [str(v) for v in _as_list(s.get("variables", list(STUDY_OPTIMUM)))]
    defaults = {"width": (0.54e-3, 1.34e-3), "crown_height": (6e-6, 13e-6),
                "crown_offset": (-54e-6, 67e-6), "tension": (8.0, 26.0)}
    lower = [float(v) for v in _as_list(s.get("lower", [defaults[v][0] for v in variables]))]
    upper = [float(v) for v in _as_list(s.get("upper", [defaults[v][1] for v in variables]))]
    st = StudySettings(
        name=str(s.get("name", path.stem)), cases=cases, labels=labels, weights=weights,
        variables=variables, lower=lower, upper=upper,
        objectives=[str(v) for v in _as_list(s.get("objectives", ["energy_loss", "mixed_share", "ring_mass"]))],
        **{k: s[k] for k in ("sampler", "samples", "surrogate", "population", "generations",
                             "repeats", "seed", "scene", "folds", "direct_population",
                             "direct_generations", "batch") if k in s},
        deck_text=path.read_text(), source=str(path))
    # checks, each naming the variable
    def bad(var, why):
        raise InputError(f"{path}: &study {var}: {why}")
    if not st.name or any(ch in st.name for ch in "/\\") or st.name.startswith("."):
        bad("name", "must be a plain file name (no folders): it names the study file")
    if len(labels) != len(cases) or len(set(labels)) != len(labels):
        bad("labels", "one distinct label per case")
    if len(weights) != len(cases) or any(w <= 0 for w in weights):
        bad("weights", "one positive weight per case")
    if not (len(lower) == len(upper) == len(variables)):
        bad("lower", "one lower and one upper bound per variable")
    if any(lo >= hi for lo, hi in zip(lower, upper)):
        bad("upper", "each upper bound must exceed its lower bound")
    for o in st.objectives:
        if o not in OBJECTIVES:
            bad("objectives", f"unknown objective '{o}' (known: {', '.join(OBJECTIVES)})")
    if st.sampler not in ("sobol", "lhs"):
        bad("sampler", "must be 'sobol' or 'lhs'")
    if st.surrogate != "quadratic":
        bad("surrogate", "must be 'quadratic'")
    nterms = 1 + 2 * len(variables) + len(variables) * (len(variables) - 1) // 2
    if st.samples < nterms + st.folds:
        bad("samples", f"need at least {nterms + st.folds} for a quadratic in {len(variables)} variables")
    for k in ("population", "generations", "repeats", "direct_population", "direct_generations", "batch"):
        if getattr(st, k) < 1:
            bad(k, "must be at least 1")
    for c in cases:
        Case.from_namelist(c)   # the kernel checks each base deck now, not after hours
    return st


# --- running designs -----------------------------------------------------------------

def _design_case(base: dict, variables: list[str], x: np.ndarray) -> Case:
    case = Case(base)
    for name, value in zip(variables, x):
        group, _, var = name.rpartition(":")
        case.set(group or "ring", **{var: float(value)})
    return case


def run_batch(base: dict, variables: list[str], xs: np.ndarray, objectives: list[str]) -> np.ndarray:
    """Worker task: run designs, return rows [objectives..., converged]."""
    from .solve import run

    out = np.empty((len(xs), len(objectives) + 1))
    for i, x in enumerate(xs):
        r = run(_design_case(base, variables, x))
        out[i, :-1] = [getattr(r, o) for o in objectives]
        out[i, -1] = float(r.converged)
    return out


class Executor:
    """Runs batches on Dask (LocalCluster or a given scheduler) or serially in-process."""

    def __init__(self, scheduler: str | None = None, workers: int | None = None,
                 serial: bool = False):
        self.client = None
        self.cluster = None
        if serial:
            return
        from dask.distributed import Client, LocalCluster

        if scheduler:
            self.client = Client(scheduler)
        else:
            self.cluster = LocalCluster(n_workers=workers or os.cpu_count() or 1,
                                        threads_per_worker=1, processes=True,
                                        dashboard_address=None)
            self.client = Client(self.cluster)

    def map(self, fn: Callable, tasks: list[tuple], on_result: Callable[[int, object], None]) -> None:
        """Call ``fn(*task)`` for every task; ``on_result(i, value)`` as each finishes."""
        if self.client is None:
            for i, t in enumerate(tasks):
                on_result(i, fn(*t))
            return
        from dask.distributed import as_completed

        futures = [self.client.submit(fn, *t, pure=False, retries=2) for t in tasks]
        index = {f.key: i for i, f in enumerate(futures)}
        try:
            for fut, value in as_completed(futures, with_results=True):
                on_result(index[fut.key], value)
        except BaseException:
            self.client.cancel(futures)
            raise

    def close(self) -> None:
        if self.client is not None:
            self.client.close()
        if self.cluster is not None:
            self.cluster.close()


# --- the study file ------------------------------------------------------------------

class Study:
    """State of a study, checkpointed to ``path`` (HDF5, atomic rewrite)."""

    def __init__(self, settings: StudySettings, path: Path):
        self.s = settings
        self.path = path
        self.runs_executed = 0      # in this process
        self.x: np.ndarray | None = None
        self.cases: dict[str, dict] = {}
        self.stages: set[str] = set()
        self.log: list[str] = []
        self._last_save = 0.0

    # persistence
    @classmethod
    def open(cls, settings: StudySettings, path: Path) -> "Study":
        st = cls(settings, path)
        if path.exists():
            with h5py.File(path, "r") as f:
                if f.attrs.get("key") != settings.key():
                    raise InputError(f"{path}: exists and belongs to a study with other samples, "
                                     "cases or variables; use another --out folder")
                st.stages = set(json.loads(f.attrs["stages"]))
                st.x = f["samples/x"][()]
                for label in settings.labels + (["scene"] if "cases/scene" in f else []):
                    g = f[f"cases/{label}"]
                    st.cases[label] = _read_group(g)
        return st

    def save(self, force: bool = True) -> None:
        now = time.perf_counter()
        if not force and now - self._last_save < 2.0:
            return
        self._last_save = now
        tmp = self.path.with_name(self.path.name + ".part")
        with h5py.File(tmp, "w") as f:
            f.attrs["key"] = self.s.key()
            f.attrs["settings"] = json.dumps(dataclasses.asdict(self.s))
            f.attrs["deck"] = self.s.deck_text
            f.attrs["stages"] = json.dumps(sorted(self.stages))
            from . import __version__
            f.attrs["ringlube_version"] = __version__
            if self.x is not None:
                d = f.create_dataset("samples/x", data=self.x)
                d.attrs["variables"] = json.dumps(self.s.variables)
                d.attrs["lower"] = self.s.lower
                d.attrs["upper"] = self.s.upper
            for label, data in self.cases.items():
                _write_group(f.require_group(f"cases/{label}"), data)
        os.replace(tmp, self.path)


def _write_group(g: h5py.Group, data: dict) -> None:
    for k, v in data.items():
        if isinstance(v, dict):
            _write_group(g.require_group(k), v)
        elif isinstance(v, str):
            g.attrs[k] = v
        elif np.isscalar(v):
            g.attrs[k] = v
        else:
            g.create_dataset(k, data=np.asarray(v))


def _read_group(g: h5py.Group) -> dict:
    out: dict = {k: (v.decode() if isinstance(v, bytes) else v) for k, v in g.attrs.items()}
    for k, v in g.items():
        out[k] = _read_group(v) if isinstance(v, h5py.Group) else v[()]
    return out


# --- the pipeline --------------------------------------------------------------------

def sample(s: StudySettings) -> np.ndarray:
    """Sobol or Latin hypercube sample of the design box (scipy.stats.qmc)."""
    from scipy.stats import qmc

    d = len(s.variables)
    if s.sampler == "sobol":
        eng = qmc.Sobol(d=d, scramble=True, seed=s.seed)
        m = int(np.ceil(np.log2(s.samples)))
        u = eng.random_base2(m)[: s.samples]
    else:
        u = qmc.LatinHypercube(d=d, seed=s.seed).random(s.samples)
    return qmc.scale(u, s.lower, s.upper)


def _objective_matrix(study: Study, label: str) -> tuple[np.ndarray, np.ndarray]:
    c = study.cases[label]
    ok = c["done"].astype(bool) & c["converged"].astype(bool)
    return study.x[ok], c["objectives"][ok]


def run_samples(study: Study, ex: Executor, progress: bool = True,
                stop_after: int | None = None) -> None:
    """Run every sample on every case; finished runs are kept across interruptions."""
    from tqdm.auto import tqdm

    s = study.s
    n, m = s.samples, len(s.objectives)
    for label in s.labels:
        if label not in study.cases:
            study.cases[label] = {"objectives": np.full((n, m), np.nan),
                                  "done": np.zeros(n, bool), "converged": np.zeros(n, bool)}
    tasks, where = [], []
    for ci, (label, deck) in enumerate(zip(s.labels, s.cases)):
        base = Case.from_namelist(deck).to_dict()
        todo = np.flatnonzero(~study.cases[label]["done"].astype(bool))
        for chunk in np.array_split(todo, max(1, int(np.ceil(len(todo) / s.batch)))):
            if len(chunk):
                tasks.append((base, s.variables, study.x[chunk], s.objectives))
                where.append((label, chunk))
    total = sum(len(c) for _, c in where)
    if total == 0:
        return
    bar = tqdm(total=total, desc="true-model runs", unit="run", disable=not progress)

    def on_result(i, rows):
        label, chunk = where[i]
        c = study.cases[label]
        c["objectives"][chunk] = rows[:, :-1]
        c["converged"][chunk] = rows[:, -1] > 0.5
        c["done"][chunk] = True
        study.runs_executed += len(chunk)
        bar.update(len(chunk))
        study.save(force=False)
        if stop_after is not None and study.runs_executed >= stop_after:
            raise KeyboardInterrupt("stop_after reached (test hook)")

    try:
        ex.map(run_batch, tasks, on_result)
    finally:
        bar.close()
        study.save()


def fit_surfaces(study: Study) -> None:
    from .surrogate import cross_validate, fit_quadratic

    s = study.s
    for label in study.cases:
        x, y = _objective_matrix(study, label)
        surfaces = {}
        for j, o in enumerate(s.objectives):
            surf = fit_quadratic(x, y[:, j], s.lower, s.upper)
            rmse, rel = cross_validate(x, y[:, j], s.lower, s.upper, k=s.folds, seed=s.seed)
            surfaces[o] = {"coef": surf.coef, "r2": surf.r2, "r2_adj": surf.r2_adj,
                           "cv_rmse": rmse, "cv_rel": rel, "n": len(y)}
        study.cases[label]["surface"] = surfaces


def surfaces_of(study: Study, label: str):
    from .surrogate import QuadraticSurface

    s = study.s
    sf = study.cases[label]["surface"]
    return [QuadraticSurface(np.array(s.lower), np.array(s.upper), np.asarray(sf[o]["coef"]))
            for o in s.objectives]


def ga_repeat(coefs: list[np.ndarray], lower, upper, population: int, generations: int,
              seed: int) -> tuple[np.ndarray, np.ndarray]:
    """One NSGA-II run (pymoo) on the quadratic surfaces; returns (X, F) of its front."""
    from pymoo.algorithms.moo.nsga2 import NSGA2
    from pymoo.core.problem import Problem
    from pymoo.optimize import minimize

    from .surrogate import QuadraticSurface

    lower, upper = np.asarray(lower, float), np.asarray(upper, float)
    surfs = [QuadraticSurface(lower, upper, np.asarray(c)) for c in coefs]

    class Surrogate(Problem):
        def __init__(self):
            super().__init__(n_var=len(lower), n_obj=len(surfs), xl=lower, xu=upper)

        def _evaluate(self, x, out, *args, **kwargs):
            out["F"] = np.column_stack([f(x) for f in surfs])

    res = minimize(Surrogate(), NSGA2(pop_size=population), ("n_gen", generations), seed=seed,
                   verbose=False)
    return np.atleast_2d(res.X), np.atleast_2d(res.F)


def nondominated(f: np.ndarray) -> np.ndarray:
    from pymoo.util.nds.non_dominated_sorting import NonDominatedSorting

    return NonDominatedSorting().do(f, only_non_dominated_front=True)


def hypervolume(f: np.ndarray, ref: np.ndarray, lo: np.ndarray) -> float:
    """Hypervolume of f in objectives normalised by (ref - lo), reference point 1."""
    from pymoo.indicators.hv import HV

    return float(HV(ref_point=np.ones(len(ref)))((f - lo) / (ref - lo)))


def optimise(study: Study, ex: Executor, progress: bool = True) -> None:
    """NSGA-II on each case's surfaces, repeated with distinct seeds, merged."""
    from tqdm.auto import tqdm

    s = study.s
    tasks, where = [], []
    for label in study.cases:
        reps = study.cases[label].setdefault("repeats", {})
        coefs = [np.asarray(study.cases[label]["surface"][o]["coef"]) for o in s.objectives]
        for r in range(s.repeats):
            if f"r{r}" not in reps:
                tasks.append((coefs, s.lower, s.upper, s.population, s.generations, s.seed + 1000 * r))
                where.append((label, r))
    bar = tqdm(total=len(tasks), desc="NSGA-II repeats", disable=not progress or not tasks)

    def on_result(i, xf):
        label, r = where[i]
        study.cases[label]["repeats"][f"r{r}"] = {"x": xf[0], "f": xf[1]}
        bar.update()
        study.save(force=False)

    try:
        ex.map(ga_repeat, tasks, on_result)
    finally:
        bar.close()
        study.save()
    for label in study.cases:
        reps = study.cases[label]["repeats"]
        xs = np.vstack([reps[f"r{r}"]["x"] for r in range(s.repeats)])
        fs = np.vstack([reps[f"r{r}"]["f"] for r in range(s.repeats)])
        keep = nondominated(fs)
        fx, ff = xs[keep], fs[keep]
        lo, ref = ff.min(0), ff.max(0) + 0.1 * (ff.max(0) - ff.min(0) + 1e-12)
        hv_all = hypervolume(ff, ref, lo)
        hv_reps = np.array([hypervolume(reps[f"r{r}"]["f"], ref, lo) for r in range(s.repeats)])
        study.cases[label]["front"] = {"x": fx, "f": ff, "hv": hv_all, "hv_repeats": hv_reps,
                                       "hv_ratio_mean": float(hv_reps.mean() / hv_all),
                                       "hv_ratio_min": float(hv_reps.min() / hv_all),
                                       "ref": ref, "lo": lo}


def choose_designs(study: Study) -> dict[str, np.ndarray]:
    """The extremes of each objective on the merged front and the knee point."""
    out = {}
    for label in study.cases:
        fr = study.cases[label]["front"]
        x, f = np.asarray(fr["x"]), np.asarray(fr["f"])
        idx = [int(np.argmin(f[:, j])) for j in range(f.shape[1])]
        z = (f - f.min(0)) / np.maximum(f.max(0) - f.min(0), 1e-300)
        knee = int(np.argmin(np.linalg.norm(z, axis=1)))
        names = [f"min {o}" for o in study.s.objectives] + ["knee"]
        out[label] = (names, x[idx + [knee]])
    return out


def check_designs(study: Study, ex: Executor) -> None:
    """Re-simulate the chosen designs with the true model; surrogate error at them."""
    s = study.s
    chosen = choose_designs(study)
    tasks, where = [], []
    for label, (names, xs) in chosen.items():
        if label == "scene":
            continue
        base = Case.from_namelist(s.cases[s.labels.index(label)]).to_dict()
        tasks.append((base, s.variables, xs, s.objectives))
        where.append(label)
        # the study's published optimum too, for comparison
        tasks.append((base, s.variables,
                      np.array([[STUDY_OPTIMUM.get(v, np.nan) for v in s.variables]]), s.objectives))
        where.append(label + "#study")
    results = {}
    ex.map(run_batch, tasks, lambda i, rows: results.__setitem__(where[i], rows))
    for label, (names, xs) in chosen.items():
        if label == "scene":
            continue
        surfs = surfaces_of(study, label)
        pred = np.column_stack([f(xs) for f in surfs])
        true = results[label][:, :-1]
        study.cases[label]["chosen"] = {"names": json.dumps(names), "x": xs, "f_surrogate": pred,
                                        "f_true": true,
                                        "rel_error": (pred - true) / np.abs(true)}
        if all(v in STUDY_OPTIMUM for v in s.variables):
            xo = np.array([[STUDY_OPTIMUM[v] for v in s.variables]])
            study.cases[label]["study_optimum"] = {
                "x": xo, "f_true": results[label + "#study"][:, :-1],
                "f_surrogate": np.column_stack([f(xo) for f in surfs])}


def scene_objectives(study: Study) -> None:
    """Weighted scene: objectives averaged over the cases with their weights."""
    s = study.s
    w = np.array(s.weights) / sum(s.weights)
    objs = [study.cases[label]["objectives"] for label in s.labels]
    done = np.all([study.cases[label]["done"] for label in s.labels], axis=0)
    conv = np.all([study.cases[label]["converged"] for label in s.labels], axis=0)
    study.cases["scene"] = {"objectives": sum(wi * o for wi, o in zip(w, objs)),
                            "done": done, "converged": conv}


def direct(study: Study, ex: Executor, progress: bool = True) -> None:
    """NSGA-II on the true model (no surrogate); compare with the surrogate front."""
    from pymoo.algorithms.moo.nsga2 import NSGA2
    from pymoo.core.problem import Problem
    from pymoo.optimize import minimize
    from tqdm.auto import tqdm

    s = study.s
    for label, deck in zip(s.labels, s.cases):
        if "direct" in study.cases[label]:
            continue
        base = Case.from_namelist(deck).to_dict()
        bar = tqdm(total=s.direct_population * s.direct_generations, unit="run",
                   desc=f"direct NSGA-II ({label})", disable=not progress)
        evaluated = []

        class TrueModel(Problem):
            def __init__(self):
                super().__init__(n_var=len(s.variables), n_obj=len(s.objectives),
                                 xl=np.array(s.lower), xu=np.array(s.upper))

            def _evaluate(self, x, out, *args, **kwargs):
                chunks = np.array_split(np.arange(len(x)), max(1, len(x) // s.batch))
                f = np.empty((len(x), len(s.objectives)))

                def put(i, rows):
                    f[chunks[i]] = rows[:, :-1]
                    bar.update(len(chunks[i]))
                ex.map(run_batch, [(base, s.variables, x[c], s.objectives) for c in chunks], put)
                evaluated.append(len(x))
                out["F"] = f

        t0 = time.perf_counter()
        res = minimize(TrueModel(), NSGA2(pop_size=s.direct_population),
                       ("n_gen", s.direct_generations), seed=s.seed, verbose=False)
        bar.close()
        wall = time.perf_counter() - t0
        fd = np.atleast_2d(res.F)
        fr = study.cases[label]["front"]
        fs = np.asarray(fr["f"])
        both = np.vstack([fd, fs])
        lo, ref = both.min(0), both.max(0) + 0.1 * (both.max(0) - both.min(0) + 1e-12)
        from pymoo.indicators.igd import IGD

        scale = ref - lo
        igd = float(IGD(fd / scale)(fs / scale))     # surrogate front to direct front
        gd = float(IGD(fs / scale)(fd / scale))      # direct front to surrogate front
        study.cases[label]["direct"] = {
            "x": np.atleast_2d(res.X), "f": fd, "runs": int(sum(evaluated)), "wall_s": wall,
            "hv_direct": hypervolume(fd, ref, lo), "hv_surrogate": hypervolume(fs, ref, lo),
            "igd_surrogate_to_direct": igd, "igd_direct_to_surrogate": gd}
        study.save()


def run_study(deck: str | os.PathLike, out: str | os.PathLike | None = None, *,
              scheduler: str | None = None, workers: int | None = None, serial: bool = False,
              with_direct: bool = False, figures: bool = True, progress: bool = True,
              stop_after: int | None = None) -> Study:
    """The whole pipeline; resumes from the study file in ``out`` if there is one."""
    s = read_study(deck)
    out = Path(out or Path("out") / s.name)
    out.mkdir(parents=True, exist_ok=True)
    study = Study.open(s, out / f"{s.name}.h5")
    if study.x is None:
        study.x = sample(s)
        study.stages.add("sampled")
        study.save()
    ex = Executor(scheduler=scheduler, workers=workers, serial=serial)
    try:
        t0 = time.perf_counter()
        run_samples(study, ex, progress=progress, stop_after=stop_after)
        study.stages.add("ran")
        for label in s.labels:
            study.cases[label]["wall_s_runs"] = study.cases[label].get("wall_s_runs", 0.0) \
                + (time.perf_counter() - t0) / len(s.labels)
        if s.scene and len(s.labels) > 1:
            scene_objectives(study)
        if "fitted" not in study.stages or "scene" in study.cases and "surface" not in study.cases["scene"]:
            fit_surfaces(study)
            study.stages.add("fitted")
            study.save()
        optimise(study, ex, progress=progress)
        study.stages.add("optimised")
        if "checked" not in study.stages:
            check_designs(study, ex)
            study.stages.add("checked")
            study.save()
        if with_direct:
            direct(study, ex, progress=progress)
            study.stages.add("direct")
            study.save()
    finally:
        ex.close()
    if figures:
        from .study_plots import study_figures

        study_figures(study, out)
    return study
