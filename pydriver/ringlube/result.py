"""Results of one cycle, by name: the series and scalars of the kernel's result tables.

Every name, unit and description comes from the kernel (:mod:`ringlube.tables`); a
result file is written by the kernel itself (``ringlube-solve``, or
``ringlube.run(case, output=path)``), so files from the command line and from Python have
one layout and the numbers never travel back to the kernel to be written.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from .errors import InputError
from .tables import FLAG_BITS, INT_SERIES, LINER, SCALARS, SERIES

__all__ = ["CycleResult", "load", "SERIES", "INT_SERIES", "SCALARS", "FLAG_BITS", "LINER"]


class CycleResult:
    """One reported engine cycle: arrays over the crank steps and scalar results (SI).

    Every series and scalar of the kernel's tables is an attribute by its short name
    (``result.h0``, ``result.friction``, ``result.energy_loss``, ...); units are in
    :data:`ringlube.tables.SERIES` and :data:`ringlube.tables.SCALARS`.

    Parameters
    ----------
    series : dict of str to ndarray
        Real and integer series by short name.
    scalars : dict of str to float
        Scalars by short name, in their stored units (ring mass in g).
    liner : dict of str to ndarray, optional
        The liner film at the end of the cycle (starved inlet only): 'liner_position' and
        'liner_oil_film'.
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
            value = d["scalars"][name]
            spec = SCALARS[name]
            if name in ("converged", "periodic"):
                return bool(value)
            return int(value) if spec.integer else float(value)
        raise AttributeError(name)

    def __dir__(self):
        return sorted(set(super().__dir__()) | set(self.series) | set(self.scalars))

    @staticmethod
    def units(name: str) -> str:
        """Unit of a series or scalar (short name)."""
        for table in (SERIES, INT_SERIES, SCALARS):
            if name in table:
                return table[name].unit
        raise KeyError(name)

    @property
    def film_ratio(self) -> np.ndarray:
        """h0 / sigma over the cycle."""
        return self.h0 / self.sigma

    def summary(self) -> str:
        """One line with units."""
        return (
            f"energy loss {self.energy_loss:.4f} J/cycle, mixed share {self.mixed_share:.2f} %, "
            f"ring mass {self.ring_mass:.3f} g, min film {self.min_film * 1e6:.4f} µm, "
            f"peak friction {self.max_friction:.3f} N, cycles {self.cycles_run}, "
            f"converged {'yes' if self.converged else 'no'}"
        )


def _text(value, strip: bool = True) -> str:
    if isinstance(value, (bytes, np.bytes_)):
        value = bytes(value).rstrip(b"\0").decode("utf-8", errors="replace")
    return str(value).strip() if strip else str(value)


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

    path = Path(path)
    if not path.exists():
        raise InputError(f"{path}: no such result file")
    if not path.is_file():
        raise InputError(f"{path}: not a regular file, not a result")
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
            return CycleResult(
                series,
                scalars,
                liner=liner,
                deck=_text(a.get("deck", b""), strip=False),
                deck_path=_text(a.get("deck_path", b"")),
                pressure_file=_text(a.get("pressure_file", b"")),
                label=path.stem,
                path=path,
            )
    except (OSError, KeyError, ValueError, TypeError) as exc:
        raise InputError(f"{path}: not a readable ringlube result ({exc})") from None
