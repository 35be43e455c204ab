"""``gearrotor torsional modes|campbell|response|transient``: the torsional audit of a train
(:mod:`gearrotor.analyses.torsional`).

* ``modes``: natural frequencies, damping, rigid-body flag, largest-stress element per mode
  (:func:`~gearrotor.analyses.torsional.torsional_modes`);
* ``campbell``: interference diagram, crossings with 1x/2x of every shaft, the mesh frequency,
  line frequency and twice it, user orders, VFD harmonics; separation margins, pass/fail
  (:func:`~gearrotor.analyses.torsional.interference`);
* ``response``: forced response to harmonic torques over a speed sweep, shaft torque and shear
  stress, coupling torque, mesh load reversal
  (:func:`~gearrotor.analyses.torsional.torsional_response`);
* ``transient``: start-up / short circuit / trip of the model's ``[torsional]`` drives and
  loads, peak torque per section, fatigue damage, allowable starts
  (:func:`~gearrotor.analyses.torsional.torsional_transient`,
  :func:`~gearrotor.analyses.torsional.fatigue`).

Every command takes ``--format table|json``, ``--plot DIR`` (PNG figures) and ``--set``.
Output locations (``--plot``, ``--output``) are checked before anything runs; files are written
atomically. Exit statuses are those of :mod:`.errors`.
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Annotated

import numpy as np
import typer

from ..errors import ModelError
from ..files import check_output, output_set
from .errors import EXIT_CODES_HELP, cli_errors
from .options import (
    MAX_SPEEDS,
    RPM,
    FormatOpt,
    SetOpt,
    check_format,
    count,
    duration,
    number,
    option_fields,
    rpm,
    speed_grid,
)

__all__ = [
    "torsional_app",
    "modes_command",
    "campbell_command",
    "response_command",
    "transient_command",
    "parse_hold",
    "parse_orders",
    "parse_torque",
]

torsional_app = typer.Typer(
    help="Torsional audit (API 617 / RP 684): modes, interference diagram, forced response, "
    "start-up and short-circuit transients with fatigue.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
    epilog=EXIT_CODES_HELP,
)

ModelArg = Annotated[Path, typer.Argument(help="TOML model file")]
MeshOpt = Annotated[
    str,
    typer.Option("--mesh", help="'flexible' (mesh spring on the line of action) or 'rigid'"),
]
PlotOpt = Annotated[Path | None, typer.Option("--plot", help="directory for PNG figures")]
HoldOpt = Annotated[
    list[str] | None,
    typer.Option(
        "--hold",
        help="hold a node at θ = 0, SHAFT:NODE (a locked rotor, a brake, a test-rig clamp); "
        "repeatable",
    ),
]
HZ = 2 * math.pi


def _check_mesh(mesh: str) -> None:
    if mesh not in ("flexible", "rigid"):
        raise ModelError(
            "unknown mesh model", field="--mesh", value=mesh, expected="'flexible' or 'rigid'"
        )


def check_plot_dir(plot: Path | None) -> None:
    """``--plot DIR``: a folder that exists or can be created, writable (before anything runs)."""
    if plot is not None:
        check_output(plot, "directory", field="--plot")


def check_output_file(path: Path | None, suffixes: tuple[str, ...]) -> None:
    """``--output FILE``: a known suffix, in a writable existing folder."""
    if path is None:
        return
    if path.suffix.lower() not in suffixes:
        raise ModelError(
            "unknown output file type",
            field="--output",
            value=str(path),
            expected=" or ".join(f"a {s} file" for s in suffixes),
        )
    check_output(path, "file", field="--output")


def parse_hold(items: list[str] | None) -> list[dict]:
    """``--hold motor:0`` (repeatable) → [{"shaft": "motor", "node": 0}, ...]."""
    out = []
    for text in items or []:
        shaft, sep, node = text.strip().rpartition(":")
        if not sep or not shaft or not node.strip().isdigit():
            raise ModelError(
                "cannot read the held node",
                field="--hold",
                value=text,
                expected="SHAFT:NODE with a node index, e.g. 'motor:0'",
            )
        out.append({"shaft": shaft, "node": int(node)})
    return out


def _torsional_model(train, mesh: str, hold: list[dict]):
    """The torsional model with the ``--hold`` nodes held (checked against the train)."""
    from ..analyses.torsional import torsional_model
    from ..model import NodeRef

    for k, ref in enumerate(hold):
        train.node_index(NodeRef.model_validate(ref), f"--hold[{k}]")
    return torsional_model(train, mesh=mesh, fixed=hold)


def parse_orders(text: str | None) -> list[tuple[str, float]]:
    """``--orders 'motor:6,compressor:0.5'`` → [(shaft, multiple), ...]."""
    if not text:
        return []
    out = []
    for item in text.split(","):
        shaft, sep, mult = item.strip().rpartition(":")
        try:
            m = float(mult)
        except ValueError:
            m = -1.0
        if not sep or not shaft or not m > 0:
            raise ModelError(
                "cannot read the excitation orders",
                field="--orders",
                value=text,
                expected="comma-separated SHAFT:MULTIPLE, e.g. 'motor:6,compressor:0.5'",
            )
        out.append((shaft, m))
    return out


def _floats(text: str | None, field: str, example: str) -> list[float]:
    if not text:
        return []
    try:
        vals = [float(x) for x in text.split(",")]
    except ValueError:
        vals = []
    if not vals or not all(v > 0 for v in vals):
        raise ModelError(
            "cannot read the list of numbers",
            field=field,
            value=text,
            expected=f"comma-separated positive numbers, e.g. '{example}'",
        )
    return vals


def parse_torque(text: str, k: int):
    """``--torque 'shaft=motor,node=4,amplitude=5 kN*m,order=2'`` (or ``frequency=120 Hz``;
    optional ``order_shaft``, ``phase``, ``name``) → :class:`HarmonicTorque`."""
    from pydantic import ValidationError

    from ..analyses.torsional import HarmonicTorque

    field = f"--torque[{k}]"
    data = {}
    for item in text.split(","):
        key, sep, val = item.partition("=")
        if not sep or not key.strip():
            raise ModelError(
                "cannot read the harmonic torque",
                field=field,
                value=text,
                expected="KEY=VALUE pairs: shaft, node, amplitude, order or frequency "
                "(e.g. 'shaft=motor,node=4,amplitude=5 kN*m,order=2')",
            )
        data[key.strip()] = val.strip()
    if "node" in data and data["node"].lstrip("-").isdigit():
        data["node"] = int(data["node"])
    try:
        return HarmonicTorque.model_validate(data)
    except ValidationError as exc:
        # an unknown key first (it explains a "missing" one), in the option's words
        errors = sorted(exc.errors(), key=lambda e: e["type"] != "extra_forbidden")
        err = errors[0]
        loc = ".".join(str(x) for x in err["loc"])
        msg = {"missing": "required key is missing", "extra_forbidden": "unknown key"}.get(
            err["type"], err["msg"].removeprefix("Value error, ")
        )
        raise ModelError(
            msg,
            field=f"{field}.{loc}" if loc else field,
            value=text,
            expected="shaft, node, amplitude (N*m) and one of order / frequency",
        ) from None


def _echo_json(obj) -> None:
    typer.echo(json.dumps(obj, indent=1, allow_nan=False, default=_jsonable))


def _jsonable(x):
    import numpy as np

    if isinstance(x, np.generic):
        return x.item()
    raise TypeError(type(x))


def _load(model: Path, set_):
    from ..io import load_model, parse_overrides

    return load_model(model, parse_overrides(set_))


@torsional_app.command("modes", epilog=EXIT_CODES_HELP)
@cli_errors()
def modes_command(
    model: ModelArg,
    mesh: MeshOpt = "flexible",
    max_frequency: Annotated[
        float | None,
        typer.Option(
            "--max-frequency", parser=number(0, strict=True), help="Hz, keep modes up to it"
        ),
    ] = None,
    n_modes: Annotated[
        int | None, typer.Option("--n-modes", parser=count(1), help="keep the lowest N")
    ] = 12,
    shapes: Annotated[bool, typer.Option(help="JSON: add each mode's twist per shaft")] = False,
    hold: HoldOpt = None,
    format: FormatOpt = "table",
    plot: PlotOpt = None,
    set_: SetOpt = None,
) -> None:
    """Torsional natural frequencies, damping and mode shapes (rigid-body modes flagged)."""
    from ..analyses.torsional import torsional_modes

    check_format(format)
    _check_mesh(mesh)
    check_plot_dir(plot)
    held = parse_hold(hold)
    train = _load(model, set_)
    res = torsional_modes(
        _torsional_model(train, mesh, held),
        max_frequency=None if max_frequency is None else max_frequency * HZ,
        n_modes=n_modes,
    )
    if format == "json":
        _echo_json(res.to_dict(shapes=shapes))
    else:
        typer.echo(f"{train.name}: torsional modes ({mesh} meshes, {res.model.n} DOF)")
        typer.echo(res.table())
    if plot is not None:
        from ..plots.torsional import plot_torsional_modes

        _plot(plot_torsional_modes, res, plot / "torsional_modes.png", format)


@torsional_app.command("campbell", epilog=EXIT_CODES_HELP)
@cli_errors()
def campbell_command(
    model: ModelArg,
    min_speed: Annotated[
        float | None,
        typer.Option(parser=rpm(0), help="rpm, minimum operating speed (default nominal)"),
    ] = None,
    max_speed: Annotated[
        float | None,
        typer.Option(
            parser=rpm(0, strict=True), help="rpm, maximum continuous speed (default nominal)"
        ),
    ] = None,
    margin: Annotated[
        float, typer.Option(parser=number(0, maximum=1), help="required separation (fraction)")
    ] = 0.10,
    line_frequency: Annotated[
        float | None,
        typer.Option(
            "--line-frequency",
            parser=number(0, strict=True),
            help="Hz (default: the electric drives')",
        ),
    ] = None,
    orders: Annotated[
        str | None, typer.Option(help="extra orders SHAFT:MULTIPLE, e.g. 'motor:6'")
    ] = None,
    vfd_harmonics: Annotated[
        str | None,
        typer.Option(help="multiples of the first electric drive's stator frequency, e.g. '6,12'"),
    ] = None,
    max_frequency: Annotated[
        float | None,
        typer.Option(
            "--max-frequency", parser=number(0, strict=True), help="Hz, highest mode checked"
        ),
    ] = None,
    mesh: MeshOpt = "flexible",
    hold: HoldOpt = None,
    format: FormatOpt = "table",
    plot: PlotOpt = None,
    set_: SetOpt = None,
) -> None:
    """Torsional interference diagram: crossings, separation margins, pass/fail."""
    from ..analyses.torsional import interference

    check_format(format)
    _check_mesh(mesh)
    check_plot_dir(plot)
    extra = parse_orders(orders)
    held = parse_hold(hold)
    vfd = _floats(vfd_harmonics, "--vfd-harmonics", "6,12")
    if not 0 <= margin < 1:
        raise ModelError(
            "the separation margin is a fraction", field="--margin", value=margin, expected="0..1"
        )
    train = _load(model, set_)
    nominal = abs(train.speed) / RPM
    lo = nominal if min_speed is None else min_speed
    hi = nominal if max_speed is None else max_speed
    if not lo <= hi:
        raise ModelError(
            "invalid operating speed range",
            field="--min-speed/--max-speed",
            value=f"{lo:g}..{hi:g} rpm",
            expected="0 < min ≤ max",
        )
    with option_fields(orders="--orders"):
        res = interference(
            _torsional_model(train, mesh, held),
            speed_range=(lo * RPM, hi * RPM),
            margin=margin,
            line_frequency=None if line_frequency is None else line_frequency * HZ,
            orders=extra,
            vfd_harmonics=vfd,
            max_frequency=None if max_frequency is None else max_frequency * HZ,
        )
    if format == "json":
        _echo_json(res.to_dict())
    else:
        typer.echo(f"{train.name}: torsional interference ({'PASS' if res.passes else 'FAIL'})")
        typer.echo(res.table())
    if plot is not None:
        from ..plots.torsional import plot_interference

        _plot(plot_interference, res, plot / "torsional_interference.png", format)


@torsional_app.command("response", epilog=EXIT_CODES_HELP)
@cli_errors()
def response_command(
    model: ModelArg,
    torque: Annotated[
        list[str],
        typer.Option(
            "--torque",
            help="harmonic torque KEY=VALUE,...: shaft, node, amplitude, order or frequency "
            "(e.g. 'shaft=motor,node=4,amplitude=5 kN*m,order=2'); repeatable",
        ),
    ],
    min_speed: Annotated[
        float | None, typer.Option(parser=rpm(0), help="rpm (default 0.5 × nominal)")
    ] = None,
    max_speed: Annotated[
        float | None, typer.Option(parser=rpm(0, strict=True), help="rpm (default 1.2 × nominal)")
    ] = None,
    n_speeds: Annotated[
        int | None,
        typer.Option(parser=count(2, MAX_SPEEDS), help="number of speeds [default: 200]"),
    ] = None,
    speed: Annotated[
        float | None,
        typer.Option(
            parser=rpm(0),
            help="rpm: the response at this one speed instead of a sweep (each torque at its "
            "one frequency: its order of this speed, or its fixed frequency)",
        ),
    ] = None,
    mesh: MeshOpt = "flexible",
    hold: HoldOpt = None,
    format: FormatOpt = "table",
    plot: PlotOpt = None,
    set_: SetOpt = None,
) -> None:
    """Forced torsional response: alternating shaft torque and stress, coupling torque, mesh
    load reversal (tooth separation) over a speed sweep, or at one speed (``--speed``)."""
    from ..analyses.torsional import torsional_response

    check_format(format)
    _check_mesh(mesh)
    check_plot_dir(plot)
    if speed is not None and (min_speed, max_speed, n_speeds) != (None, None, None):
        raise ModelError(
            "give either one --speed or a sweep",
            field="--speed",
            value=f"{speed:g} rpm with --min-speed/--max-speed/--n-speeds",
            expected="--speed alone, or --min-speed/--max-speed/--n-speeds",
        )
    exc = [parse_torque(t, k) for k, t in enumerate(torque)]
    held = parse_hold(hold)
    train = _load(model, set_)
    if speed is not None:
        lo = hi = speed
        speeds = np.array([speed * RPM])
    else:
        nominal = abs(train.speed) / RPM
        lo = 0.5 * nominal if min_speed is None else min_speed
        hi = 1.2 * nominal if max_speed is None else max_speed
        speeds = speed_grid(
            lo, hi, 200 if n_speeds is None else n_speeds, "--min-speed/--max-speed"
        )
    with option_fields(excitations="--torque"):
        res = torsional_response(
            _torsional_model(train, mesh, held), excitations=exc, speeds=speeds
        )
    if format == "json":
        _echo_json(res.to_dict())
    else:
        where = f"at {lo:.0f} rpm" if speed is not None else f"{lo:.0f}..{hi:.0f} rpm"
        typer.echo(f"{train.name}: torsional forced response {where}")
        typer.echo(res.table())
    if plot is not None:
        from ..plots.torsional import plot_torsional_response

        _plot(plot_torsional_response, res, plot / "torsional_response.png", format)


@torsional_app.command("transient", epilog=EXIT_CODES_HELP)
@cli_errors()
def transient_command(
    model: ModelArg,
    t_end: Annotated[float, typer.Option("--t-end", parser=duration(), help="end time, s")] = 20.0,
    dt: Annotated[
        float | None,
        typer.Option("--dt", parser=duration(), help="time step, s (default: automatic)"),
    ] = None,
    initial_speed: Annotated[
        float,
        typer.Option("--initial-speed", parser=rpm(0), help="rpm of the reference shaft at t = 0"),
    ] = 0.0,
    mesh: MeshOpt = "flexible",
    sn_m: Annotated[
        float,
        typer.Option(
            "--sn-m", parser=number(0, strict=True), help="S-N curve exponent m (N = C S^-m)"
        ),
    ] = 8.0,
    sn_stress: Annotated[
        str, typer.Option("--sn-stress", help="shear stress amplitude of the S-N point")
    ] = "200 MPa",
    sn_cycles: Annotated[
        float,
        typer.Option("--sn-cycles", parser=number(0, strict=True), help="cycles at that stress"),
    ] = 1e4,
    endurance_limit: Annotated[
        str | None, typer.Option("--endurance-limit", help="shear stress amplitude, e.g. '60 MPa'")
    ] = None,
    output: Annotated[
        Path | None,
        typer.Option("--output", "-o", help="write the histories: FILE.nc (NetCDF) or FILE.json"),
    ] = None,
    format: FormatOpt = "table",
    plot: PlotOpt = None,
    set_: SetOpt = None,
) -> None:
    """Start-up / short-circuit / trip transient of the model's torsional drives and loads:
    peak torque per shaft section, coupling and mesh loads, fatigue damage, allowable starts."""
    from ..analyses.torsional import SNCurve, fatigue, torsional_transient

    check_format(format)
    _check_mesh(mesh)
    check_plot_dir(plot)
    check_output_file(output, (".nc", ".json"))
    if output is not None and output.suffix.lower() == ".nc":
        import h5netcdf  # noqa: F401  (fails early, naming the extra to install)
        import xarray  # noqa: F401
    if not sn_cycles > 0:
        raise ModelError("cycles must be positive", field="--sn-cycles", value=sn_cycles)
    try:
        sn = SNCurve.from_point(
            m=sn_m, stress=sn_stress, cycles=sn_cycles, endurance_limit=endurance_limit
        )
    except ValueError as exc:  # ModelError included: name the options
        msg = exc.message if isinstance(exc, ModelError) else str(exc)
        raise ModelError(
            f"invalid S-N curve: {msg}",
            field="--sn-m/--sn-stress/--sn-cycles/--endurance-limit",
            value=f"m={sn_m:g}, {sn_stress} at {sn_cycles:g} cycles, endurance {endurance_limit}",
            expected="m > 0 and positive stresses with units, e.g. --sn-stress '200 MPa'",
        ) from None
    train = _load(model, set_)
    res = torsional_transient(
        train, t_end=t_end, dt=dt, mesh=mesh, initial_speed=initial_speed * RPM
    )
    fat = fatigue(res, sn)
    with output_set():  # the result file and the figures appear together or not at all
        if output is not None:
            res.save(output, fatigue=fat)
        if plot is not None:
            from ..plots.torsional import plot_fatigue_damage, plot_torsional_transient

            _close(plot_torsional_transient(res, path=plot / "torsional_transient.png"))
            _close(plot_fatigue_damage(fat, path=plot / "torsional_fatigue.png"))
    if format == "json":
        _echo_json({**res.to_dict(), "fatigue": fat.to_dict()})
    else:
        typer.echo(f"{train.name}: torsional transient 0..{t_end:g} s")
        typer.echo(res.table())
        n = fat.allowable_starts
        typer.echo("")
        typer.echo(
            f"fatigue (S-N m = {sn.m:g}, {sn_stress} at {sn_cycles:g} cycles"
            f"{'' if endurance_limit is None else f', endurance {endurance_limit}'}): "
            f"allowable events {'unlimited' if n == float('inf') else f'{n:.4g}'}"
        )
        typer.echo(fat.table())
    if output is not None:
        typer.echo(f"result written to {output}", err=format == "json")
    if plot is not None:
        typer.echo(f"plots written to {plot}/", err=format == "json")


def _close(fig) -> None:
    import matplotlib.pyplot as plt

    plt.close(fig)


def _plot(figure, result, path: Path, format: str) -> None:
    """``figure(result, path=path)`` (a :mod:`gearrotor.plots.torsional` function), its figure
    closed, and the path reported (on stderr when stdout carries JSON)."""
    _close(figure(result, path=path))
    typer.echo(f"plot written to {path}", err=format == "json")
