"""Study files (TOML): a base model, a table of cases, the analysis and the outputs.

A study file names a base model file, parameters (each a short name for one or more dotted model
paths, with an optional unit), the cases (explicit rows, or the product of value lists), the
analysis with its settings and the outputs. Unknown keys are errors; every error names the file,
the field, the value and what was expected. See ``docs/studies.md`` for the format::

    name = "Ka sweep"
    model = "unity_gearbox.toml"            # relative to the study file
    output = "ka_sweep.study"               # study folder (default: <stem>.study)

    [set]                                   # overrides applied to every case
    "meshes[0].variation.terms" = 5

    [parameters]
    unbalance = { paths = ["unbalances[0].amount", "unbalances[1].amount"], unit = "g*mm" }
    ka = { path = "meshes[0].variation.ka_ratio" }

    [cases]
    columns = ["unbalance", "ka"]
    rows = [[720, 0.1], [720, 0.2]]         # or: product = { ka = [0.1, 0.2], unbalance = [...] }

    [analysis]
    type = "transient"                      # or "modal"
    t_end = "0.5 s"
    integrator = "modal-rk4"                # or "rk4"

    [outputs]
    window = "0.25 s"                       # steady-state window at the end of each run
    histories = "window"                    # time histories kept per case: window, full, none
"""

from __future__ import annotations

import dataclasses
import itertools
import math
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Annotated, Any, Literal

from pydantic import BaseModel, ConfigDict, Field, ValidationError, model_validator

from ..errors import ModelError
from ..inputs import read_toml
from ..io import format_validation_error, model_from_file_data
from ..units import AngularSpeed, Time

__all__ = [
    "Case",
    "CasesSpec",
    "ModalSettings",
    "Outputs",
    "Parameter",
    "Study",
    "StudyFile",
    "TransientSettings",
    "load_study",
    "study_from_dict",
    "check_cases",
]

Scalar = float | int | bool | str
# names used by the collected dataset (dimensions, coordinates, metrics)
RESERVED = frozenset(
    {
        "case",
        "label",
        "key",
        "status",
        "error",
        "time",
        "probe",
        "shaft",
        "mesh",
        "component",
        "mode",
        "node",
        "bearing",
        "direction",
        "wall_time",
        "amp_1x",
        "amp_2x",
        "dominant_frequency",
        "speed_mean",
        "speed_fluctuation",
        "speed_dominant_frequency",
        "peak_mesh_force",
        "contact_loss_fraction",
        "mesh_frequency",
        "whirl_power_peak",
        "whirl_power_mean",
        "damped_frequency",
        "log_dec",
        "mode_type",
        "whirl",
    }
)


class _Spec(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)


class Parameter(_Spec):
    """A study parameter: one value per case, written to every model path in ``paths``.

    ``unit`` (e.g. ``"g*mm"``) makes the cell values plain numbers in that unit (the override is
    ``"<value> <unit>"``); without it cells are TOML scalars passed as they are (SI numbers,
    integers, or strings with units). Cells equal to one of ``unset`` leave the base model's
    value in place (SPEC 6.1 writes contact ratio 0 for "no stiffness variation")."""

    path: str | None = None
    paths: list[str] | None = Field(default=None, min_length=1)
    unit: str | None = None
    unset: list[Scalar] = Field(default_factory=list)

    @model_validator(mode="after")
    def _one_path(self) -> Parameter:
        if (self.path is None) == (self.paths is None):
            raise ValueError("give either 'path' (one dotted model path) or 'paths' (a list)")
        return self

    @property
    def targets(self) -> tuple[str, ...]:
        return (self.path,) if self.path is not None else tuple(self.paths or ())


class CasesSpec(_Spec):
    """The case table: ``columns`` + ``rows`` (one row per case), or ``product`` (every
    combination of the value lists, first parameter slowest)."""

    columns: list[str] | None = Field(default=None, min_length=1)
    rows: list[list[Scalar]] | None = Field(default=None, min_length=1)
    product: dict[str, list[Scalar]] | None = Field(default=None, min_length=1)

    @model_validator(mode="after")
    def _one_form(self) -> CasesSpec:
        if (self.rows is None) == (self.product is None):
            raise ValueError("give either 'rows' (with 'columns') or 'product'")
        if self.rows is not None and self.columns is None:
            raise ValueError("'rows' needs 'columns' (the parameter name of each value)")
        if self.product is not None and self.columns is not None:
            raise ValueError("'columns' is used with 'rows' only; 'product' names its parameters")
        return self


class TransientSettings(_Spec):
    """Transient analysis (SPEC 3.3). t_end, dt, save_dt : s; blowup : m.

    ``integrator = "modal-rk4"`` (default: :class:`~gearrotor.analyses.transient.ModalRK4`,
    ``dt`` optional) or ``"rk4"`` (:class:`~gearrotor.analyses.transient.RK4`, the full-model
    reference, ``dt`` required). ``integrator_options`` are passed to the integrator's
    constructor by name (e.g. ``cutoff`` in Hz, ``cutoff_factor``, ``accuracy``,
    ``static_correction``, ``tolerance`` for ModalRK4); unknown names are errors.
    ``save_dt``, ``reactions`` and ``blowup`` as in
    :func:`~gearrotor.analyses.transient.transient`."""

    type: Literal["transient"]
    t_end: Time = Field(gt=0)
    integrator: Literal["modal-rk4", "rk4"] = "modal-rk4"
    dt: Time | None = Field(default=None, gt=0)
    integrator_options: dict[str, float | int | bool | None] = Field(default_factory=dict)
    save_dt: Time | None = Field(default=None, gt=0)
    reactions: bool = True
    blowup: float = Field(default=0.05, gt=0)

    @model_validator(mode="after")
    def _integrator(self) -> TransientSettings:
        if self.integrator == "rk4" and self.dt is None:
            raise ValueError("integrator 'rk4' needs 'dt' (e.g. dt = \"8e-6 s\")")
        cls = integrator_class(self.integrator)
        names = {f.name for f in dataclasses.fields(cls) if f.init} - {"dt"}
        bad = sorted(set(self.integrator_options) - names)
        if bad:
            raise ValueError(
                f"unknown integrator_options {bad} for {self.integrator!r}; "
                f"expected some of {sorted(names)}"
            )
        return self


def integrator_class(name: str) -> type:
    """The integrator option class of a study's ``integrator`` name."""
    from ..analyses.transient import RK4, ModalRK4

    return RK4 if name == "rk4" else ModalRK4


class ModalSettings(_Spec):
    """Damped eigenvalues (SPEC 3.1) at the model's nominal speed (or ``speed``), the lowest
    ``n_modes`` elastic modes (rigid-body and over-damped modes excluded)."""

    type: Literal["modal"]
    n_modes: int = Field(default=10, gt=0)
    speed: AngularSpeed | None = None
    max_frequency: AngularSpeed | None = Field(default=None, gt=0)


class Outputs(_Spec):
    """What each case keeps and how the metrics are taken (window : s; default: the last half
    of the run, at most 0.5 s). ``histories``: the time histories stored per case — the
    ``window`` only (default), the ``full`` run, or ``none`` (metrics still come from the
    window, computed before the histories are dropped)."""

    window: Time | None = Field(default=None, gt=0)
    histories: Literal["window", "full", "none"] = "window"


class StudyFile(_Spec):
    """The study file as written (validated, before the cases are expanded)."""

    name: str | None = None
    model: str
    output: str | None = None
    set: dict[str, Scalar] = Field(default_factory=dict)
    parameters: dict[str, Parameter] = Field(min_length=1)
    cases: CasesSpec
    analysis: Annotated[TransientSettings | ModalSettings, Field(discriminator="type")]
    outputs: Outputs = Outputs()


@dataclass(frozen=True)
class Case:
    """One row of the study: ``values`` by parameter name (as written), ``overrides`` by
    dotted model path (as given to :func:`gearrotor.io.load_model`)."""

    index: int
    values: dict[str, Scalar]
    overrides: dict[str, Any]
    label: str = ""
    where: str = ""  # the case's place in the study file: "cases.rows[3]", "cases.product"


@dataclass(frozen=True)
class Study:
    """A validated study: absolute paths, expanded cases."""

    file: Path
    name: str
    model: Path
    folder: Path
    parameters: dict[str, Parameter]
    base_overrides: dict[str, Any]
    analysis: TransientSettings | ModalSettings
    outputs: Outputs
    cases: tuple[Case, ...] = field(repr=False)

    @property
    def window(self) -> float:
        """Metric window (s)."""
        if self.outputs.window is not None:
            return float(self.outputs.window)
        if isinstance(self.analysis, TransientSettings):
            return min(0.5, 0.5 * float(self.analysis.t_end))
        return 0.0

    @property
    def parameter_names(self) -> tuple[str, ...]:
        return tuple(self.parameters)


def _override_value(name: str, par: Parameter, value: Scalar, where: str, file: str) -> Any:
    if par.unit is None:
        return value
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise ModelError(
            f"parameter {name!r} has unit {par.unit!r}, so its values must be plain numbers",
            field=where,
            value=value,
            expected=f"a number in {par.unit}",
            file=file,
        )
    if not math.isfinite(value):
        raise ModelError("a parameter value must be finite", field=where, value=value, file=file)
    return f"{value!r} {par.unit}"


def _expand(spec: StudyFile, file: str) -> tuple[Case, ...]:
    cs = spec.cases
    if cs.rows is not None:
        columns = list(cs.columns or [])
        rows = cs.rows
        row_field = "cases.rows"
    else:
        columns = list(cs.product or {})
        rows = [list(r) for r in itertools.product(*(cs.product or {}).values())]
        row_field = "cases.product"
    for name in spec.parameters:
        if not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", name) or name in RESERVED:
            raise ModelError(
                "unusable parameter name",
                field=f"parameters.{name}",
                value=name,
                expected="a name of letters, digits and _, not one of the result names "
                f"{sorted(RESERVED)}",
                file=file,
            )
    for k, name in enumerate(columns):
        where = f"cases.columns[{k}]" if cs.rows is not None else f"cases.product.{name}"
        if name not in spec.parameters:
            raise ModelError(
                "unknown parameter",
                field=where,
                value=name,
                expected=f"one of the [parameters] names {sorted(spec.parameters)}",
                file=file,
            )
    dup = sorted({c for c in columns if columns.count(c) > 1})
    if dup:
        raise ModelError(
            "a parameter appears twice in the columns", field="cases.columns", value=dup, file=file
        )
    unused = sorted(set(spec.parameters) - set(columns))
    if unused:
        raise ModelError(
            "parameter defined but not used by the cases",
            field="parameters",
            value=unused,
            expected="a column of [cases] for every parameter",
            file=file,
        )
    targets: dict[str, str] = {}
    for name in columns:
        for p in spec.parameters[name].targets:
            if p in targets or p in spec.set:
                raise ModelError(
                    "a model path is set by more than one parameter (or also by [set])",
                    field=f"parameters.{name}",
                    value=p,
                    file=file,
                )
            targets[p] = name
    cases = []
    for i, row in enumerate(rows):
        where = f"{row_field}[{i}]" if cs.rows is not None else row_field
        if len(row) != len(columns):
            raise ModelError(
                "wrong number of values in a row",
                field=where,
                value=row,
                expected=f"{len(columns)} values, one per column {columns}",
                file=file,
            )
        values = dict(zip(columns, row, strict=True))
        overrides = dict(spec.set)
        for k, (name, value) in enumerate(values.items()):
            par = spec.parameters[name]
            if value in par.unset and not isinstance(value, bool):
                continue
            ov = _override_value(
                name,
                par,
                value,
                f"{where}[{k}]" if cs.rows is not None else f"cases.product.{name}",
                file,
            )
            for p in par.targets:
                overrides[p] = ov
        label = ", ".join(
            f"{k}={v}" + (f" {spec.parameters[k].unit}" if spec.parameters[k].unit else "")
            for k, v in values.items()
        )
        place = where if cs.rows is not None else f"{row_field} (case {i})"
        cases.append(Case(index=i, values=values, overrides=overrides, label=label, where=place))
    return tuple(cases)


def check_cases(study: Study) -> None:
    """Every case's model (the base model with the case's overrides) is valid: ``study run``
    calls it before anything runs. Raises :class:`ModelError` naming the study file, the case's
    row and what the model check said. (:func:`load_study` does not: ``study status`` and
    ``study report`` show the cases of a study as they are, invalid ones as failed.)"""
    base = read_toml(study.model, "model")
    file = str(study.file)
    model = study.model
    for case in study.cases:
        try:
            model_from_file_data(base, model, case.overrides)
        except ModelError as exc:
            field = case.where or f"case {case.index}"
            text = "; ".join(line.strip() for line in str(exc).splitlines())
            raise ModelError(
                f"the case's model is invalid: {text}",
                field=field,
                value=case.label or None,
                file=file,
            ) from None


def study_from_dict(data: dict, *, file: str | Path) -> Study:
    """Validate a study given as nested dicts (as read from TOML); ``file`` anchors the
    relative paths and names the file in errors."""
    file = Path(file).resolve()
    name = str(file)
    if not data:
        raise ModelError(
            "the study file is empty", file=name, expected="a study file (see docs/studies.md)"
        )
    if "shafts" in data and "cases" not in data:
        raise ModelError(
            "this is a rotor model file, not a study file",
            file=name,
            expected="a study file naming its model (see docs/studies.md)",
        )
    try:
        spec = StudyFile.model_validate(data)
    except ValidationError as exc:
        err = format_validation_error(exc, data, name, "the study file")
        # the analysis table is a tagged union: drop the tag from the field paths
        msg = re.sub(r"analysis\.(?:transient|modal)(?=[.:\s])", "analysis", err.message)
        raise ModelError(msg, file=err.file) from None
    model = (file.parent / spec.model).resolve()
    if not model.exists():
        raise ModelError(
            "base model file not found",
            field="model",
            value=spec.model,
            expected="a model file (TOML) path relative to the study file",
            file=name,
        )
    if (
        isinstance(spec.analysis, TransientSettings)
        and spec.outputs.window is not None
        and spec.outputs.window >= spec.analysis.t_end
    ):
        raise ModelError(
            "the metric window must be shorter than the run",
            field="outputs.window",
            value=spec.outputs.window,
            expected=f"less than analysis.t_end = {spec.analysis.t_end} s",
            file=name,
        )
    folder = (file.parent / (spec.output or f"{file.stem}.study")).resolve()
    cases = _expand(spec, name)
    return Study(
        file=file,
        name=spec.name or file.stem,
        model=model,
        folder=folder,
        parameters=dict(spec.parameters),
        base_overrides=dict(spec.set),
        analysis=spec.analysis,
        outputs=spec.outputs,
        cases=cases,
    )


def load_study(path: str | Path) -> Study:
    """Read and validate a study file (TOML). Raises :class:`~gearrotor.errors.ModelError`."""
    path = Path(path)
    return study_from_dict(read_toml(path, "study"), file=path)
