"""Results of one cycle, by name: the series and scalars of the kernel's result tables.

Every name, unit and description comes from the kernel (:mod:`ringlube.tables`); a
result is written to HDF5 by the kernel's own writer, so files from ``ringlube-solve``
and from Python have one layout.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from .errors import InputError, error_for
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
    ):
        self.series = dict(series)
        self.scalars = dict(scalars)
        self.liner = dict(liner or {})
        self.deck = deck
        self.deck_path = deck_path
        self.pressure_file = pressure_file
        #: the calibration file the deck included (never overwritten by to_hdf5)
        self.calibration_file = calibration_file
        self.label = label

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

    def to_hdf5(self, path: str | os.PathLike) -> Path:
        """Write the SPEC layout with the kernel's writer (atomically).

        Raises
        ------
        RinglubeError
            If the file cannot be written (the message names it).
        """
        from . import _kernel

        if not str(path) or "\0" in str(path):
            raise InputError(f"{str(path)!r}: not a usable file name")
        path = Path(path)
        n = len(self.crank_angle_deg)
        s = np.column_stack([np.asarray(self.series.get(k, np.zeros(n)), float) for k in SERIES])
        i = np.column_stack([np.asarray(self.series[k], np.int32) for k in INT_SERIES])
        c = np.array([float(self.scalars.get(k, 0.0)) for k in SCALARS])
        produced = np.array([int("inlet_fill" in self.series), int(bool(self.liner))], np.int32)
        lin = np.column_stack([self.liner[k] for k in LINER]) if self.liner else np.zeros((0, len(LINER)))
        code, message = _kernel.rl_write(
            os.fsencode(path),
            s,
            i,
            c,
            produced,
            lin,
            _b(self.deck),
            _b(self.deck_path),
            _b(self.pressure_file),
            _b(self.calibration_file),
        )
        if code:
            raise error_for(code, _text(message))
        return path


def _b(s: str) -> bytes:
    return s.encode("utf-8", "surrogateescape")


def _text(value, strip: bool = True) -> str:
    if isinstance(value, (bytes, np.bytes_)):
        value = bytes(value).rstrip(b"\0").decode("utf-8", errors="replace")
    return str(value).strip() if strip else str(value)


def load(path: str | os.PathLike) -> CycleResult:
    """Read a result written by ``ringlube-solve`` or :meth:`CycleResult.to_hdf5`.

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
    >>> r = ringlube.run(ringlube.Case().with_numerics(nodes=31, dpsi_deg=4.0))
    >>> p = r.to_hdf5(os.path.join(tempfile.mkdtemp(), "r.h5"))
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
            )
    except (OSError, KeyError, ValueError, TypeError) as exc:
        raise InputError(f"{path}: not a readable ringlube result ({exc})") from None
