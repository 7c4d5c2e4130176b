"""Synthetic in-cylinder gas-pressure traces from a single-zone cylinder model.

The source study used measured pressure traces that it does not publish, so ringlube
ships synthetic ones (SPEC section 10). The model, per crank angle psi (deg, 0 = TDC at
the start of intake, 360 = firing TDC):

* slider-crank volume ``V = Vc + (pi/4) B^2 x(psi)``, compression ratio ``rc``;
* intake (0 .. ivc): manifold pressure; exhaust (evo+blowdown .. 720): exhaust pressure;
* closed cycle (ivc .. evo): first law of a single ideal-gas zone with ratio of specific
  heats ``gamma`` and a Wiebe heat release
  ``x_b = 1 - exp(-a ((psi - soc)/duration)^(m+1))``,
  ``dp = (gamma - 1)/V dQ - gamma p/V dV``;
* blowdown (evo .. evo + blowdown): pressure relaxes exponentially to the exhaust value.

The total heat released is scaled so the peak pressure equals ``peak_pressure``.
Everything is a plain parameter of :class:`GasModel`, and ``python -m ringlube.gas``
regenerates the shipped traces.
"""

from __future__ import annotations

import argparse
import dataclasses
from pathlib import Path

import numpy as np

__all__ = ["GasModel", "PRESETS", "trace", "write_csv", "read_csv"]


@dataclasses.dataclass(frozen=True)
class GasModel:
    """Parameters of the single-zone model (SI units, angles in degrees).

    Examples
    --------
    >>> m = GasModel(peak_pressure=50e5)
    >>> float(m.volume([180.0])[0]) > float(m.volume([0.0])[0])
    True
    """

    bore: float = 96e-3
    crank_radius: float = 31.5e-3
    conrod_length: float = 107e-3
    compression_ratio: float = 12.0
    manifold_pressure: float = 1.0e5
    exhaust_pressure: float = 1.1e5
    gamma: float = 1.32
    ivc: float = 200.0  # intake valve closing
    evo: float = 490.0  # exhaust valve opening
    blowdown: float = 50.0  # deg over which the cylinder empties to exhaust pressure
    soc: float = 345.0  # start of combustion
    duration: float = 55.0  # combustion duration
    wiebe_a: float = 5.0
    wiebe_m: float = 2.0
    peak_pressure: float = 60e5

    def volume(self, psi_deg: np.ndarray) -> np.ndarray:
        """Cylinder volume [m^3] at crank angles [deg] (the kernel's slider-crank)."""
        from . import _kernel

        psi = np.atleast_1d(np.asarray(psi_deg, dtype=float))
        x, _ = _kernel.rl_kinematics(psi, self.crank_radius, self.conrod_length, 1.0)
        area = np.pi / 4 * self.bore**2
        vd = area * 2 * self.crank_radius
        vc = vd / (self.compression_ratio - 1)
        return vc + area * x


#: Shipped operating points (see inputs/README.md).
PRESETS: dict[str, GasModel] = {
    "crf450r_4000rpm_full": GasModel(manifold_pressure=1.0e5, peak_pressure=60e5, soc=342.0),
    "crf450r_3000rpm_half": GasModel(manifold_pressure=0.55e5, peak_pressure=35e5, soc=348.0),
}


def _closed_cycle(m: GasModel, psi: np.ndarray, q_total: float) -> np.ndarray:
    """Integrate the first law from ivc to evo with RK2 on the fine grid ``psi``."""
    v = m.volume(psi)
    p = np.empty_like(psi)
    p[0] = m.manifold_pressure
    xb_prev = 0.0

    def burned(a: float) -> float:
        if a <= m.soc:
            return 0.0
        z = (a - m.soc) / m.duration
        return 1.0 - np.exp(-m.wiebe_a * z ** (m.wiebe_m + 1))

    for i in range(1, len(psi)):
        xb = burned(psi[i])
        dq = q_total * (xb - xb_prev)
        xb_prev = xb
        dv = v[i] - v[i - 1]
        vm = 0.5 * (v[i] + v[i - 1])
        # trapezoidal in p for the compression term (stable for any step)
        g = m.gamma
        p[i] = (p[i - 1] * (1 - 0.5 * g * dv / vm) + (g - 1) * dq / vm) / (1 + 0.5 * g * dv / vm)
    return p


def trace(m: GasModel, step: float = 0.5) -> tuple[np.ndarray, np.ndarray]:
    """Crank angle (deg, 0..720 inclusive) and absolute pressure (Pa) of one cycle.

    Parameters
    ----------
    m : GasModel
    step : float
        Crank-angle step [deg].

    Returns
    -------
    (ndarray, ndarray)

    Examples
    --------
    >>> psi, p = trace(PRESETS["crf450r_4000rpm_full"])
    >>> round(float(p.max()) / 1e5, 3), float(psi[-1])
    (60.0, 720.0)
    """
    psi = np.arange(0.0, 720.0 + step / 2, step)
    fine = np.linspace(m.ivc, m.evo, int((m.evo - m.ivc) / 0.05) + 1)

    def peak(q: float) -> float:
        return float(_closed_cycle(m, fine, q).max())

    lo, hi = 0.0, 1.0e4
    while peak(hi) < m.peak_pressure:
        hi *= 2
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if peak(mid) < m.peak_pressure else (lo, mid)
    pc = _closed_cycle(m, fine, 0.5 * (lo + hi))
    p_evo = pc[-1]

    p = np.full_like(psi, m.exhaust_pressure)
    p[psi <= m.ivc] = m.manifold_pressure
    closed = (psi > m.ivc) & (psi <= m.evo)
    p[closed] = np.interp(psi[closed], fine, pc)
    blow = (psi > m.evo) & (psi <= m.evo + m.blowdown)
    frac = (psi[blow] - m.evo) / m.blowdown
    p[blow] = m.exhaust_pressure + (p_evo - m.exhaust_pressure) * np.exp(-5.0 * frac) * (1 - frac)
    return psi, p


def write_csv(path: str | Path, psi: np.ndarray, p: np.ndarray, header: str = "") -> None:
    """Write a trace as the CSV the kernel reads (header line, then ``deg,Pa`` rows).

    Parameters
    ----------
    path : path
        Written atomically (``path.part``, then renamed).
    psi, p : ndarray
        Crank angle [deg] and absolute pressure [Pa].
    header : str
        Comment lines.

    Examples
    --------
    >>> import numpy as np, tempfile, os
    >>> f = os.path.join(tempfile.mkdtemp(), "t.csv")
    >>> write_csv(f, np.array([0.0, 360.0, 720.0]), np.array([1e5, 2e5, 1e5]))
    >>> read_csv(f)[1].tolist()
    [100000.0, 200000.0, 100000.0]
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_suffix(path.suffix + ".part")
    with open(tmp, "w") as fh:
        if header:
            for line in header.splitlines():
                fh.write(f"# {line}\n")
        fh.write("crank_angle_deg,pressure_Pa\n")
        for a, b in zip(psi, p):
            fh.write(f"{a:.3f},{b:.6e}\n")
    tmp.replace(path)


def read_csv(path: str | Path) -> tuple[np.ndarray, np.ndarray]:
    """Read a measured or synthetic trace (``deg,Pa``) with the kernel's own CSV reader.

    Parameters
    ----------
    path : path

    Returns
    -------
    (ndarray, ndarray)
        Crank angle [deg] and absolute pressure [Pa].

    Examples
    --------
    >>> psi, p = read_csv("inputs/pressure/crf450r_4000rpm_full.csv")
    >>> float(psi[0]), float(psi[-1])
    (0.0, 720.0)

    Raises
    ------
    InputError
        Naming the file and line of a bad row (the rules of the deck's pressure_file).
    """
    from . import _kernel
    from .case import Case, kernel_case

    case = Case(name=f"trace {Path(path).name}").set(
        "operating", pressure_file=str(Path(path).resolve()), pressure_scale=1.0
    )
    with kernel_case(case) as k:
        n = _kernel.rl_trace_length(k.handle)
        psi, p = _kernel.rl_trace(k.handle, n)
    return psi, p


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="inputs/pressure", help="output folder")
    ap.add_argument("names", nargs="*", help="presets to write (default: all)")
    args = ap.parse_args(argv)
    for name in args.names or sorted(PRESETS):
        m = PRESETS[name]
        psi, p = trace(m)
        params = ", ".join(f"{k}={v}" for k, v in dataclasses.asdict(m).items())
        write_csv(
            Path(args.out) / f"{name}.csv",
            psi,
            p,
            header=f"ringlube synthetic single-zone trace '{name}'\n{params}",
        )
        i = int(np.argmax(p))
        print(f"{name}: peak {p[i] / 1e5:.1f} bar at {psi[i]:.1f} deg")


if __name__ == "__main__":
    main()
