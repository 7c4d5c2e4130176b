"""Results of one cycle, by name: the series and scalars of the kernel's result tables.

Every name, unit and description comes from the kernel (:mod:`ringlube.tables`); a
result file is written by the kernel itself (``ringlube-solve``, or
``ringlube.run(case, output=path)``), so files from the command line and from Python have
one layout and the numbers never travel back to the kernel to be written.
"""

from __future__ import annotations

import html
import os
from pathlib import Path

import numpy as np

from .errors import InputError, input_file
from .tables import FLAG_BITS, INT_SERIES, LINER, SCALARS, SECTORS, SERIES

__all__ = [
    "CycleResult",
    "Comparison",
    "compare",
    "load",
    "SERIES",
    "INT_SERIES",
    "SCALARS",
    "FLAG_BITS",
    "LINER",
    "SECTORS",
]

#: the scalars :func:`compare` shows by default (those a run has), in this order
COMPARED = (
    "energy_loss",
    "friction_power",
    "fmep",
    "mixed_share",
    "oil_to_chamber",
    "oil_to_chamber_rate",
    "blowby",
    "face_leakage",
    "light_gap_share",
    "conformability",
    "ring_lift_share",
    "flutter_events",
    "ring_mass",
    "min_film",
    "max_friction",
    "converged",
)


class CycleResult:
    """One reported engine cycle: arrays over the crank steps and scalar results.

    Every series and scalar of the kernel's tables is an attribute by its short name
    (``result.h0``, ``result.friction``, ``result.energy_loss``, ...) in the unit of the
    table (``result.units(name)``; mostly SI, but ring mass in g, mixed share in %, oil to
    the chamber in mm^3 per cycle and g/h, FMEP in kPa): :data:`ringlube.tables.SERIES`
    and :data:`ringlube.tables.SCALARS`.

    A distorted bore's run (``&physics bore = 'distorted'``) also has the series of each
    sector, 2-D arrays (crank step x sector) by their short names in
    :data:`ringlube.tables.SECTORS` (``result.sector_h0`` [m], ``result.sector_load``
    [N/m]), the sectors' angles ``result.sector_angle_deg`` (sector j at 360 (j - 1) / M
    deg) and ``result.conformability_by_order`` ({order k: A_k over its conformability
    limit}, in the order the distortion gives them). A round bore's run has none of them.

    Parameters
    ----------
    series : dict of str to ndarray
        Real and integer series by short name.
    scalars : dict of str to float
        Scalars by short name, in their stored units (ring mass in g).
    liner : dict of str to ndarray, optional
        The liner film at the end of the cycle (starved inlet only): 'liner_position' and
        'liner_oil_film'.
    sectors : dict of str to ndarray, optional
        A distorted bore's series per crank step and sector (shape (steps, sectors)) by
        short name (:data:`ringlube.tables.SECTORS`).
    conformability_by_order : dict of int to float, optional
        A distorted bore's A_k over its conformability limit by order k (None: a round bore).
    deck, deck_path, pressure_file : str
        The deck's text as the kernel read it, where it came from, and the gas trace.
    label : str
        Legend label.
    calibration_file : str
        The calibration file the deck included.
    path : Path, optional
        The result file the kernel wrote (``run(case, output=...)``) or :func:`load` read.

    Examples
    --------
    >>> import ringlube
    >>> r = ringlube.run(ringlube.Case().with_numerics(nodes=31, dpsi_deg=4.0))
    >>> r.h0.shape, r.units("energy_loss")
    ((180,), 'J')
    """

    def __init__(
        self,
        series: dict[str, np.ndarray],
        scalars: dict[str, float],
        *,
        liner: dict[str, np.ndarray] | None = None,
        sectors: dict[str, np.ndarray] | None = None,
        conformability_by_order: dict[int, float] | None = None,
        deck: str = "",
        deck_path: str = "",
        pressure_file: str = "",
        label: str = "",
        calibration_file: str = "",
        path: os.PathLike | None = None,
    ):
        self.series = dict(series)
        self.scalars = dict(scalars)
        self.liner = dict(liner or {})
        #: a distorted bore's series per crank step and sector, by short name (else empty)
        self.sectors = dict(sectors or {})
        self._conformability = None
        if conformability_by_order is not None:
            self._conformability = {int(k): float(v) for k, v in conformability_by_order.items()}
        self.deck = deck
        self.deck_path = deck_path
        self.pressure_file = pressure_file
        self.calibration_file = calibration_file
        self.label = label
        #: the HDF5 file of this result, if it has one
        self.path = Path(path) if path is not None else None

    def __getattr__(self, name: str):
        d = self.__dict__
        if name in d.get("series", {}):
            return d["series"][name]
        if name in d.get("scalars", {}):
            return SCALARS[name].value(d["scalars"][name])
        if name in d.get("sectors", {}):
            return d["sectors"][name]
        if name == "conformability_by_order" and d.get("_conformability") is not None:
            return dict(d["_conformability"])
        if name == "sector_angle_deg" and d.get("sectors"):
            m = np.shape(next(iter(d["sectors"].values())))[1]
            return 360.0 * np.arange(m) / m
        spec = SCALARS.get(name) or SERIES.get(name) or INT_SERIES.get(name) or SECTORS.get(name)
        if name in _BORE_ATTRIBUTES:
            spec = SCALARS["conformability"]
        if spec is not None and spec.requires and "series" in d:
            from .tables import MODELS

            m = MODELS[spec.requires]
            raise AttributeError(
                f"{name}: not produced by this run (it needs &{m.group} {m.variable} = '{m.value}')"
            )
        raise AttributeError(name)

    def __dir__(self):
        extra = set(self.sectors) | ({"sector_angle_deg"} if self.sectors else set())
        extra |= {"conformability_by_order"} if self._conformability is not None else set()
        return sorted(set(super().__dir__()) | set(self.series) | set(self.scalars) | extra)

    @property
    def distorted(self) -> bool:
        """Whether the run had a distorted bore (sector series and conformability per order)."""
        return self.__dict__.get("_conformability") is not None

    @staticmethod
    def units(name: str) -> str:
        """Unit of a series or scalar (short name)."""
        for table in (SERIES, INT_SERIES, SCALARS, SECTORS):
            if name in table:
                return table[name].unit
        raise KeyError(name)

    @property
    def film_ratio(self) -> np.ndarray:
        """h0 / sigma over the cycle."""
        return self.h0 / self.sigma

    def summary(self, title: str = "", written: str = "") -> str:
        """The summary ``ringlube-solve`` prints (the kernel formats it): one line per
        quantity with its unit, energy, friction power, FMEP, mixed share, oil to the
        chamber (starved inlet), blowby (ring pack), the conformability per order, light
        gaps and face leakage (distorted bore), ring mass, film, friction, convergence and
        run time.

        Parameters
        ----------
        title, written : str
            First line and the file written (last line); left out when empty.

        Examples
        --------
        >>> import ringlube
        >>> r = ringlube.run(ringlube.Case().with_numerics(nodes=31, dpsi_deg=4.0))
        >>> print(r.summary().splitlines()[1].split())
        ['mean', 'friction', 'power', ..., 'W', '(energy', 'per', 'cycle', 'x', 'cycles', 'per', 'second)']
        """
        from . import _kernel

        v = np.array([float(self.scalars.get(k, 0.0)) for k in SCALARS])
        made = np.array([k in self.scalars for k in SCALARS], dtype=np.int32)
        conf = self._conformability or {}
        # (f2py takes no empty array: one element more, nk of them used)
        orders = np.array([*conf, 0], dtype=np.int32)
        ratios = np.array([*conf.values(), 0.0])
        text, n = _kernel.rl_summary(v, made, len(conf), orders, ratios, title.encode(), written.encode())
        text = bytes(text[:n]).decode("utf-8", "replace") if isinstance(text, bytes) else str(text)[:n]
        return text.rstrip("\n")

    def __repr__(self) -> str:
        head = f"<CycleResult {self.label!r}" if self.label else "<CycleResult"
        return f"{head}\n{self.summary()}>"

    def _repr_html_(self) -> str:
        rows = "".join(
            f"<tr><td>{k}</td><td style='text-align:right'>{_num(self.scalars[k])}</td>"
            f"<td>{SCALARS[k].unit}</td><td>{html.escape(SCALARS[k].long_name)}</td></tr>"
            for k in SCALARS
            if k in self.scalars
        )
        rows += "".join(
            f"<tr><td>conformability_{k}</td><td style='text-align:right'>{_num(v)}</td><td>1</td>"
            f"<td>A_{k} over its conformability limit (order {k})</td></tr>"
            for k, v in (self._conformability or {}).items()
        )
        title = html.escape(f"CycleResult {self.label}".strip())
        return (
            f"<table><caption>{title} ({len(self.crank_angle_deg)} crank steps)</caption>"
            f"<tr><th>result</th><th>value</th><th>unit</th><th>meaning</th></tr>{rows}</table>"
        )


class Comparison:
    """Scalar results of several runs side by side (:func:`compare`).

    Attributes
    ----------
    labels : list of str
        One per result (column).
    names : list of str
        Scalar short names (rows), with their units in :attr:`units`.
    values : dict of str to ndarray
        Each row's values, one per result (NaN where a result lacks it).
    results : list of CycleResult

    Examples
    --------
    >>> import ringlube
    >>> base = ringlube.Case().with_numerics(nodes=31, dpsi_deg=4.0)
    >>> rs = [ringlube.run(base), ringlube.run(base.with_ring(width=1.2e-3))]
    >>> t = ringlube.compare(rs, labels=["1.0 mm", "1.2 mm"])
    >>> t.values["energy_loss"].shape, t.units["energy_loss"]
    ((2,), 'J')
    """

    def __init__(self, results, labels, names):
        self.results = list(results)
        self.labels = list(labels)
        self.names = list(names)
        self.units = {n: SCALARS[n].unit for n in self.names}
        self.values = {
            n: np.array([float(r.scalars[n]) if n in r.scalars else np.nan for r in self.results])
            for n in self.names
        }

    def rows(self) -> list[list[str]]:
        """Header row, then one row per quantity: name [unit], then the values as text."""
        head = ["quantity", *self.labels]
        body = [[f"{n} [{self.units[n]}]", *(_num(v) for v in self.values[n])] for n in self.names]
        return [head, *body]

    def to_markdown(self) -> str:
        """A Markdown table (quantities as rows, results as columns)."""
        rows = self.rows()
        lines = ["| " + " | ".join(rows[0]) + " |", "|---" + "|---:" * (len(rows[0]) - 1) + "|"]
        lines += ["| " + " | ".join(r) + " |" for r in rows[1:]]
        return "\n".join(lines)

    def __str__(self) -> str:
        rows = self.rows()
        widths = [max(len(r[j]) for r in rows) for j in range(len(rows[0]))]
        return "\n".join(
            "  ".join(c.ljust(w) if j == 0 else c.rjust(w) for j, (c, w) in enumerate(zip(r, widths)))
            for r in rows
        )

    def __repr__(self) -> str:
        return f"<Comparison of {len(self.results)} results>\n{self}"

    def _repr_markdown_(self) -> str:
        return self.to_markdown()

    def figure(self):
        """Friction and film ratio h0/sigma over the cycle, every result overlaid."""
        from .plot import overlay_figure

        return overlay_figure(self.results, self.labels)


def compare(results, labels=None, names=None) -> Comparison:
    """Scalar results of several runs side by side, and an overlay figure.

    Parameters
    ----------
    results : sequence of CycleResult
    labels : sequence of str, optional
        Column names (default: each result's label, else its index).
    names : sequence of str, optional
        Scalars to compare (short names; default: the summary quantities).

    Returns
    -------
    Comparison
        ``str()`` a text table, ``.to_markdown()``, ``.values`` (dict of arrays) and
        ``.figure()`` (matplotlib).

    Raises
    ------
    InputError
        For an unknown name or a labels list of another length.

    Examples
    --------
    >>> import ringlube
    >>> base = ringlube.Case().with_numerics(nodes=31, dpsi_deg=4.0)
    >>> t = compare([ringlube.run(base), ringlube.run(base.with_ring(width=1.2e-3))], ["a", "b"])
    >>> print(t.to_markdown().splitlines()[0])
    | quantity | a | b |
    """
    results = list(results)
    if labels is None:
        labels = [r.label or str(i) for i, r in enumerate(results)]
    labels = [str(x) for x in labels]
    if len(labels) != len(results):
        raise InputError(f"compare: {len(labels)} labels for {len(results)} results")
    if names is None:
        names = [n for n in COMPARED if any(n in r.scalars for r in results)]
    elif isinstance(names, str):  # one name, not its characters
        names = [names]
    unknown = [n for n in names if n not in SCALARS]
    if unknown:
        raise InputError(f"compare: unknown results {unknown} (known: {', '.join(SCALARS)})")
    return Comparison(results, labels, names)


def _num(v: float) -> str:
    """Four significant digits ('-' for NaN)."""
    if not np.isfinite(v):
        return "-"
    return f"{v:.4g}"


def _text(value, strip: bool = True) -> str:
    if isinstance(value, (bytes, np.bytes_)):
        value = bytes(value).rstrip(b"\0").decode("utf-8", errors="replace")
    return str(value).strip() if strip else str(value)


#: attributes of a distorted bore's result that are not in the kernel's tables
_BORE_ATTRIBUTES = ("conformability_by_order", "sector_angle_deg")


def _conformability_attrs(attrs) -> dict[int, float]:
    """A distorted bore's ``conformability_<k>`` root attributes as {k: ratio}, in the order
    of the deck's ``bore.order`` list (as the run reports them), else ascending (a
    distortion file).

    Examples
    --------
    >>> _conformability_attrs({"conformability_2": 0.5, "conformability_4": 3.0, "bore.order": "4, 2"})
    {4: 3.0, 2: 0.5}
    >>> _conformability_attrs({"conformability_10": 1.0, "conformability_3": 2.0, "conformability": 2.0})
    {3: 2.0, 10: 1.0}
    """
    found = {}
    for key in attrs:
        head, _, k = key.partition("conformability_")
        if not head and k.isdigit():
            found[int(k)] = float(attrs[key])
    listed = _text(attrs.get("bore.order", b"")).replace(",", " ").split()
    given = [int(k) for k in listed if k.lstrip("-").isdigit() and int(k) in found]
    return {k: found[k] for k in dict.fromkeys([*given, *sorted(found)])}


def load(path: str | os.PathLike) -> CycleResult:
    """Read a result file written by ``ringlube-solve``, ``ringlube run`` or
    ``ringlube.run(case, output=path)``.

    Parameters
    ----------
    path : path
        An HDF5 result file.

    Returns
    -------
    CycleResult

    Raises
    ------
    InputError
        If the file is missing, not HDF5, truncated or not a ringlube result.

    Examples
    --------
    >>> import ringlube, tempfile, os
    >>> p = os.path.join(tempfile.mkdtemp(), "r.h5")
    >>> r = ringlube.run(ringlube.Case().with_numerics(nodes=31, dpsi_deg=4.0), output=p)
    >>> ringlube.load(p).energy_loss == r.energy_loss
    True
    """
    import h5py

    path = input_file(path, "no such result file", "not a regular file, not a result")
    try:
        with h5py.File(path, "r") as f:
            a = f.attrs
            c = f["cycle"]
            series = {
                k: c[spec.stored][()] for k, spec in {**SERIES, **INT_SERIES}.items() if spec.stored in c
            }
            missing = [spec.stored for spec in SERIES.values() if not spec.requires and spec.stored not in c]
            if missing:
                raise KeyError(", ".join(missing))
            n = len(series["crank_angle_deg"])
            odd = [k for k, v in series.items() if np.shape(v) != (n,)]
            if odd or "flags" not in series:
                raise KeyError(f"series of other lengths or missing flags: {odd or ['flags']}")
            scalars = {k: float(a[spec.stored]) for k, spec in SCALARS.items() if spec.stored in a}
            liner = {k: f["liner"][spec.stored][()] for k, spec in LINER.items()} if "liner" in f else {}
            sectors = {k: c[spec.stored][()] for k, spec in SECTORS.items() if spec.stored in c}
            odd = [k for k, v in sectors.items() if np.ndim(v) != 2 or len(v) != n]
            if odd:
                raise KeyError(f"sector series not of {n} crank steps x sectors: {odd}")
            conformability = _conformability_attrs(a) if "conformability" in scalars else None
            return CycleResult(
                series,
                scalars,
                liner=liner,
                sectors=sectors,
                conformability_by_order=conformability,
                deck=_text(a.get("deck", b""), strip=False),
                deck_path=_text(a.get("deck_path", b"")),
                pressure_file=_text(a.get("pressure_file", b"")),
                label=path.stem,
                path=path,
            )
    except (OSError, KeyError, ValueError, TypeError) as exc:
        raise InputError(f"{path}: not a readable ringlube result ({exc})") from None
