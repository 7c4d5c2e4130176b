"""Results of one cycle: numpy arrays plus the scalar results, in the SPEC HDF5 layout."""

from __future__ import annotations

import dataclasses
import os
from pathlib import Path

import h5py
import numpy as np

__all__ = ["CycleResult", "load", "SERIES", "FLAG_BITS"]

#: Per-step datasets in /cycle: (dataset name, attribute name, units).
SERIES = (
    ("crank_angle_deg", "crank_angle_deg", "deg"),
    ("sliding_speed_m_s", "sliding_speed", "m/s"),
    ("h0_m", "h0", "m"),
    ("lambda_min", "lambda_min", "1"),
    ("gas_pressure_Pa", "gas_pressure", "Pa"),
    ("applied_load_N", "applied_load", "N"),
    ("hydrodynamic_load_N", "hydrodynamic_load", "N"),
    ("asperity_load_N", "asperity_load", "N"),
    ("viscous_friction_N", "viscous_friction", "N"),
    ("boundary_friction_N", "boundary_friction", "N"),
    ("friction_N", "friction", "N"),
    ("power_loss_W", "power_loss", "W"),
    ("load_residual", "load_residual", "1"),
)
#: Meaning of the bits of /cycle/flags.
FLAG_BITS = {
    1: "h0 at h0_floor",
    2: "h0 at h0_ceiling",
    4: "load outside load_tol",
    8: "pressure-viscosity loop not converged",
    16: "cavitation set not settled",
    32: "film pressure above 1 GPa (Roelands clipped)",
}


@dataclasses.dataclass
class CycleResult:
    """One reported engine cycle. Arrays have one value per crank step (SI units)."""

    crank_angle_deg: np.ndarray
    sliding_speed: np.ndarray
    h0: np.ndarray
    lambda_min: np.ndarray
    gas_pressure: np.ndarray
    applied_load: np.ndarray
    hydrodynamic_load: np.ndarray
    asperity_load: np.ndarray
    viscous_friction: np.ndarray
    boundary_friction: np.ndarray
    friction: np.ndarray
    power_loss: np.ndarray
    load_residual: np.ndarray
    flags: np.ndarray
    film_solves: np.ndarray
    energy_loss: float          #: J per cycle
    mixed_share: float          #: % of the cycle with h0/sigma < 4
    ring_mass: float            #: g
    min_film: float             #: m
    max_friction: float         #: N
    converged: bool
    cycles_run: int
    cycle_change: float
    sigma: float                #: m, composite roughness
    run_time: float             #: s, kernel time
    deck: str = ""
    label: str = ""
    reynolds_solves: int = 0    #: Reynolds (Thomas) solves over the run
    cycles_computed: float = 0.0  #: cycles' worth of crank steps solved, warm-up included

    @property
    def film_ratio(self) -> np.ndarray:
        """h0 / sigma over the cycle."""
        return self.h0 / self.sigma

    def summary(self) -> str:
        return (f"energy loss {self.energy_loss:.4f} J/cycle, mixed share {self.mixed_share:.2f} %, "
                f"ring mass {self.ring_mass:.3f} g, min film {self.min_film * 1e6:.4f} um, "
                f"peak friction {self.max_friction:.3f} N, cycles {self.cycles_run}, "
                f"converged {'yes' if self.converged else 'no'}")

    def to_hdf5(self, path: str | os.PathLike) -> Path:
        """Write the SPEC layout (atomically: ``path.part`` renamed when complete)."""
        path = Path(path)
        tmp = path.with_name(path.name + ".part")
        try:
            with h5py.File(tmp, "w") as f:
                f.attrs["energy_loss_J"] = self.energy_loss
                f.attrs["mixed_share_pct"] = self.mixed_share
                f.attrs["ring_mass_g"] = self.ring_mass
                f.attrs["min_film_m"] = self.min_film
                f.attrs["max_friction_N"] = self.max_friction
                f.attrs["converged"] = np.int32(self.converged)
                f.attrs["cycles_run"] = np.int32(self.cycles_run)
                f.attrs["cycle_change"] = self.cycle_change
                f.attrs["sigma_m"] = self.sigma
                f.attrs["run_time_s"] = self.run_time
                f.attrs["reynolds_solves"] = np.int32(self.reynolds_solves)
                f.attrs["cycles_computed"] = self.cycles_computed
                f.attrs["deck"] = np.bytes_(self.deck.encode())
                g = f.create_group("cycle")
                for dset, attr, units in SERIES:
                    d = g.create_dataset(dset, data=getattr(self, attr))
                    d.attrs["units"] = np.bytes_(units.encode())
                d = g.create_dataset("flags", data=self.flags.astype(np.int32))
                d.attrs["units"] = np.bytes_(b"1")
                d.attrs["description"] = np.bytes_(
                    ", ".join(f"{k}: {v}" for k, v in FLAG_BITS.items()).encode())
                d = g.create_dataset("film_solves", data=self.film_solves.astype(np.int32))
                d.attrs["units"] = np.bytes_(b"1")
            os.replace(tmp, path)
        finally:
            if tmp.exists():
                tmp.unlink()
        return path


def _attr_text(value) -> str:
    if isinstance(value, bytes | np.bytes_):
        return bytes(value).rstrip(b"\0").decode(errors="replace")
    return str(value)


def load(path: str | os.PathLike) -> CycleResult:
    """Read a result written by ``ringlube-solve`` or :meth:`CycleResult.to_hdf5`."""
    with h5py.File(path, "r") as f:
        a = f.attrs
        c = f["cycle"]
        arrays = {attr: c[dset][()] for dset, attr, _ in SERIES}
        return CycleResult(
            **arrays,
            flags=c["flags"][()],
            film_solves=c["film_solves"][()] if "film_solves" in c else np.zeros(0, int),
            energy_loss=float(a["energy_loss_J"]),
            mixed_share=float(a["mixed_share_pct"]),
            ring_mass=float(a["ring_mass_g"]),
            min_film=float(a["min_film_m"]),
            max_friction=float(a["max_friction_N"]),
            converged=bool(a["converged"]),
            cycles_run=int(a["cycles_run"]),
            cycle_change=float(a.get("cycle_change", np.nan)),
            sigma=float(a.get("sigma_m", np.nan)),
            run_time=float(a.get("run_time_s", np.nan)),
            deck=_attr_text(a.get("deck", b"")),
            label=Path(path).stem,
            reynolds_solves=int(a.get("reynolds_solves", 0)),
            cycles_computed=float(a.get("cycles_computed", 0.0)),
        )
