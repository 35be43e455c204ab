"""``gearrotor stability``: the API 617 stability audit, Level I and Level II
(:func:`gearrotor.analyses.audit.stability_audit.stability_audit`).

Level I inputs come from the model's ``[api_audit]`` table; the options replace them: ``--qa``
(Q_A directly) or the formula's inputs (``--power``, ``--diameter``, ``--height``,
``--density-ratio``, ``--kind``: one stage, at the first ``--at`` node; or ``--stage``, repeated,
one impeller or blade row each), ``--at`` (where Q acts, split by the weights),
``--average-density``, ``--operating-speed``, ``--exclude-bearing``, ``--edition`` (API 617 8th or
9th; default the table's, else the 8th). Level I runs at the
maximum continuous speed, Level II at the operating range's ends and the MCS (``--mcs``,
``--operating-range`` override the model's).
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Annotated

import typer

from ..errors import ModelError
from ..files import check_output, output_set
from .errors import cli_errors
from .options import (
    RPM,
    FormatOpt,
    McsOpt,
    OperatingPointOpt,
    OperatingRangeOpt,
    SetOpt,
    check_format,
    check_operating_point,
    check_png,
    number,
    operating_range_from_options,
    rpm,
)
from .progress import current

__all__ = ["stability_command", "parse_site", "parse_stage"]

_STAGE_KEYS = {
    "power": "power",
    "diameter": "length",
    "height": "length",
    "density_ratio": "dimensionless",
    "kind": None,
}


def parse_site(text: str) -> tuple[str, int | str, float]:
    """``SHAFT:NODE[:WEIGHT]`` -> (shaft, node, weight); NODE an index or ``mid`` (the middle
    of the shaft's bearing span)."""
    parts = text.split(":")
    bad = ModelError(
        "cannot read the site",
        field="--at",
        value=text,
        expected="SHAFT:NODE or SHAFT:NODE:WEIGHT (NODE an index or 'mid', WEIGHT > 0)",
    )
    if len(parts) not in (2, 3) or not parts[0]:
        raise bad
    node: int | str
    if parts[1] in ("mid", "mid_span"):
        node = "mid_span"
    else:
        try:
            node = int(parts[1])
        except ValueError:
            raise bad from None
        if node < 0:
            raise bad
    try:
        weight = float(parts[2]) if len(parts) == 3 else 1.0
    except ValueError:
        raise bad from None
    if not weight > 0:
        raise bad
    return parts[0], node, weight


def parse_stage(text: str):
    """``SHAFT:NODE:power=...,diameter=...,height=...[,density_ratio=...][,kind=axial]``."""
    from ..analyses.audit.stability import Stage
    from ..units import to_si

    head, _, rest = text.partition(":")
    node_text, _, spec = rest.partition(":")
    expected = (
        "SHAFT:NODE:power=1.5 MW,diameter=0.4 m,height=25 mm,density_ratio=1.3"
        "[,kind=centrifugal|axial]"
    )
    try:
        node = int(node_text)
        items = dict(kv.split("=", 1) for kv in spec.split(",") if kv.strip())
    except ValueError:
        raise ModelError(
            "cannot read the stage", field="--stage", value=text, expected=expected
        ) from None
    items = {k.strip(): v.strip() for k, v in items.items()}
    unknown = set(items) - set(_STAGE_KEYS)
    missing = {"power", "diameter", "height"} - set(items)
    if not head or node < 0 or unknown or missing:
        if unknown:
            what = f"unknown stage input {sorted(unknown)}"
        elif missing:
            what = f"stage input missing: {sorted(missing)}"
        else:
            what = "cannot read the stage"
        raise ModelError(what, field="--stage", value=text, expected=expected)
    vals = {}
    for k, kind in _STAGE_KEYS.items():
        if k not in items or kind is None:
            continue
        try:
            vals[k] = to_si(items[k], kind)
        except ValueError as exc:
            raise ModelError(str(exc), field=f"--stage {k}", value=items[k]) from None
        if not vals[k] > 0:
            raise ModelError(
                f"a stage's {k.replace('_', ' ')} must be positive",
                field=f"--stage {k}",
                value=items[k],
                expected="a positive value",
            )
    return Stage(
        head,
        node,
        vals["power"],
        vals["diameter"],
        vals["height"],
        vals.get("density_ratio", 1.0),
        items.get("kind", "centrifugal"),
    )


def _positive(text, kind: str, field: str) -> float | None:
    from ..units import to_si

    if text is None:
        return None
    try:
        v = to_si(text, kind)
    except ValueError as exc:
        raise ModelError(str(exc), field=field, value=text) from None
    if not v > 0:
        raise ModelError(
            f"{field} must be positive", field=field, value=text, expected="a positive value"
        )
    return v


def _chart_paths(plot: Path | None) -> tuple[Path, ...]:
    """The three charts of ``--plot FILE.png``: Level I, the screening chart, Level II."""
    if plot is None:
        return ()
    return (
        plot,
        plot.with_name(plot.stem + "_screening.png"),
        plot.with_name(plot.stem + "_level2.png"),
    )


@cli_errors()
def stability_command(
    model: Annotated[Path, typer.Argument(help="TOML model file")],
    at: Annotated[
        list[str] | None,
        typer.Option(
            "--at",
            help="SHAFT:NODE[:WEIGHT] where the cross-coupling acts (NODE 'mid': mid-span); "
            "repeatable, Q split by the weights (default: the model's [api_audit] at)",
        ),
    ] = None,
    qa: Annotated[
        str | None, typer.Option(help="anticipated cross-coupling Q_A, N/m or with units")
    ] = None,
    power: Annotated[str | None, typer.Option(help="rated power P_r, W or e.g. '12 MW'")] = None,
    diameter: Annotated[
        str | None, typer.Option(help="impeller diameter D_c / blade pitch diameter D_t, m")
    ] = None,
    height: Annotated[
        str | None,
        typer.Option(help="H_c (min. diffuser / impeller discharge width) / blade height H_t, m"),
    ] = None,
    density_ratio: Annotated[
        float | None,
        typer.Option(parser=number(0, strict=True), help="discharge / suction gas density ρ_d/ρ_s"),
    ] = None,
    kind: Annotated[str, typer.Option(help="centrifugal (impeller) or axial (stage)")] = (
        "centrifugal"
    ),
    stage: Annotated[
        list[str] | None,
        typer.Option(
            help="one stage 'SHAFT:NODE:power=..,diameter=..,height=..,density_ratio=..'"
            " (repeatable; Q split by the stages' q_A unless --at is given)"
        ),
    ] = None,
    average_density: Annotated[
        str | None,
        typer.Option(help="average gas density (suction + discharge)/2, kg/m³: screening chart"),
    ] = None,
    operating_speed: Annotated[
        float | None,
        typer.Option(
            parser=rpm(0, strict=True),
            help="normal operating speed N_r of the formula, rpm (default: the model's)",
        ),
    ] = None,
    exclude_bearing: Annotated[
        list[str] | None,
        typer.Option(help="a bearing or seal left out of Level I, by name (repeatable)"),
    ] = None,
    edition: Annotated[
        str | None,
        typer.Option(
            help="API 617 edition: 8th (2014) or 9th (2022); default: the model's "
            "[api_audit] edition, else 8th"
        ),
    ] = None,
    operating_range: OperatingRangeOpt = None,
    mcs: McsOpt = None,
    operating_point: OperatingPointOpt = None,
    format: FormatOpt = "table",
    plot: Annotated[
        Path | None,
        typer.Option(
            help="Level I chart to this PNG; the screening chart and the Level II chart beside "
            "it (NAME_screening.png, NAME_level2.png)"
        ),
    ] = None,
    set_: SetOpt = None,
) -> None:
    """API 617 stability audit: Level I (Q_0 by root search, Q_0/Q_A, screening chart) and
    Level II (log dec of every forward lateral mode with the model's destabilisers)."""
    from ..analyses.audit.stability import Stage
    from ..analyses.audit.stability import edition as pick_edition
    from ..analyses.audit.stability_audit import stability_audit
    from ..io import load_model, parse_overrides
    from ..model import NodeRef

    check_format(format)
    check_png(plot)
    for extra in _chart_paths(plot)[1:]:  # the other two charts (and what killed runs left)
        check_output(extra, "file", field="--plot", parents=True)
    if edition is not None:
        edition = pick_edition(edition, "--edition").key
    sites = [parse_site(a) for a in at or ()]
    stages = [parse_stage(s) for s in stage or ()]
    q = _positive(qa, "stiffness", "--qa")
    rho = _positive(average_density, "density", "--average-density")
    if rho is not None:
        from ..model.api_audit import gas_density

        try:
            gas_density(rho)
        except ValueError as exc:
            what, _, expected = str(exc).partition("; expected ")
            raise ModelError(
                what, field="--average-density", value=average_density, expected=expected
            ) from None
    formula = {"--power": power, "--diameter": diameter, "--height": height}
    given = [k for k, v in formula.items() if v is not None]
    if density_ratio is not None and not density_ratio > 0:
        raise ModelError(
            "the density ratio must be positive",
            field="--density-ratio",
            value=density_ratio,
            expected="ρ_discharge / ρ_suction > 0",
        )
    if density_ratio is not None and not given:
        given = ["--density-ratio"]
    if given and len([k for k in formula if formula[k] is not None]) < 3:
        missing = [k for k, v in formula.items() if v is None]
        raise ModelError(
            "the anticipated cross-coupling formula needs power, diameter and height",
            field=", ".join(missing),
            expected="--power, --diameter and --height (and --density-ratio for an impeller)",
        )
    if kind not in ("centrifugal", "axial"):
        raise ModelError(
            "unknown stage kind", field="--kind", value=kind, expected="'centrifugal' or 'axial'"
        )
    sources = [n for n, v in (("--qa", q), ("--power ...", given), ("--stage", stages)) if v]
    if len(sources) > 1:
        raise ModelError(
            "give the anticipated cross-coupling once",
            field=" / ".join(sources),
            expected="one of --qa, the formula's inputs (--power ...) or --stage",
        )
    if (q is not None or given) and not sites:
        raise ModelError(
            "Q_A from the options needs the nodes where it acts",
            field="--at",
            expected="one or more --at SHAFT:NODE",
        )
    if given and kind == "centrifugal" and density_ratio is None:
        raise ModelError(
            "an impeller's anticipated cross-coupling needs the density ratio",
            field="--density-ratio",
            expected="ρ_discharge / ρ_suction (or --kind axial for a turbine stage)",
        )
    if operating_speed is not None and not operating_speed > 0:
        raise ModelError(
            "the operating speed must be positive", field="--operating-speed", value=operating_speed
        )

    train = load_model(model, parse_overrides(set_))
    check_operating_point(train, operating_point)
    train = operating_range_from_options(train, operating_range, mcs)
    if train.max_continuous_speed is None:
        raise ModelError(
            "the stability audit runs Level I at the maximum continuous speed, and the model "
            "states none",
            file=str(model),
            field="max_continuous_speed",
            expected="max_continuous_speed = '... rpm' in the model, or --mcs RPM",
        )
    for shaft, node, _ in sites:
        if node == "mid_span":
            train.shaft_index(shaft, "--at")
        else:
            train.node_index(NodeRef(shaft=shaft, node=node), "--at")
    for k, s in enumerate(stages):
        train.node_index(NodeRef(shaft=s.shaft, node=s.node), f"--stage[{k}]")
    if given:
        first = sites[0]
        node = first[1]
        if node == "mid_span":
            from ..analyses.audit.stability import mid_span

            node = mid_span(train, first[0]).node
        stages = [
            Stage(
                first[0],
                node,
                _positive(power, "power", "--power"),
                _positive(diameter, "length", "--diameter"),
                _positive(height, "length", "--height"),
                density_ratio if density_ratio is not None else 1.0,
                kind,
            )
        ]
    names = [b.name or f"bearings[{k}]" for k, b in enumerate(train.bearings)]
    names += [sl.name or f"seals[{k}]" for k, sl in enumerate(train.seals)]
    for e in exclude_bearing or ():
        if e not in names:
            raise ModelError(
                "no such bearing or seal to exclude",
                field="--exclude-bearing",
                value=e,
                expected=f"one of {names}",
            )
    res = stability_audit(
        train,
        qa=q,
        stages=stages or None,
        at=sites or None,
        operating_speed=None if operating_speed is None else operating_speed * RPM,
        average_density=rho,
        exclude_bearings=exclude_bearing or None,
        operating_point=operating_point,
        progress=current(),
        edition=edition,
    )
    if format == "json":
        typer.echo(json.dumps({"model": train.name, **res.to_dict()}, indent=1))
    else:
        at = f" at operating point {operating_point}" if operating_point else ""
        typer.echo(f"{train.name}: {res.level1.edition} stability audit{at}")
        typer.echo(res.table())
    if plot is not None:
        import matplotlib.pyplot as plt

        from ..plots.audit import plot_level1, plot_level2, plot_screening

        paths = _chart_paths(plot)
        with output_set():  # the three charts appear together or not at all
            plt.close(plot_level1(res.level1, path=paths[0]))
            plt.close(plot_screening(res.level1, path=paths[1]))
            plt.close(plot_level2(res.level2, path=paths[2]))
        typer.echo("charts written: " + ", ".join(map(str, paths)), err=format == "json")
