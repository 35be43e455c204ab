"""Drives, loads and shaft stress data for torsional analysis (``[torsional]`` of a model).

A drive or a load is a torque about the shaft axis at one shaft node, a function of time t,
the node's speed Ω along its shaft's sense of rotation and (for a synchronous motor) its angle:

* drives act **with** the rotation (a positive drive torque accelerates the shaft in its
  nominal sense of rotation); loads act **against** it;
* the sense of rotation of a shaft is the sign of its nominal speed (``Train.speed`` times the
  shaft's speed ratio; the ratio's sign when the train speed is 0);
* electric-motor torques are given in per unit of the drive's rated torque
  ``T_r = rated_power / rated_speed`` where tables say so.

Drive types (``type = ...``):

``"induction_motor"``
    torque–speed curve from the Steinmetz per-phase equivalent circuit (``circuit``: R1, X1,
    R2, X2, Xm referred to the stator, line-to-line voltage, star connection) or a measured
    ``table`` (torque against speed). Circuit torque (Thevenin form; e.g. Chapman, *Electric
    Machinery Fundamentals*, 4th ed. 2005, §7.5, eq. 7-50):
    ``T = q V_th² (R2/s) / (Ω_s [(R_th + R2/s)² + (X_th + X2)²])``, s = 1 − Ω/Ω_s,
    Ω_s = ω_line / (poles/2).
``"synchronous_motor"``
    asynchronous start-up on the damper cage: average torque T_avg(s) and pulsating torque
    amplitude T_p(s) against slip from a ``start`` table (per unit of rated torque); the
    pulsating torque is ``T_p(s) sin 2δ`` with the electrical angle ``δ = ω_line t − (poles/2) θ``
    between the stator field and the rotor, so it pulsates at 2·s·f_line whatever the speed
    history (dδ/dt = s ω_line). At ``pull_in_slip`` the field is applied and the motor pulls
    into step: from then on ``T = T_avg(s) + T_po sin(δ − δ_p)`` (pull-out torque ``T_po``,
    δ_p the angle at pull-in, so the synchronous torque starts from zero).
``"torque"``
    a prescribed torque: a constant ``value``, a ``table`` against speed (a turbine, a
    measured motor curve without electrical model) or a ``history`` against time (a measured
    or computed air-gap torque, an engine's torque record, a test-rig drive).

Events on an electric drive: ``voltage`` (a voltage factor v(t) against time, e.g. a dip
during start-up: asynchronous torques scale with v², the synchronous torque with v),
``short_circuit`` (the air-gap torque of a two- or three-phase terminal fault, which replaces
the motor torque from its ``time`` until ``clear_time``, after which the motor is
disconnected); on every drive ``trip_time`` (the drive torque drops to zero).

Short-circuit air-gap torque, per unit of rated torque, τ = t − t_fault. The textbook form:
a three-phase terminal fault gives an air-gap torque oscillating at line frequency that decays
with the armature time constant, ≈ (E²/X''_d) e^{−τ/T_a} sin ωτ, and a line-to-line (two-phase)
fault adds a twice-line-frequency term (Concordia, *Synchronous Machines: Theory and
Performance*, 1951; the machine's reactances and time constants as in Kundur, *Power System
Stability and Control*, 1994, ch. 3-4; torsional use and typical traces in Wachel & Szenasi,
*Analysis of torsional vibrations in rotating machinery*, Proc. 22nd Turbomachinery Symposium,
Texas A&M, 1993):

    T(τ)/T_r = a0 e^{−τ/τ0} + a1 e^{−τ/τ1} sin(ω τ) − a2 e^{−τ/τ2} sin(2 ω τ),   ω = 2π f_line

(``a0`` the unidirectional braking component from the resistive losses; ``a2 = 0`` for a
three-phase fault). The amplitudes and time constants are inputs: they come from the machine's
sub-transient reactances and time constants.

Loads (``type = ...``): ``"constant"`` (``torque``), ``"quadratic"`` (``torque`` at ``speed``,
T ∝ Ω², a centrifugal compressor or fan), ``"table"`` (torque against speed) or ``"history"``
(torque against time: a recorded process load, a propeller's ice impacts); ``steps`` multiply
the load torque by a factor from a time on (load rejection: factor 0). In the linear analyses
(the rated operating point) a history acts with its last value.

Tables are interpolated linearly and held constant beyond their ends.
"""

from __future__ import annotations

from typing import Annotated, Literal

import numpy as np
from pydantic import Field, model_serializer, model_validator

from ..errors import ModelError
from ..units import (
    AngularSpeed,
    Dimensionless,
    Frequency,
    Power,
    Resistance,
    Time,
    Torque,
    Voltage,
)
from .components import Int, NodeRef, Spec

__all__ = [
    "MAX_TORQUE",
    "SpeedTorqueTable",
    "TorqueHistory",
    "EquivalentCircuit",
    "StartTable",
    "VoltageProfile",
    "ShortCircuit",
    "InductionMotor",
    "SynchronousMotor",
    "TorqueDrive",
    "Drive",
    "LoadStep",
    "Load",
    "StressConcentration",
    "Torsional",
]


def _strictly_increasing(values, name: str) -> None:
    bad = [k for k in range(1, len(values)) if values[k] <= values[k - 1]]
    if bad:
        k = bad[0]
        raise ValueError(
            f"'{name}' must be strictly increasing: {name}[{k}] = {values[k]:.6g} follows "
            f"{name}[{k - 1}] = {values[k - 1]:.6g}"
        )


# Bounds on magnitudes, each with its reason (issue 23: absurd values ran, or diverged with a
# misleading "reduce dt"):
#: |torque| of a drive, a load or a table entry (N·m): the largest machines built carry ~1e7 N·m
#: (a 1.75 GW turbine–generator at 1500 rpm: 1.1e7 N·m); a hundred times that is no machine.
MAX_TORQUE = 1e9
#: rated power (W): ten times the largest turbine–generators (~1.75 GW).
MAX_POWER = 1e10
#: supply frequency (Hz): 50/60 Hz grids, inverter-fed high-speed motors up to ~1.5 kHz.
MAX_LINE_FREQUENCY_HZ = 2000.0
#: voltage factor (p.u. of rated): supplies are held within ±10 %; twice rated would break
#: down the insulation, not start the motor.
MAX_VOLTAGE_FACTOR = 2.0
#: motor torques per unit of rated (tables, pull-out, breakdown of a circuit): NEMA/IEC motors
#: break down at 1.6–3 p.u., synchronous motors pull out at 1.5–2.5 p.u.
MAX_MOTOR_PU = 10.0
#: short-circuit air-gap torque amplitudes (p.u.): terminal faults peak at 4–10 × rated
#: (Kundur, Power System Stability and Control, 1994, §3.7; Wachel & Szenasi 1993).
MAX_SHORT_CIRCUIT_PU = 20.0


def _bounded(values, name: str, limit: float, unit: str, reason: str) -> None:
    for k, v in enumerate(values if isinstance(values, list | tuple) else [values]):
        if v is not None and not abs(v) <= limit:
            where = f"{name}[{k}]" if isinstance(values, list | tuple) else name
            raise ValueError(f"{where} = {v:.6g} {unit} is beyond {limit:.3g} {unit} ({reason})")


_TORQUE_REASON = "no machine carries more; the largest carry ~1e7 N·m"


class SpeedTorqueTable(Spec):
    """Torque (N·m) against speed along the sense of rotation (rad/s, or e.g. ``"1500 rpm"``)."""

    speed: list[AngularSpeed] = Field(min_length=2)
    torque: list[Torque] = Field(min_length=2)

    @model_validator(mode="after")
    def _check(self) -> SpeedTorqueTable:
        if len(self.speed) != len(self.torque):
            raise ValueError(
                f"'speed' has {len(self.speed)} values, 'torque' has {len(self.torque)}"
            )
        _strictly_increasing(self.speed, "speed")
        _bounded(self.torque, "torque", MAX_TORQUE, "N·m", _TORQUE_REASON)
        return self


class TorqueHistory(Spec):
    """Torque (N·m) against time (s): interpolated linearly, held beyond its ends."""

    time: list[Time] = Field(min_length=2)
    torque: list[Torque] = Field(min_length=2)

    @model_validator(mode="after")
    def _check(self) -> TorqueHistory:
        if len(self.time) != len(self.torque):
            raise ValueError(f"'time' has {len(self.time)} values, 'torque' has {len(self.torque)}")
        _strictly_increasing(self.time, "time")
        _bounded(self.torque, "torque", MAX_TORQUE, "N·m", _TORQUE_REASON)
        return self


class EquivalentCircuit(Spec):
    """Steinmetz per-phase equivalent circuit of an induction motor, referred to the stator
    (ohm per phase), with the line-to-line supply ``voltage`` (rms) of a star connection."""

    r1: Resistance = Field(ge=0, description="stator resistance")
    x1: Resistance = Field(ge=0, description="stator leakage reactance")
    r2: Resistance = Field(gt=0, description="rotor resistance referred to the stator")
    x2: Resistance = Field(ge=0, description="rotor leakage reactance")
    xm: Resistance = Field(gt=0, description="magnetising reactance")
    voltage: Voltage = Field(gt=0, description="line-to-line rms voltage")
    phases: Int = Field(default=3, ge=1)

    def thevenin(self) -> tuple[float, float, float]:
        """(V_th phase rms, R_th, X_th) of the stator side seen from the rotor branch."""
        v_phase = self.voltage / np.sqrt(3.0) if self.phases == 3 else self.voltage
        z1 = complex(self.r1, self.x1)
        zm = complex(0.0, self.xm)
        vth = abs(v_phase * zm / (z1 + zm))
        zth = z1 * zm / (z1 + zm)
        return float(vth), float(zth.real), float(zth.imag)


class StartTable(Spec):
    """Synchronous-motor start-up torques against slip s = 1 − Ω/Ω_s (0 ≤ s ≤ 1), per unit of
    the rated torque: ``average`` (damper-cage asynchronous torque) and ``pulsating``
    (amplitude of the torque at 2·s·f_line from the rotor's saliency)."""

    slip: list[Dimensionless] = Field(min_length=2)
    average: list[Dimensionless] = Field(min_length=2)
    pulsating: list[Dimensionless] = Field(min_length=2)

    @model_validator(mode="after")
    def _check(self) -> StartTable:
        n = len(self.slip)
        for name in ("average", "pulsating"):
            if len(getattr(self, name)) != n:
                raise ValueError(f"'{name}' has {len(getattr(self, name))} values, 'slip' has {n}")
        for k, s in enumerate(self.slip):
            if not 0.0 <= s <= 1.0:
                raise ValueError(f"slip[{k}] = {s:.6g} is outside 0..1 (s = 1 − Ω/Ω_s)")
        d = np.diff(self.slip)
        if not (np.all(d > 0) or np.all(d < 0)):
            raise ValueError("'slip' must be strictly monotone (e.g. 1.0, 0.8, ..., 0.0)")
        if any(p < 0 for p in self.pulsating):
            raise ValueError("'pulsating' amplitudes must be ≥ 0")
        for name in ("average", "pulsating"):
            _bounded(getattr(self, name), name, MAX_MOTOR_PU, "p.u.", "a motor's start-up torque")
        return self

    def arrays(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(slip, average, pulsating) sorted by increasing slip."""
        order = np.argsort(self.slip)
        return (
            np.asarray(self.slip, float)[order],
            np.asarray(self.average, float)[order],
            np.asarray(self.pulsating, float)[order],
        )


class VoltageProfile(Spec):
    """Supply voltage factor v(t) (1 = rated) against time, e.g. a dip during start-up."""

    time: list[Time] = Field(min_length=1)
    factor: list[Dimensionless] = Field(min_length=1)

    @model_validator(mode="after")
    def _check(self) -> VoltageProfile:
        if len(self.time) != len(self.factor):
            raise ValueError(f"'time' has {len(self.time)} values, 'factor' has {len(self.factor)}")
        _strictly_increasing(self.time, "time")
        if any(f < 0 for f in self.factor):
            raise ValueError("voltage factors must be ≥ 0")
        _bounded(
            self.factor,
            "factor",
            MAX_VOLTAGE_FACTOR,
            "p.u.",
            "supplies are held within ±10 % of rated",
        )
        return self


class ShortCircuit(Spec):
    """Air-gap torque of a terminal short circuit (module docstring): from ``time`` to
    ``clear_time`` (default: not cleared within the run) it replaces the motor torque; after
    clearing the motor is disconnected. Amplitudes per unit of rated torque, time constants s."""

    type: Literal["three_phase", "two_phase"]
    time: Time = Field(ge=0)
    clear_time: Time | None = None
    a0: Dimensionless = 0.0
    tau0: Time = Field(default=1.0, gt=0)
    a1: Dimensionless
    tau1: Time = Field(gt=0)
    a2: Dimensionless = 0.0
    tau2: Time = Field(default=1.0, gt=0)

    @model_validator(mode="after")
    def _check(self) -> ShortCircuit:
        if self.clear_time is not None and self.clear_time <= self.time:
            raise ValueError(
                f"clear_time = {self.clear_time:.6g} s must be after the fault time "
                f"{self.time:.6g} s"
            )
        for name in ("a0", "a1", "a2"):
            _bounded(
                getattr(self, name),
                name,
                MAX_SHORT_CIRCUIT_PU,
                "p.u.",
                "terminal faults peak at 4–10 × rated",
            )
        if self.type == "three_phase" and self.a2 != 0:
            raise ValueError(
                f"a three-phase fault has no twice-line-frequency torque: a2 = {self.a2:.6g}; "
                "expected a2 = 0 (or type = 'two_phase')"
            )
        return self


class _DriveBase(NodeRef):
    name: str | None = None
    rated_power: Power = Field(gt=0, description="W")
    rated_speed: AngularSpeed | None = Field(default=None, gt=0)
    trip_time: Time | None = Field(default=None, ge=0)

    @model_validator(mode="after")
    def _rated_power_bounded(self) -> _DriveBase:
        _bounded(self.rated_power, "rated_power", MAX_POWER, "W", "ten times the largest machines")
        return self

    @property
    def rated_torque(self) -> float:
        """T_r = rated_power / nominal_speed (N·m)."""
        return self.rated_power / self.nominal_speed

    @property
    def nominal_speed(self) -> float:
        """Rated speed (rad/s)."""
        return self.rated_speed


class _ElectricDrive(_DriveBase):
    poles: Int = Field(ge=2, description="number of poles (even)")
    line_frequency: Frequency = Field(gt=0, description="rad/s, e.g. '60 Hz'")
    voltage: VoltageProfile | None = None
    short_circuit: ShortCircuit | None = None

    @model_validator(mode="after")
    def _even_poles(self) -> _ElectricDrive:
        if self.poles % 2:
            raise ValueError(f"poles = {self.poles}: the number of poles must be even")
        _bounded(
            self.line_frequency / (2 * np.pi),
            "line_frequency",
            MAX_LINE_FREQUENCY_HZ,
            "Hz",
            "grids run at 50/60 Hz, inverter-fed high-speed motors up to ~1.5 kHz",
        )
        return self

    @property
    def synchronous_speed(self) -> float:
        """Ω_s = ω_line / (poles / 2) (rad/s)."""
        return self.line_frequency / (self.poles / 2)

    @property
    def nominal_speed(self) -> float:
        """Rated speed (rad/s): ``rated_speed``, else the synchronous speed."""
        return self.rated_speed if self.rated_speed is not None else self.synchronous_speed


class InductionMotor(_ElectricDrive):
    """Induction motor: ``circuit`` or ``table`` (module docstring)."""

    type: Literal["induction_motor"]
    circuit: EquivalentCircuit | None = None
    table: SpeedTorqueTable | None = None

    @model_validator(mode="after")
    def _one_curve(self) -> InductionMotor:
        if (self.circuit is None) == (self.table is None):
            raise ValueError("give exactly one of 'circuit' (equivalent circuit) or 'table'")
        if self.circuit is not None:
            pu = self.breakdown_torque / self.rated_torque
            if not pu <= MAX_MOTOR_PU:
                raise ValueError(
                    f"the circuit's breakdown torque is {pu:.4g} × the rated torque "
                    f"({self.rated_power:.6g} W / {self.nominal_speed * 30 / np.pi:.6g} rpm): "
                    f"beyond {MAX_MOTOR_PU:g} × (motors break down at 1.6–3 ×); check the "
                    "circuit's voltage and impedances against the rated power"
                )
        return self

    @property
    def breakdown_torque(self) -> float:
        """Largest air-gap torque of the circuit at rated voltage (N·m): the Thevenin maximum
        ``q V_th² / (2 Ω_s [R_th + √(R_th² + (X_th + X2)²)])`` (Chapman 2005, eq. 7-54)."""
        c = self.circuit
        vth, rth, xth = c.thevenin()
        return c.phases * vth**2 / (2 * self.synchronous_speed * (rth + np.hypot(rth, xth + c.x2)))

    def circuit_torque(self, slip) -> np.ndarray:
        """Air-gap torque (N·m) of the equivalent circuit at rated voltage for slip s (any
        sign; written in the form regular at s = 0)."""
        c = self.circuit
        vth, rth, xth = c.thevenin()
        s = np.asarray(slip, float)
        return (
            c.phases
            * vth**2
            * c.r2
            * s
            / (self.synchronous_speed * ((rth * s + c.r2) ** 2 + (s * (xth + c.x2)) ** 2))
        )


class SynchronousMotor(_ElectricDrive):
    """Synchronous motor start-up and synchronisation (module docstring)."""

    type: Literal["synchronous_motor"]
    start: StartTable
    pull_in_slip: Dimensionless = Field(default=0.05, gt=0, lt=1)
    pull_out_torque: Dimensionless = Field(
        gt=0, le=MAX_MOTOR_PU, description="T_po per unit of rated torque"
    )


class TorqueDrive(_DriveBase):
    """A prescribed drive torque: constant ``value``, a ``table`` against speed or a
    ``history`` against time."""

    type: Literal["torque"]
    value: Torque | None = None
    table: SpeedTorqueTable | None = None
    history: TorqueHistory | None = None

    @model_serializer(mode="wrap")
    def _without_absent_history(self, handler):
        out = handler(self)  # a drive without a history serialises as before it existed
        if self.history is None:
            out.pop("history", None)
        return out

    @model_validator(mode="after")
    def _one_law(self) -> TorqueDrive:
        if sum(x is not None for x in (self.value, self.table, self.history)) != 1:
            raise ValueError(
                "give exactly one of 'value' (constant torque), 'table' (against speed) or "
                "'history' (against time)"
            )
        _bounded(self.value, "value", MAX_TORQUE, "N·m", _TORQUE_REASON)
        if self.rated_speed is None:
            raise ValueError("a 'torque' drive needs 'rated_speed' (for its rated torque)")
        return self


Drive = Annotated[InductionMotor | SynchronousMotor | TorqueDrive, Field(discriminator="type")]


class LoadStep(Spec):
    """From ``time`` on the load torque is multiplied by ``factor`` (0: load rejection)."""

    time: Time = Field(ge=0)
    factor: Dimensionless = Field(ge=0)


class Load(NodeRef):
    """A load torque against the rotation (module docstring)."""

    name: str | None = None
    type: Literal["constant", "quadratic", "table", "history"]
    torque: Torque | None = Field(default=None, ge=0)
    speed: AngularSpeed | None = Field(default=None, gt=0)
    table: SpeedTorqueTable | None = None
    history: TorqueHistory | None = None
    steps: list[LoadStep] = Field(default_factory=list)

    @model_serializer(mode="wrap")
    def _without_absent_history(self, handler):
        out = handler(self)  # a load without a history serialises as before it existed
        if self.history is None:
            out.pop("history", None)
        return out

    @model_validator(mode="after")
    def _law(self) -> Load:
        if self.type != "history" and self.history is not None:
            raise ValueError(f"a '{self.type}' load takes no 'history' (type = 'history' does)")
        if self.type == "history":
            if self.history is None or self.torque is not None or self.table is not None:
                raise ValueError("a 'history' load needs 'history' (and no 'torque' or 'table')")
        elif self.type == "table":
            if self.table is None or self.torque is not None:
                raise ValueError("a 'table' load needs 'table' (and no 'torque')")
        else:
            if self.torque is None or self.table is not None:
                raise ValueError(f"a '{self.type}' load needs 'torque' (and no 'table')")
            if self.type == "quadratic" and self.speed is None:
                raise ValueError("a 'quadratic' load needs 'speed', where it takes 'torque'")
            _bounded(self.torque, "torque", MAX_TORQUE, "N·m", _TORQUE_REASON)
        _strictly_increasing([s.time for s in self.steps], "steps.time")
        return self

    def torque_at(self, speed: float) -> float:
        """Steady load torque (N·m, ≥ 0 against the rotation) at a speed along the rotation."""
        if self.type == "constant":
            return self.torque
        if self.type == "quadratic":
            return self.torque * speed * abs(speed) / self.speed**2
        if self.type == "history":
            return float(self.history.torque[-1])  # held beyond its end: the steady value
        return float(np.interp(speed, self.table.speed, self.table.torque))


class StressConcentration(Spec):
    """Stress concentration factor (≥ 1) on the shear stress of every element of one section
    (``section`` index of the shaft's ``sections``): keyways, shoulder fillets, shrink fits."""

    shaft: str
    section: Int = Field(ge=0)
    factor: Dimensionless = Field(ge=1)


class Torsional(Spec):
    """Torsional input of a train: ``drives``, ``loads`` and ``stress_concentrations``."""

    drives: list[Drive] = Field(default_factory=list)
    loads: list[Load] = Field(default_factory=list)
    stress_concentrations: list[StressConcentration] = Field(default_factory=list)

    def check(self, train) -> None:
        """Cross-references against the train (node references, shafts, sections); drive and
        load names unique (they label the histories); no drive and load on one node."""
        nodes: dict[tuple[int, int], str] = {}
        names: dict[str, str] = {}
        for group in ("drives", "loads"):
            for k, item in enumerate(getattr(self, group)):
                field = f"torsional.{group}[{k}]"
                node = train.node_index(item, field)
                name = item.name or field
                if name in names:
                    raise ModelError(
                        f"duplicate name: {names[name]} is also called {name!r} (drives and "
                        "loads label the transient's histories)",
                        field=f"{field}.name",
                        value=name,
                        expected="a name no other drive or load has",
                    )
                names[name] = field
                other = nodes.get(node)
                if other is not None and other.split("[")[0] != field.split("[")[0]:
                    raise ModelError(
                        f"a drive and a load on the same node ({other} is there too): the "
                        "load would be taken where it is put in, nothing would transmit it",
                        field=field,
                        value=f"shaft {item.shaft!r}, node {node[1]}",
                        expected="the load where the driven machine is, on another node",
                    )
                nodes.setdefault(node, field)
        for k, sc in enumerate(self.stress_concentrations):
            field = f"torsional.stress_concentrations[{k}]"
            si = train.shaft_index(sc.shaft, f"{field}.shaft")
            n = len(train.shafts[si].sections)
            if sc.section >= n:
                raise ModelError(
                    f"shaft '{sc.shaft}' has no such section",
                    field=f"{field}.section",
                    value=sc.section,
                    expected=f"a section index 0..{n - 1}",
                )
