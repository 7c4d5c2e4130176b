"""Synthetic in-cylinder gas-pressure traces for any engine: trace files, figures and the command.

The single-zone model itself (volume, Wiebe heat release, closed cycle, the shipped presets)
is :mod:`ringlube.gas.model`; its names are re-exported here. A trace file is CSV (crank
angle in deg, absolute pressure in Pa) whose ``#`` header records every parameter of the
:class:`GasModel` and the command that regenerates it. ``ringlube gas -o FILE.csv ...`` writes
the trace of your engine; ``ringlube gas --out DIR`` writes the shipped traces
(:data:`PRESETS`) there (``--out inputs/pressure`` regenerates them byte for byte). Nothing is
written before the trace is checked as the kernel will read it, and every file is written
atomically (a temporary file renamed when complete).
"""

from __future__ import annotations

import shlex
from pathlib import Path

import numpy as np

from ..errors import InputError
from .model import (
    CRF450R,
    PRESETS,
    R_AIR,
    GasModel,
    burn_angles,
    heat_released,
    heat_transfer_coefficient,
    imep,
    load_solution,
    trace,
    wall_heat,
)

__all__ = [
    "GasModel",
    "PRESETS",
    "CRF450R",
    "R_AIR",
    "trace",
    "imep",
    "heat_released",
    "heat_transfer_coefficient",
    "load_solution",
    "wall_heat",
    "burn_angles",
    "describe",
    "check_trace",
    "header",
    "command",
    "write_csv",
    "write_trace",
    "read_csv",
    "figure",
    "main",
]


def describe(m: GasModel, psi: np.ndarray, p: np.ndarray) -> str:
    """One line of derived quantities of a trace (peak, IMEP, heat, wall heat loss, burn
    angles).

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
    >>> describe(m := GasModel(**CRF450R, heat_fraction=0), *trace(m)).split(", ")[-1]
    'motored (no combustion)'
    """
    i = int(np.argmax(p))
    text = (
        f"swept volume {m.swept_volume * 1e6:.1f} cm3, peak {p[i] / 1e5:.2f} bar at {psi[i]:.1f} deg, "
        f"net IMEP {imep(psi, p, m) / 1e5:.3f} bar, "
    )
    text += "motored (no combustion)" if m.motored else f"heat released {heat_released(m):.1f} J"
    if m.heat_transfer != "none":
        scale = load_solution(m)[1]
        how = "fitted factor" if m.load == "peak_pressure and imep" else "factor"
        text += f", wall heat loss {wall_heat(m):.1f} J ({m.heat_transfer}, {how} {scale:.4g})"
    if not m.motored:
        ca10, ca50, ca90 = burn_angles(m)
        text += f", 10/50/90 % burned at {ca10:.1f}/{ca50:.1f}/{ca90:.1f} deg"
    return text


# command-line options of `ringlube gas` for the model's parameters (one home)
OPTIONS: dict[str, tuple[str, str]] = {
    "bore": ("--bore", "bore [m]"),
    "crank_radius": ("--stroke", "stroke [m] (the crank radius is half of it)"),
    "conrod_length": ("--conrod", "connecting-rod length, centre to centre [m]"),
    "compression_ratio": ("--compression-ratio", "geometric compression ratio"),
    "speed_rpm": ("--speed-rpm", "engine speed [r/min] (recorded; with wall heat loss it sets its time)"),
    "manifold_pressure": ("--manifold-pressure", "intake manifold pressure [Pa abs]"),
    "imep": ("--imep", "target net IMEP [Pa] (sets the heat released)"),
    "peak_pressure": ("--peak-pressure", "target peak pressure [Pa abs] (sets the heat released)"),
    "heat_fraction": (
        "--heat-fraction",
        "share of the fuel's energy heating the gas: net of the wall loss without --heat-transfer "
        "(0.75), the combustion efficiency with it (0.95)",
    ),
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
    "heat_transfer": ("--heat-transfer", "wall heat loss: none, woschni or hohenberg (needs --speed-rpm)"),
    "wall_temperature": ("--wall-temperature", "mean chamber wall temperature [K] (wall heat loss)"),
    "heat_transfer_scale": (
        "--heat-transfer-scale",
        "factor on the correlation's coefficient (fitted with both --peak-pressure and --imep)",
    ),
}

#: Options that describe the combustion (refused with ``--motored``).
COMBUSTION_OPTIONS = (
    "imep",
    "peak_pressure",
    "heat_fraction",
    "air_fuel_ratio",
    "lower_heating_value",
    "soc",
    "duration",
    "wiebe_a",
    "wiebe_m",
)


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
        if name == "heat_fraction" and m.motored:
            words.append("--motored")
            continue
        if name == "crank_radius":
            value = 2 * value
        if isinstance(value, str):
            words += [OPTIONS[name][0], value]
            continue
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
        Written atomically (a temporary file beside it, renamed when complete); refused if
        it is a symbolic link, a folder or in a missing folder (:func:`ringlube.outputs.check_output`).
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
    from ..outputs import atomic_path

    with atomic_path(path) as tmp:
        _write_rows(tmp, psi, p, header)


def _write_rows(path: Path, psi: np.ndarray, p: np.ndarray, header: str) -> None:
    with open(path, "w") as fh:
        if header:
            for line in header.splitlines():
                fh.write(f"# {line}\n")
        fh.write("crank_angle_deg,pressure_Pa\n")
        for a, b in zip(psi, p):
            fh.write(f"{a:.3f},{b:.6e}\n")


def check_trace(psi: np.ndarray, p: np.ndarray) -> None:
    """Check a trace by the kernel's own rules for a trace (crank angles, pressures
    positive and at most its limit) before anything is written.

    Parameters
    ----------
    psi, p : ndarray
        Crank angle [deg] and absolute pressure [Pa].

    Raises
    ------
    ValueError
        The kernel's reason, with the trace's peak.

    Examples
    --------
    >>> check_trace(np.array([0.0, 360.0, 720.0]), np.array([1e5, 2e9, 1e5]))
    Traceback (most recent call last):
    ...
    ValueError: the trace reaches 20000 bar at 360.0 deg, which the kernel refuses: point 2: ...
    """
    from .. import _kernel
    from ..case import Case
    from ..case.kernel import kernel_case, kernel_text

    with kernel_case(Case(), warn=False) as k:
        code, message = _kernel.rl_set_trace(k.handle, np.asarray(psi, float), np.asarray(p, float))
    if code:
        i = int(np.argmax(p))
        reason = kernel_text(message).split("pressure trace: ", 1)[-1]  # not the default case's name
        raise ValueError(
            f"the trace reaches {p[i] / 1e5:.0f} bar at {psi[i]:.1f} deg, which the kernel refuses: {reason}"
        )


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
    from .. import _kernel
    from ..case import Case
    from ..case.kernel import kernel_case

    path = Path(path)
    resolved = str(path.resolve())
    case = Case(name=path.name).set("operating", pressure_file=resolved, pressure_scale=1.0)
    try:
        with kernel_case(case, warn=False) as k:
            n = _kernel.rl_trace_length(k.handle)
            psi, p = _kernel.rl_trace(k.handle, n)
    except InputError as exc:  # the file's own problem, not a case's the user never wrote
        text = str(exc)
        reason = text.split(f"{resolved}: ", 1)[1] if f"{resolved}: " in text else text
        raise InputError(f"{path}: {reason}") from None
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

    from ..plot import crank_axis  # (plot sets the Agg backend: files only)

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
    crank_axis(ax)
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


def write_trace(
    m: GasModel, output: str | Path, name: str | None = None, figures: bool = True, option: str = ""
) -> tuple[list[Path], np.ndarray, np.ndarray]:
    """Write the trace of ``m`` to ``output`` (CSV with its inputs in the header) and, with
    ``figures``, ``output`` with .png and .pdf beside it.

    Every file is checked first (:func:`ringlube.outputs.check_output`: not a symbolic
    link, a folder or in a missing folder), the trace is checked by the kernel's rules
    (:func:`check_trace`) and read back from its temporary file by the kernel's reader, and
    only then are the files renamed into place: a refused trace leaves every file as it was.

    Parameters
    ----------
    m : GasModel
    output : path
        The CSV file.
    name : str, optional
        Name in the header (default: the file's stem).
    figures : bool
        Also write the figure.
    option : str
        What gave ``output``, for messages (e.g. ``"-o"``).

    Returns
    -------
    (list of Path, ndarray, ndarray)
        The files written and the trace as the kernel reads it from the CSV.

    Raises
    ------
    ValueError
        A parameter or load the model cannot meet, or a trace the kernel refuses.
    InputError
        An output that may not be written.

    Examples
    --------
    >>> import tempfile, os
    >>> out = os.path.join(tempfile.mkdtemp(), "p.csv")
    >>> [f.suffix for f in write_trace(PRESETS["crf450r_4000rpm_full"], out)[0]]
    ['.csv', '.png', '.pdf']
    """
    import contextlib

    from ..outputs import atomic_path, check_output

    output = Path(output)
    name = name or output.stem
    files = [output] + ([output.with_suffix(f".{fmt}") for fmt in ("png", "pdf")] if figures else [])
    for f in files:
        check_output(f, option=option if f == output else "")
    psi, p = trace(m)
    check_trace(psi, p)
    derived = describe(m, psi, p)
    with contextlib.ExitStack() as stack:  # every rename only once all are complete
        tmp = stack.enter_context(atomic_path(output, option=option))
        _write_rows(tmp, psi, p, header(m, name, derived, output))
        try:
            back = read_csv(tmp)
        except InputError as exc:
            raise ValueError(f"the trace as written is refused by the kernel's reader: {exc}") from None
        if figures:
            _write_figures(m, psi, p, name, derived, files[1:], stack)
    return files, *back


def _write_figures(m: GasModel, psi, p, name: str, derived: str, paths: list[Path], stack) -> None:
    import matplotlib.pyplot as plt

    from ..outputs import atomic_path
    from ..plot import save_metadata

    parts = derived.split(", ")
    fig = figure(m, psi, p, title=f"'{name}': {', '.join(parts[:3])}\n{', '.join(parts[3:])}")
    try:
        for path in paths:
            fmt = path.suffix.lstrip(".")
            tmp = stack.enter_context(atomic_path(path))
            fig.savefig(tmp, format=fmt, dpi=150, metadata=save_metadata(fmt))
    finally:
        plt.close(fig)


#: Shipped traces written by ``ringlube gas -o`` (their headers record that command and the
#: derived quantities); the others have the parameters alone.
_WITH_COMMAND = ("crf450r_8000rpm_full", "crf450r_12000rpm_full", "own86_3000rpm_full")


def write_presets(out: str | Path, names: list[str] | None = None) -> list[str]:
    """Write shipped traces (:data:`PRESETS`) into the folder ``out`` (created if needed),
    each atomically and as ``inputs/pressure`` holds it; returns one line per trace.

    Parameters
    ----------
    out : path
        Output folder.
    names : list of str, optional
        The traces (default: all).

    Examples
    --------
    >>> import tempfile
    >>> write_presets(tempfile.mkdtemp(), ["crf450r_3000rpm_half"])
    ['crf450r_3000rpm_half: peak 35.0 bar at 381.5 deg']
    """
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    lines = []
    for name in names or sorted(PRESETS):
        m = PRESETS[name]
        psi, p = trace(m)
        check_trace(psi, p)
        if name in _WITH_COMMAND:
            head = header(m, name, describe(m, psi, p), Path("inputs") / "pressure" / f"{name}.csv")
        else:
            head = header(m, name)
        write_csv(out / f"{name}.csv", psi, p, header=head)
        i = int(np.argmax(p))
        lines.append(f"{name}: peak {p[i] / 1e5:.1f} bar at {psi[i]:.1f} deg")
    return lines


def main(argv: list[str] | None = None) -> None:
    """Regenerate shipped traces: ``python -m ringlube.gas --out DIR [NAME ...]``.

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

    ap = argparse.ArgumentParser(prog="python -m ringlube.gas", description=__doc__.splitlines()[0])
    ap.add_argument("--out", required=True, help="output folder (inputs/pressure: the shipped traces)")
    ap.add_argument("names", nargs="*", help=f"presets to write (default: all, {', '.join(sorted(PRESETS))})")
    args = ap.parse_args(argv)
    unknown = [n for n in args.names if n not in PRESETS]
    if unknown:
        ap.error(f"unknown trace {', '.join(unknown)}")
    for line in write_presets(args.out, args.names):
        print(line)


if __name__ == "__main__":
    main()
