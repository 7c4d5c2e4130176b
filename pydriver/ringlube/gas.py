"""Synthetic in-cylinder gas-pressure traces for any engine: trace files, figures and the command.

The single-zone model itself (volume, Wiebe heat release, closed cycle, the shipped presets)
is :mod:`ringlube.gas_model`; its names are re-exported here. A trace file is CSV (crank
angle in deg, absolute pressure in Pa) whose ``#`` header records every parameter of the
:class:`GasModel` and the command that regenerates it. ``ringlube gas`` (no arguments)
regenerates the shipped traces (:data:`PRESETS`).
"""

from __future__ import annotations

import shlex
from pathlib import Path

import numpy as np

from .gas_model import (
    CRF450R,
    PRESETS,
    R_AIR,
    GasModel,
    burn_angles,
    heat_released,
    imep,
    trace,
)

__all__ = [
    "GasModel",
    "PRESETS",
    "CRF450R",
    "R_AIR",
    "trace",
    "imep",
    "burn_angles",
    "describe",
    "header",
    "command",
    "write_csv",
    "write_trace",
    "read_csv",
    "figure",
    "main",
]


def describe(m: GasModel, psi: np.ndarray, p: np.ndarray) -> str:
    """One line of derived quantities of a trace (peak, IMEP, heat, burn angles).

    Parameters
    ----------
    m : GasModel
    psi, p : ndarray
        The trace: crank angle [deg], absolute pressure [Pa].

    Examples
    --------
    >>> m = PRESETS["crf450r_4000rpm_full"]
    >>> describe(m, *trace(m)).split(",")[1]
    ' peak 60.00 bar at 375.5 deg'
    """
    i = int(np.argmax(p))
    ca10, ca50, ca90 = burn_angles(m)
    return (
        f"swept volume {m.swept_volume * 1e6:.1f} cm3, peak {p[i] / 1e5:.2f} bar at {psi[i]:.1f} deg, "
        f"net IMEP {imep(psi, p, m) / 1e5:.3f} bar, heat released {heat_released(m):.1f} J, "
        f"10/50/90 % burned at {ca10:.1f}/{ca50:.1f}/{ca90:.1f} deg"
    )


# command-line options of `ringlube gas` for the model's parameters (one home)
OPTIONS: dict[str, tuple[str, str]] = {
    "bore": ("--bore", "bore [m]"),
    "crank_radius": ("--stroke", "stroke [m] (the crank radius is half of it)"),
    "conrod_length": ("--conrod", "connecting-rod length, centre to centre [m]"),
    "compression_ratio": ("--compression-ratio", "geometric compression ratio"),
    "speed_rpm": ("--speed-rpm", "engine speed [r/min] (recorded; the trace does not depend on it)"),
    "manifold_pressure": ("--manifold-pressure", "intake manifold pressure [Pa abs]"),
    "imep": ("--imep", "target net IMEP [Pa] (sets the heat released)"),
    "peak_pressure": ("--peak-pressure", "target peak pressure [Pa abs] (sets the heat released)"),
    "heat_fraction": ("--heat-fraction", "share of the fuel's energy heating the gas (0: motored)"),
    "intake_temperature": ("--intake-temperature", "charge temperature at intake valve closing [K]"),
    "air_fuel_ratio": ("--air-fuel-ratio", "air-fuel mass ratio"),
    "lower_heating_value": ("--lower-heating-value", "fuel lower heating value [J/kg]"),
    "soc": ("--soc", "start of combustion [deg, 360 = firing TDC]"),
    "duration": ("--duration", "combustion (Wiebe) duration [deg]"),
    "wiebe_a": ("--wiebe-a", "Wiebe efficiency factor a"),
    "wiebe_m": ("--wiebe-m", "Wiebe form factor m"),
    "exhaust_pressure": ("--exhaust-pressure", "exhaust pressure [Pa abs]"),
    "gamma": ("--gamma", "ratio of specific heats (polytropic exponent)"),
    "ivc": ("--ivc", "intake valve closing [deg]"),
    "evo": ("--evo", "exhaust valve opening [deg]"),
    "blowdown": ("--blowdown", "blowdown duration after evo [deg]"),
}


def command(m: GasModel, output: str | Path) -> str:
    """The ``ringlube gas`` command that writes this model's trace to ``output``.

    Parameters
    ----------
    m : GasModel
    output : path
        The trace file named in the command.

    Examples
    --------
    >>> command(GasModel(0.086, 0.043, 0.1435, 10.5, imep=9e5), "p.csv").split()[:5]
    ['ringlube', 'gas', '-o', 'p.csv', '--bore']
    """
    words = ["ringlube", "gas", "-o", str(output)]
    for name, value in m.parameters().items():
        if name == "crank_radius":
            value = 2 * value
        words += [OPTIONS[name][0], f"{value:g}" if float(value).is_integer() else repr(float(value))]
    return shlex.join(words)


def header(m: GasModel, name: str, derived: str = "", output: str | Path | None = None) -> str:
    """The comment lines of a trace file: its name, parameters and (for traces made with
    ``ringlube gas -o``) the command that regenerates it and derived quantities.

    Parameters
    ----------
    m : GasModel
    name : str
        The trace's name.
    derived : str
        A line of derived quantities (:func:`describe`), if any.
    output : path, optional
        The file written; given, the header records the command that writes it.

    Examples
    --------
    >>> header(PRESETS["crf450r_4000rpm_full"], "x").splitlines()[1].split(", ")[0]
    'bore=0.096'
    """
    params = ", ".join(f"{k}={v}" for k, v in m.parameters().items())
    lines = [f"ringlube synthetic single-zone trace '{name}'", params]
    if output is not None:
        lines.append(f"command: {command(m, output)}")
    if derived:
        lines.append(f"derived: {derived}")
    return "\n".join(lines)


def write_csv(path: str | Path, psi: np.ndarray, p: np.ndarray, header: str = "") -> None:
    """Write a trace as the CSV the kernel reads (``#`` comment lines, a header line, then
    ``deg,Pa`` rows).

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
    >>> write_csv(f, np.array([0.0, 360.0, 720.0]), np.array([1e5, 2e5, 1e5]), header="a\\nb")
    >>> read_csv(f)[1].tolist()
    [100000.0, 200000.0, 100000.0]
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_suffix(path.suffix + ".part")
    try:
        with open(tmp, "w") as fh:
            if header:
                for line in header.splitlines():
                    fh.write(f"# {line}\n")
            fh.write("crank_angle_deg,pressure_Pa\n")
            for a, b in zip(psi, p):
                fh.write(f"{a:.3f},{b:.6e}\n")
        tmp.replace(path)
    finally:
        tmp.unlink(missing_ok=True)


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
    from .case import Case
    from .case_kernel import kernel_case

    case = Case(name=f"trace {Path(path).name}").set(
        "operating", pressure_file=str(Path(path).resolve()), pressure_scale=1.0
    )
    with kernel_case(case) as k:
        n = _kernel.rl_trace_length(k.handle)
        psi, p = _kernel.rl_trace(k.handle, n)
    return psi, p


def figure(m: GasModel, psi: np.ndarray, p: np.ndarray, title: str = ""):
    """The trace over the cycle and its log p - log V diagram.

    Parameters
    ----------
    m : GasModel
    psi, p : ndarray
        The trace: crank angle [deg], absolute pressure [Pa].
    title : str
        Figure title.

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> m = PRESETS["crf450r_4000rpm_full"]
    >>> len(figure(m, *trace(m)).axes)
    2
    """
    import matplotlib.pyplot as plt

    from .plot import _crank_axis

    fig, (ax, axv) = plt.subplots(
        1, 2, figsize=(11, 4.2), layout="constrained", gridspec_kw={"width_ratios": [1.7, 1]}
    )
    i = int(np.argmax(p))
    ax.plot(psi, p / 1e5, lw=1.4, color="C0")
    ax.plot(psi[i], p[i] / 1e5, "o", color="C3", ms=4)
    ax.annotate(
        f"peak {p[i] / 1e5:.1f} bar at {psi[i]:.1f} deg",
        (psi[i], p[i] / 1e5),
        xytext=(12, -4),
        textcoords="offset points",
        fontsize=8,
        va="top",
    )
    ca50 = burn_angles(m, (0.5,))[0]
    ax.axvline(ca50, color="C1", lw=0.8, ls="--", label=f"50 % burned, {ca50:.1f} deg")
    ax.set_ylabel("gas pressure [bar abs]")
    ax.set_ylim(bottom=0)
    _crank_axis(ax)
    ax.legend(fontsize=8, loc="upper left")
    v = m.volume(psi)
    axv.loglog(v * 1e6, p / 1e5, lw=1.2, color="C0")
    from matplotlib.ticker import LogLocator, NullFormatter, ScalarFormatter

    for axis in (axv.xaxis, axv.yaxis):
        axis.set_major_locator(LogLocator(subs=(1.0, 2.0, 5.0)))
        axis.set_major_formatter(ScalarFormatter())
        axis.set_minor_formatter(NullFormatter())
    axv.set_xlabel("cylinder volume [cm3]")
    axv.set_ylabel("gas pressure [bar abs]")
    axv.set_title(f"net IMEP {imep(psi, p, m) / 1e5:.2f} bar", fontsize=9)
    axv.grid(True, which="both", color="0.9", lw=0.6)
    if title:
        fig.suptitle(title, fontsize=10)
    return fig


def write_trace(m: GasModel, output: str | Path, name: str | None = None, figures: bool = True) -> list[Path]:
    """Write the trace of ``m`` to ``output`` (CSV with its inputs in the header) and, with
    ``figures``, ``output`` with .png and .pdf beside it; returns the files written.

    Parameters
    ----------
    m : GasModel
    output : path
        The CSV file (written atomically; its folder is created).
    name : str, optional
        Name in the header (default: the file's stem).
    figures : bool
        Also write the figure.

    Examples
    --------
    >>> import tempfile, os
    >>> out = os.path.join(tempfile.mkdtemp(), "p.csv")
    >>> [f.suffix for f in write_trace(PRESETS["crf450r_4000rpm_full"], out)]
    ['.csv', '.png', '.pdf']
    """
    import matplotlib.pyplot as plt

    from .plot import save_metadata

    output = Path(output)
    name = name or output.stem
    psi, p = trace(m)
    derived = describe(m, psi, p)
    write_csv(output, psi, p, header=header(m, name, derived, output))
    files = [output]
    if figures:
        head, _, tail = derived.partition(", heat")
        fig = figure(m, psi, p, title=f"'{name}': {head}\nheat{tail}")
        for fmt in ("png", "pdf"):
            path = output.with_suffix(f".{fmt}")
            tmp = path.with_name(path.name + ".part")
            fig.savefig(tmp, format=fmt, dpi=150, metadata=save_metadata(fmt))
            tmp.replace(path)
            files.append(path)
        plt.close(fig)
    return files


def main(argv: list[str] | None = None) -> None:
    """Regenerate shipped traces: ``python -m ringlube.gas [--out DIR] [NAME ...]``.

    Parameters
    ----------
    argv : list of str, optional
        Command-line arguments.

    Examples
    --------
    >>> import tempfile
    >>> main(["--out", tempfile.mkdtemp(), "crf450r_3000rpm_half"])
    crf450r_3000rpm_half: peak 35.0 bar at 381.5 deg
    """
    import argparse

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="inputs/pressure", help="output folder")
    ap.add_argument("names", nargs="*", help="presets to write (default: all)")
    args = ap.parse_args(argv)
    for name in args.names or sorted(PRESETS):
        m = PRESETS[name]
        psi, p = trace(m)
        write_csv(Path(args.out) / f"{name}.csv", psi, p, header=header(m, name))
        i = int(np.argmax(p))
        print(f"{name}: peak {p[i] / 1e5:.1f} bar at {psi[i]:.1f} deg")


if __name__ == "__main__":
    main()
