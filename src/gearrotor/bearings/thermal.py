"""Thermal fluid-film bearings: effective-temperature and THD models iterated with the film.

A :class:`ThermalModel` in :class:`~gearrotor.bearings.film.SolverOptions` makes
:func:`~gearrotor.bearings.equilibrium` iterate the film (Reynolds, with a viscosity per pad or a
nodal viscosity field) and the temperatures to a consistent state; the dynamic coefficients are
then taken at that viscosity field (the temperatures frozen, as usual for THD coefficients).

The oil flow of a pad
---------------------
Every model starts from the same mass-conserving flow field of a pad, built from the film's
face flows (:func:`~gearrotor.bearings.reynolds.pad_fluxes`, half bearing) on the nodes'
control volumes (half volumes at the bearing edge, the mid-plane and the pad ends):

* a node with a pressure keeps the Reynolds flows of its faces (they balance to round-off);
* a cavitated node (p = 0) or a node on the bearing edge carries downstream what reaches it
  (no axial flow in a cavity), at most the full-film Couette flow of its downstream face: the
  excess leaves the film (a cavity: *spill*; the bearing edge: *side* leakage). Its oil fills the
  gap by the fraction ``arriving flow / full-film Couette flow``;
* where a cavity ends (reformation), the pressurised node draws its Reynolds flow: what the
  cavity brings is topped up by oil from the supply (*make-up*: the oil hole of a plain bearing,
  the groove of a pad), or the surplus spills;
* the leading-edge nodes of a pad take their inflow from the groove at the pad's inlet
  temperature; the trailing-edge nodes deliver the pad's *outlet* flow.

So every control volume balances exactly, and the flows of the pad satisfy
``inlet + make-up = outlet + spill + side``. Power loss is the viscous dissipation
``Φ = r (μU²/h + h³|∇p|²/(12μ))`` over the pad (``r`` the fill fraction; the temperature, hence
μ, uniform across the film).

Inlet mixing (hot-oil carry-over, Ettles' coefficient λ = ``carry_over``): the oil entering pad
k is ``λ Q_out`` of the pad upstream (in the direction of rotation) at that pad's outlet
temperature, topped up with fresh oil at the supply temperature (all of it hot oil when
``λ Q_out`` exceeds what the pad draws). A 360° plain (periodic) film recirculates its own oil:
only the make-up is fresh.

``"effective"`` (adiabatic bulk model, every bearing type)
    Per pad: ``T_out − T_in = P / (ρ c (Q_out + Q_side/2))`` (side leakage leaving at the mean of
    inlet and outlet temperatures), the pad's film at ``T_eff = T_in + f (T_out − T_in)``
    (``f = effective_factor``, 0.5 the mean film temperature of Raimondi & Boyd), one viscosity per
    pad.

``"thd"`` (energy equation in the film resolved across it, fixed-geometry and tilting-pad
journals)
    The steady energy equation ρc u·∇T = ∂/∂y(k ∂T/∂y) + μ|∂u/∂y|² of the film, as the 3-D THD
    models solve it (Ettles; Knight & Barrett): every control volume of the flow field above
    split into ``cross_film_layers`` equal layers across the film (y from the journal, η = y/h).
    Each in-plane flow is shared between the layers by its velocity profile, Couette
    U(1 − η) (share ∫2(1 − η)dη) plus Poiseuille ∝ η(1 − η) (share ∫6η(1 − η)dη), from the
    Couette part the flow field records for every transfer (axial flows are Poiseuille,
    cavity streamers Couette); a layer whose share is negative (back-flow near the pad)
    flows the other way; the oil entering or leaving the film at a pad's edges takes the
    one-way part of its profile. The flow between layers that closes every layer's mass
    balance is the cross-film convection. All convection is first-order upwind and
    conservative; conduction is across the film only (between layer centres h/n apart, and
    through the half layers to the walls; in its plane it is negligible, Péclet numbers
    10⁴–10⁶); each layer's dissipation is (μ/h)∫(∂u/∂η)² + (∂w/∂η)² dη over it, which sums
    to μU²/h + h³|∇p|²/(12μ). The journal surface conducts to the journal body at T_j through
    ``journal_heat_transfer`` α_j (inf: the surface at T_j), the pad surface through the pad
    to the oil behind it, at the supply temperature T_s, through ``pad_heat_transfer`` α_p
    (the pad's conduction and the back's convection in series; the film's own conduction is
    the layers'). The matrix is an M-matrix
    (upwind convection, conduction, sources ≥ 0): no temperature in the film or on a wall
    falls below the coldest oil fed in, or the journal if it is colder (maximum principle),
    and the film develops its profile along the pad (the thermal entrance length U h²/a is
    metres against a pad's centimetres) instead of being given a developed one. One layer is
    the 2-D bulk model (the temperature uniform across the film, the walls through the half
    film h/(2k)), ROSS 3.1's ``"adiabatic"`` film class. The film's viscosity (a nodal field on
    every pad) is taken at the mean temperature across the film (the Reynolds equation is
    2-D; the velocity profiles are those of a film of uniform viscosity). The pad surface
    (babbitt) temperature is the pad-side layer's less its half layer's drop, and the
    hottest temperature reported is the hottest pad surface. The journal is at
    ``journal_temperature``, or, when not given, at the temperature that makes its net heat
    flow zero, solved exactly within every energy balance (every field is affine in the
    inlet and journal temperatures: one sparse LU per pad, three right-hand sides).

Energy is conserved exactly (to round-off) in both models: the power loss equals the heat the
flows carry out (enthalpy out − in, fresh oil at the supply temperature) plus the heat
conducted; :attr:`ThermalResult.energy_residual` reports the difference.

Properties: ρ c taken at the bearing's mean film temperature (constant within a solve, so the
balance is exact), μ(T) from :class:`~gearrotor.bearings.lubricant.Lubricant`.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any, Literal

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray
from scipy.sparse.linalg import splu

from ..errors import ModelError, SolverError
from .lubricant import CELSIUS, Lubricant
from .reynolds import PadFilm, pad_fluxes

__all__ = [
    "ThermalModel",
    "ThermalResult",
    "PadThermal",
    "PadFlow",
    "pad_flow",
    "solve_thermal",
]

Model = Literal["effective", "thd"]


@dataclass(frozen=True)
class ThermalModel:
    """Thermal model of a bearing (module docstring).

    Attributes
    ----------
    model
        ``"effective"`` (adiabatic bulk energy balance, one temperature per pad) or ``"thd"``
        (the energy equation in the film, resolved across it).
    lubricant
        The oil.
    supply_temperature
        Oil supply temperature (K).
    carry_over
        Hot-oil carry-over coefficient λ (0..1): the fraction of a pad's outlet flow that enters
        the next pad. Default 0.8 (ROSS 3.1's default).
    effective_factor
        ``"effective"``: the pad film temperature ``T_in + f (T_out − T_in)``, 0..1; default 0.5
        (the mean film temperature, Raimondi & Boyd 1958).
    pad_heat_transfer
        ``"thd"``: heat transfer coefficient from the pad surface to the oil behind the pads
        (at the supply temperature): the pad's conduction and the back's convection in series
        (W/(m²·K)); 0 = adiabatic (default); the film conducts across its layers to the
        surface (module docstring).
    journal_heat_transfer
        ``"thd"``: heat transfer coefficient from the journal surface to the journal body
        (W/(m²·K)); inf = the surface at the journal temperature (a steel journal); default 0
        (adiabatic); the film conducts across its layers to the surface.
    journal_temperature
        ``"thd"``: journal temperature (K); None = the temperature at which the journal takes no
        net heat (it only carries heat from the hot to the cold part of the film).
    cross_film_layers
        ``"thd"``: equal layers across the film (default 8: the hottest pad surface within
        0.1 K of 32 layers on the tilting-pad examples); 1 = the temperature uniform across
        the film (the 2-D bulk model).
    tol
        Convergence (K): the largest change, from one iteration to the next, of a pad's mean
        film temperature and (THD) of a node's temperature weighted by its share of the peak
        pressure. Default 0.1 K: where the cavity boundary moves by a node between iterations
        (its oil, and the make-up, with it), a few hundredths of a kelvin keep cycling; the
        film does not feel them.
    max_iter
        Iterations of the film–temperature loop.
    relaxation
        Under-relaxation of the temperatures between iterations (0 < r ≤ 1); halved (down to
        0.05) whenever four iterations have not reduced the change by a fifth.
    """

    model: Model
    lubricant: Lubricant
    supply_temperature: float
    carry_over: float = 0.8
    effective_factor: float = 0.5
    pad_heat_transfer: float = 0.0
    journal_heat_transfer: float = 0.0
    journal_temperature: float | None = None
    cross_film_layers: int = 8
    tol: float = 0.1
    max_iter: int = 100
    relaxation: float = 0.7

    def __post_init__(self) -> None:
        if self.model not in ("effective", "thd"):
            raise ModelError(
                "unknown thermal model",
                field="thermal.model",
                value=self.model,
                expected="'isoviscous', 'effective' or 'thd'",
            )
        self.lubricant.check_temperature(self.supply_temperature, "thermal.supply_temperature")
        if self.journal_temperature is not None:
            self.lubricant.check_temperature(
                self.journal_temperature, "thermal.journal_temperature"
            )
        for name in ("carry_over", "effective_factor"):
            v = getattr(self, name)
            if not 0.0 <= v <= 1.0:
                raise ModelError(
                    f"{name} out of range", field=f"thermal.{name}", value=v, expected="0 to 1"
                )
        for name in ("pad_heat_transfer", "journal_heat_transfer"):
            v = getattr(self, name)
            if not v >= 0.0:  # inf: the wall at its sink's temperature
                raise ModelError(
                    f"{name} must be ≥ 0",
                    field=f"thermal.{name}",
                    value=v,
                    expected="a coefficient ≥ 0 W/(m^2*K), or inf",
                )
            if v > 0 and self.model != "thd":
                raise ModelError(
                    f"{name} applies to the THD model only (the effective-temperature model is "
                    "adiabatic)",
                    field=f"thermal.{name}",
                    value=v,
                    expected="model = 'thd', or no heat transfer",
                )
        if not (
            isinstance(self.cross_film_layers, int | np.integer) and 1 <= self.cross_film_layers
        ):
            raise ModelError(
                "cross_film_layers must be a whole number ≥ 1",
                field="thermal.cross_film_layers",
                value=self.cross_film_layers,
                expected="an integer ≥ 1 (1: the temperature uniform across the film)",
            )
        if not (0.0 < self.relaxation <= 1.0):
            raise ModelError(
                "relaxation out of range",
                field="thermal.relaxation",
                value=self.relaxation,
                expected="0 < relaxation ≤ 1",
            )
        if not (self.tol > 0 and self.max_iter >= 1):
            raise ModelError(
                "thermal tolerance and iterations must be positive",
                field="thermal.tol",
                value=(self.tol, self.max_iter),
                expected="tol > 0 K, max_iter ≥ 1",
            )


@dataclass(frozen=True)
class PadThermal:
    """Temperatures, flows and power of one pad (flows over the whole bearing length).

    Attributes
    ----------
    inlet_temperature
        Mixed oil entering the pad at its leading edge (K); for a 360° film, the oil entering
        the pressure zone (its own outlet mixed with the make-up).
    outlet_temperature
        Flow-weighted oil leaving at the trailing edge and out of cavities (K).
    max_temperature
        Hottest pad surface (babbitt) temperature (K): the film's in an adiabatic film
        (module docstring).
    film_temperature
        ``"effective"``: the pad's effective temperature; ``"thd"``: the area mean (K).
    power_loss
        Viscous dissipation in the pad's film (W).
    inlet_flow
        Oil entering: leading edge plus make-up (m³/s).
    outlet_flow
        Oil leaving at the trailing edge and out of cavities (m³/s).
    side_flow
        Leakage out of both bearing ends (m³/s).
    carried_flow
        Hot oil carried over from the pad upstream (or, 360° film, recirculated) (m³/s).
    supply_flow
        Fresh oil entering (m³/s).
    heat_conducted
        Heat to the pad and journal (W, ``"thd"`` with heat transfer).
    heat_carried
        Enthalpy the oil carries out of the pad: ρ c (Σ outflow · T − Σ inflow · T) (W).
    temperature
        ``"thd"``: film (bulk) temperature at the pad's nodes (K), shape (m+1, n+1) (θ from
        the pad start, z from the bearing edge to the mid-plane); None for ``"effective"``.
    surface_temperature
        ``"thd"``: pad surface temperature at the same nodes (K) (module docstring); None for
        ``"effective"``.
    viscosity
        The viscosity the film was solved with: Pa·s, or the nodal field.
    layer_temperature
        ``"thd"``: the temperature of every layer across the film at the same nodes (K), shape
        (m+1, n+1, layers), layer 0 at the journal; None for ``"effective"``.
    """

    inlet_temperature: float
    outlet_temperature: float
    max_temperature: float
    film_temperature: float
    power_loss: float
    inlet_flow: float
    outlet_flow: float
    side_flow: float
    carried_flow: float
    supply_flow: float
    heat_conducted: float
    heat_carried: float
    temperature: NDArray | None = field(default=None, repr=False)
    viscosity: float | NDArray = field(default=0.0, repr=False)
    surface_temperature: NDArray | None = field(default=None, repr=False)
    layer_temperature: NDArray | None = field(default=None, repr=False)


@dataclass(frozen=True)
class ThermalResult:
    """The thermal state of a bearing at equilibrium.

    Attributes
    ----------
    model
        ``"effective"`` or ``"thd"``.
    supply_temperature
        K.
    pads
        Per pad (in the bearing's pad order).
    journal_temperature
        K (``"thd"`` with heat transfer to the journal, or a given journal temperature); NaN
        otherwise.
    iterations
        Film–temperature iterations.
    rho_c
        Volumetric heat capacity ρ c used (J/(m³·K)).
    """

    model: str
    supply_temperature: float
    pads: tuple[PadThermal, ...]
    journal_temperature: float
    iterations: int
    rho_c: float

    @property
    def power_loss(self) -> float:
        """Total viscous dissipation (W)."""
        return sum(p.power_loss for p in self.pads)

    @property
    def side_flow(self) -> float:
        """Total side leakage (m³/s)."""
        return sum(p.side_flow for p in self.pads)

    @property
    def supply_flow(self) -> float:
        """Fresh oil the bearing draws (m³/s): it leaves as side leakage and drain."""
        return sum(p.supply_flow for p in self.pads)

    @property
    def max_temperature(self) -> float:
        """Hottest pad surface temperature (K)."""
        return max(p.max_temperature for p in self.pads)

    @property
    def heat_conducted(self) -> float:
        """Heat to pads and journal (W)."""
        return sum(p.heat_conducted for p in self.pads)

    @property
    def viscosity(self) -> tuple[float | NDArray, ...]:
        """Per pad: the viscosity (Pa·s) or nodal field the film was solved with."""
        return tuple(p.viscosity for p in self.pads)

    @property
    def heat_carried(self) -> float:
        """Enthalpy the oil carries out of the bearing (W): the pads' sum (the oil carried over
        leaves one pad and enters the next at the same temperature), i.e. side leakage, drained
        and spilled oil out minus fresh oil in at the supply temperature."""
        return sum(p.heat_carried for p in self.pads)

    @property
    def energy_residual(self) -> float:
        """power loss − heat carried − heat conducted (W): zero to round-off."""
        return self.power_loss - self.heat_carried - self.heat_conducted


# ---------------------------------------------------------------------------------------------
# The flow field of one pad
# ---------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class PadFlow:
    """Mass-conserving flow of one pad on its control volumes (half bearing), in flow
    coordinates (node index increasing with the direction of rotation).

    Cells are the pad's nodes: ``M × (n+1)`` (M = m + 1, or m for a 360° periodic film whose
    last node is its first), flattened row-major (``cell = i (n+1) + j``).

    Attributes
    ----------
    up, down, flow
        Internal transfers: ``flow[k]`` ≥ 0 m³/s from cell ``up[k]`` to cell ``down[k]``.
    inlet
        Flow entering each cell from the leading-edge groove (m³/s).
    makeup
        Flow entering each cell from the supply where a cavity ends (m³/s).
    recirculated
        Part of each cell's inflow at a reformation that comes from the cavity upstream
        (360° films: the film's own oil) (m³/s).
    recirculated_from
        The same flows, counted at the cavity cells they leave (m³/s).
    outlet
        Flow leaving each cell at the trailing edge (m³/s).
    side
        Flow leaving each cell through the bearing edge (m³/s).
    spill
        Flow leaving the film from each cell (a cavity's excess) (m³/s).
    fill
        Fraction of each cell's gap filled with oil.
    area
        Cell area (m², half bearing).
    periodic
        A 360° film.
    shape
        (M, n+1).
    couette
        The Couette part of every internal transfer (m³/s, in the transfer's direction; the
        rest is its Poiseuille part): how the transfer is shared between the levels across the
        film (``"thd"``, module docstring). Axial transfers are pure Poiseuille, cavity
        streamers pure Couette.
    inlet_couette, outlet_couette
        The Couette part of each cell's ``inlet`` and ``outlet`` flow (m³/s).
    """

    up: NDArray
    down: NDArray
    flow: NDArray
    inlet: NDArray
    makeup: NDArray
    recirculated: NDArray
    recirculated_from: NDArray
    outlet: NDArray
    side: NDArray
    spill: NDArray
    fill: NDArray
    area: NDArray
    periodic: bool
    shape: tuple[int, int]
    couette: NDArray | None = field(default=None, repr=False)
    inlet_couette: NDArray | None = field(default=None, repr=False)
    outlet_couette: NDArray | None = field(default=None, repr=False)

    def imbalance(self) -> NDArray:
        """Net outflow of every cell (m³/s): zero to round-off."""
        n = self.fill.size
        out = np.bincount(self.up, self.flow, n) + self.outlet + self.side + self.spill
        inn = np.bincount(self.down, self.flow, n) + self.inlet + self.makeup
        return out - inn


def _to_flow_coords(a: NDArray, reverse: bool, periodic: bool, axis_faces: bool = False):
    """Node arrays (m+1, …) → flow coordinates (M, …)."""
    if reverse:
        a = -a[::-1] if axis_faces else a[::-1]
    if periodic and not axis_faces:
        a = a[:-1]
    return a


def pad_flow(mesh: Any, film: PadFilm, q: NDArray, omega: float, viscosity, radius, clearance):
    """The :class:`PadFlow` of a steady film (module docstring) and the nodal inputs of the
    energy balance in flow coordinates: (flow, film thickness h (m), pressure gradient
    (∂p/∂x, ∂p/∂z) (Pa/m; x in the direction of rotation, z from the bearing edge), viscosity
    μ (Pa·s)), each (M, n+1)."""
    ft, fz = pad_fluxes(
        mesh, film, q, omega, viscosity=viscosity, radius=radius, clearance=clearance
    )
    periodic = bool(mesh.periodic)
    reverse = omega < 0
    n1 = len(mesh.zeta)
    p = film.pressure
    h = film.film
    mu = np.broadcast_to(np.asarray(viscosity, dtype=float), p.shape)
    # pressure gradient (physical), nodal
    dx = radius * mesh.dth
    dz = radius * mesh.dze
    if periodic:
        pp = p[:-1]
        dpx = (np.roll(pp, -1, axis=0) - np.roll(pp, 1, axis=0)) / (2 * dx)
        dpx = np.vstack([dpx, dpx[:1]])
    else:
        dpx = np.gradient(p, dx, axis=0)
    dpz = np.gradient(p, dz, axis=1)
    dpz[:, -1] = 0.0  # symmetry at the mid-plane

    # Couette part of every θ-face flow (the capacity of a carried face)
    k = clearance * radius**2 / 12.0
    wz = mesh.dzw.copy()
    wz[0] = 0.5 * mesh.dze
    # full-film Couette flow of each θ-face: the face's own Couette film from the conductances
    ft_p0 = pad_fluxes(
        mesh,
        _zero_pressure(film),
        q,
        omega,
        viscosity=viscosity,
        radius=radius,
        clearance=clearance,
    )[0]

    # flow coordinates
    ft = _to_flow_coords(ft, reverse, periodic, axis_faces=True)
    cap = np.abs(_to_flow_coords(ft_p0, reverse, periodic, axis_faces=True))
    fz = _to_flow_coords(fz, reverse, periodic)
    pf = _to_flow_coords(p, reverse, periodic)
    hf = _to_flow_coords(h, reverse, periodic)
    dpxf = _to_flow_coords(dpx, reverse, periodic)
    if reverse:
        dpxf = -dpxf
    dpzf = _to_flow_coords(dpz, reverse, periodic)
    muf = _to_flow_coords(np.array(mu), reverse, periodic)
    big_m = pf.shape[0]
    shape = (big_m, n1)

    # classes: 0 pressure, 1 cavity, 2 edge, 3 leading column, 4 trailing column
    cav = film.pressure == 0.0
    cav[mesh.unk_i, mesh.unk_j] |= film.active  # Swift–Stieber cavitated set
    cls = np.where(_to_flow_coords(cav, reverse, periodic), 1, 0)
    cls[:, 0] = 2
    if not periodic:
        cls[0, :] = 3
        cls[-1, :] = 4
    n_faces = big_m if periodic else big_m - 1

    def nxt(i):
        return (i + 1) % big_m

    def axial_in(i, j):
        s = 0.0
        if j > 0 and fz[i, j - 1] > 0:
            s += fz[i, j - 1]
        if j < n1 - 1 and fz[i, j] < 0:
            s -= fz[i, j]
        return s

    size = big_m * n1
    inlet = np.zeros(size)
    makeup = np.zeros(size)
    recirc = np.zeros(size)
    recirc_from = np.zeros(size)
    outlet = np.zeros(size)
    inlet_c = np.zeros(size)
    outlet_c = np.zeros(size)
    side = np.zeros(size)
    spill = np.zeros(size)
    arrive = np.zeros(size)  # carried arrivals of non-pressure cells (for the fill fraction)
    ups, downs, flows, couettes = [], [], [], []

    def cell(i, j):
        return i * n1 + j

    def transfer(a, b, f, fc):
        """f > 0 from cell a to cell b, of which fc is the Couette part."""
        if f > 0:
            ups.append(a)
            downs.append(b)
            flows.append(f)
            couettes.append(fc)

    # axial faces: Reynolds flows (none between two cells without pressure)
    fz = np.where((cls[:, :-1] == 0) | (cls[:, 1:] == 0), fz, 0.0)
    for i in range(big_m):
        for j in range(n1 - 1):
            f = fz[i, j]
            if f > 0:
                transfer(cell(i, j), cell(i, j + 1), f, 0.0)
            elif f < 0:
                transfer(cell(i, j + 1), cell(i, j), -f, 0.0)

    carried = np.full((n_faces, n1), np.nan)  # east outflow of non-pressure cells
    for j in range(n1):
        row = cls[:, j]
        if periodic:
            starts = [i for i in range(big_m) if row[i] == 0]
            order_start = (starts[0] + 1) % big_m if starts else int(np.argmax(cap[:, j]))
            order = [(order_start + s) % big_m for s in range(big_m)]
            passes = 1 if starts else 4
        else:
            order = list(range(n_faces))
            passes = 1
        prev_vals = None
        for _ in range(passes):
            for i in order:
                c = row[i]
                if c in (1, 2):
                    w = (i - 1) % big_m if periodic else i - 1
                    if w < 0:
                        west = 0.0
                    elif cls[w, j] in (1, 2) and not np.isnan(carried[w, j]):
                        west = carried[w, j]
                    elif cls[w, j] in (1, 2):
                        west = cap[w, j]  # first pass around a ring of cavities
                    else:
                        west = max(ft[w, j], 0.0)
                    arrive[cell(i, j)] = west + axial_in(i, j)
                    carried[i, j] = min(arrive[cell(i, j)], cap[i, j])
            vals = carried[:, j].copy()
            if prev_vals is not None and np.allclose(vals, prev_vals, rtol=1e-14, atol=0):
                break
            prev_vals = vals
        # faces of this row
        for i in range(n_faces):
            a, b = cell(i, j), cell(nxt(i), j)
            ca, cb = row[i], row[nxt(i)]
            if ca in (1, 2):
                fc = carried[i, j]
                excess = arrive[a] - fc
                if ca == 2:
                    side[a] += excess
                else:
                    spill[a] += excess
                if cb == 0:  # reformation: the pressure cell draws its Reynolds flow
                    fss = ft[i, j]
                    take = min(fc, max(fss, 0.0))
                    transfer(a, b, take, take)
                    recirc[b] += take
                    recirc_from[a] += take
                    makeup[b] += max(fss, 0.0) - take
                    spill[a] += fc - take
                    if fss < 0:
                        transfer(b, a, -fss, -fss)
                        spill[a] += -fss
                else:
                    transfer(a, b, fc, fc)
            else:
                f = ft[i, j]
                if f >= 0:
                    transfer(a, b, f, cap[i, j])
                else:
                    transfer(b, a, -f, -cap[i, j])
        if not periodic:
            # leading column: closure with the groove; trailing column: outlet
            a = cell(0, j)
            f0 = ft[0, j]
            if f0 >= 0:
                inlet[a] += f0
                inlet_c[a] += cap[0, j]
            else:
                spill[a] += -f0
            b = cell(big_m - 1, j)
            w = big_m - 2
            cavity = cls[w, j] in (1, 2)
            fl = carried[w, j] if cavity else ft[w, j]
            if fl >= 0:
                outlet[b] += fl
                outlet_c[b] += fl if cavity else cap[w, j]
            else:
                makeup[b] += -fl

    up = np.array(ups, dtype=np.int64)
    down = np.array(downs, dtype=np.int64)
    flow = np.array(flows, dtype=float)
    # fill fraction of the cells without pressure: arriving flow / full-film Couette flow
    fill = np.ones(size)
    couette_cell = np.empty(shape)
    couette_cell[:] = (6.0 * abs(omega) * k / clearance) * hf * wz[None, :]
    nonp = (cls.ravel() == 1) | (cls.ravel() == 2)
    fill[nonp] = np.clip(arrive[nonp] / couette_cell.ravel()[nonp], 0.0, 1.0)
    wt = np.full(big_m, mesh.dth)
    if not periodic:
        wt[[0, -1]] *= 0.5
    area = (radius**2 * wt[:, None] * wz[None, :]).ravel()
    pf_flow = PadFlow(
        up,
        down,
        flow,
        inlet,
        makeup,
        recirc,
        recirc_from,
        outlet,
        side,
        spill,
        fill,
        area,
        periodic,
        shape,
        np.array(couettes, dtype=float),
        inlet_c,
        outlet_c,
    )
    return pf_flow, hf, (dpxf, dpzf), muf


def _zero_pressure(film: PadFilm) -> PadFilm:
    from dataclasses import replace

    return replace(film, pressure=np.zeros_like(film.pressure))


def _from_flow_coords(a: NDArray, reverse: bool, periodic: bool) -> NDArray:
    """(M, n+1) flow-coordinate node array → the pad's (m+1, n+1) node order."""
    if periodic:
        a = np.vstack([a, a[:1]])
    return a[::-1] if reverse else a


# ---------------------------------------------------------------------------------------------
# Energy balances
# ---------------------------------------------------------------------------------------------


@dataclass
class _PadState:
    """One pad's flows and sources at the current film (internal, flow coordinates)."""

    flow: PadFlow
    dissipation: NDArray  # W per cell (half bearing)
    reverse: bool
    film: NDArray  # film thickness per cell (m)
    speed: float = 0.0  # surface speed of the journal U (m/s)
    viscosity: NDArray | None = None  # per cell (Pa·s)
    poiseuille: tuple[NDArray, NDArray] | None = None  # mean Poiseuille velocities (m/s)
    # bulk quantities (whole bearing length)
    q_in: float = 0.0
    q_out: float = 0.0
    q_side: float = 0.0
    q_rec: float = 0.0
    q_make: float = 0.0
    power: float = 0.0


def _pad_state(ev: Any, k: int, film: PadFilm, u: NDArray) -> _PadState:
    b = ev.bearing
    q = ev.local_q(k, u)
    mesh = ev.meshes[k]
    flow, h, (dpx, dpz), mu = pad_flow(
        mesh, film, q, ev.speed, ev.viscosity[k], b.radius, b.clearance
    )
    u_s = abs(ev.speed) * b.radius
    phi = flow.fill * (mu * u_s**2 / h + h**3 * (dpx**2 + dpz**2) / (12.0 * mu)).ravel()
    # mean Poiseuille velocities −h² ∇p/(12μ) (x in the direction of rotation)
    vel = (-(h**2) * dpx / (12.0 * mu), -(h**2) * dpz / (12.0 * mu))
    st = _PadState(
        flow,
        phi * flow.area,
        ev.speed < 0,
        h.ravel(),
        u_s,
        np.asarray(mu, dtype=float).ravel(),
        (vel[0].ravel(), vel[1].ravel()),
    )
    st.q_side = 2.0 * float(flow.side.sum())
    st.q_make = 2.0 * float(flow.makeup.sum())
    st.power = 2.0 * float(st.dissipation.sum())
    if flow.periodic:
        st.q_rec = 2.0 * float(flow.recirculated.sum())
        st.q_in = st.q_rec + st.q_make
        st.q_out = st.q_rec + 2.0 * float(flow.spill.sum())
    else:
        st.q_in = 2.0 * float(flow.inlet.sum()) + st.q_make
        st.q_out = 2.0 * float((flow.outlet + flow.spill).sum())
    return st


def _upstream(ev: Any) -> list[int]:
    """Index of the pad upstream of each pad (in the direction of rotation)."""
    pads = ev.bearing.pads
    starts = [p.start % (2 * math.pi) for p in pads]
    order = sorted(range(len(pads)), key=lambda k: starts[k])
    up = [0] * len(pads)
    for pos, k in enumerate(order):
        up[k] = order[pos - 1] if ev.speed > 0 else order[(pos + 1) % len(order)]
    return up


def _mixing(states: list[_PadState], up: list[int], lam: float) -> tuple[NDArray, NDArray]:
    """Per pad: the carried fraction c_k of its inflow and the carried flow (m³/s)."""
    c = np.zeros(len(states))
    carried = np.zeros(len(states))
    for k, st in enumerate(states):
        if st.flow.periodic:
            carried[k] = st.q_rec
        else:
            carried[k] = min(lam * states[up[k]].q_out, max(st.q_in, 0.0))
        c[k] = carried[k] / st.q_in if st.q_in > 0 else 0.0
    return c, carried


def _inlet_temperatures(
    c: NDArray, up: list[int], a: NDArray, b: NDArray, t_s: float, periodic: list[bool]
) -> NDArray:
    """Solve T_in,k = c_k T_out,up(k) + (1 − c_k) T_s with T_out,k = a_k + b_k T_in,k (linear;
    a 360° film mixes inside its own energy balance, its T_in is not used)."""
    n = len(c)
    mat = np.eye(n)
    rhs = np.zeros(n)
    for k in range(n):
        if periodic[k]:
            rhs[k] = t_s
            continue
        mat[k, up[k]] -= c[k] * b[up[k]]
        rhs[k] = c[k] * a[up[k]] + (1.0 - c[k]) * t_s
    return np.linalg.solve(mat, rhs)


def _no_flow(k: int) -> SolverError:
    return SolverError(
        f"thermal model: no oil flows through pad {k + 1} to carry its heat away (no inflow, "
        "or all of it leaves at once); the adiabatic energy balance has no solution"
    )


def _effective_step(
    model: ThermalModel, states: list[_PadState], up: list[int], rho_c: float
) -> tuple[NDArray, list[dict]]:
    """Bulk energy balance of every pad: new effective temperatures and pad outputs."""
    n = len(states)
    dt = np.zeros(n)
    for k, st in enumerate(states):
        den = st.q_out + 0.5 * st.q_side
        if not den > 0:
            raise _no_flow(k)
        dt[k] = st.power / (rho_c * den)
    c, carried = _mixing(states, up, model.carry_over)
    periodic = [st.flow.periodic for st in states]
    t_s = model.supply_temperature
    # T_out = T_in + ΔT; a 360° film mixes its own outlet with the make-up: solve it alone
    t_in = _inlet_temperatures(c, up, dt, np.ones(n), t_s, periodic)
    for k in range(n):
        if periodic[k]:
            if not c[k] < 1.0:
                raise _no_flow(k)
            t_in[k] = t_s + c[k] / (1.0 - c[k]) * dt[k]
    t_out = t_in + dt
    t_eff = t_in + model.effective_factor * dt
    out = []
    for k, st in enumerate(states):
        heat = rho_c * (
            st.q_out * t_out[k] + st.q_side * 0.5 * (t_in[k] + t_out[k]) - st.q_in * t_in[k]
        )
        out.append(
            dict(
                inlet_temperature=float(t_in[k]),
                outlet_temperature=float(t_out[k]),
                max_temperature=float(t_out[k]),
                film_temperature=float(t_eff[k]),
                power_loss=st.power,
                inlet_flow=st.q_in,
                outlet_flow=st.q_out,
                side_flow=st.q_side,
                carried_flow=float(carried[k]),
                supply_flow=st.q_in - float(carried[k]),
                heat_conducted=0.0,
                heat_carried=float(heat),
            )
        )
    return t_eff, out


def _layers(n: int) -> tuple[NDArray, NDArray, NDArray, NDArray, NDArray]:
    """The film's n levels (equal layers in η = y/h, y from the journal): per layer the share of
    a unit Couette flow (velocity ∝ 1 − η) and of a unit Poiseuille flow (∝ η(1 − η)) it
    carries, and the integrals ∫dη, ∫(1 − 2η)dη, ∫(1 − 2η)²dη of the dissipation."""
    e = np.linspace(0.0, 1.0, n + 1)
    a, b = e[:-1], e[1:]
    couette = 2.0 * (b - a) - (b**2 - a**2)
    poiseuille = 3.0 * (b**2 - a**2) - 2.0 * (b**3 - a**3)
    i1 = (b - a) - (b**2 - a**2)
    i2 = ((1.0 - 2.0 * a) ** 3 - (1.0 - 2.0 * b) ** 3) / 6.0
    return couette, poiseuille, b - a, i1, i2


def _shares(total: NDArray, couette: NDArray, c_l: NDArray, p_l: NDArray, clip: bool) -> NDArray:
    """Flows (…) with Couette part ``couette`` split over the layers: (…, n). ``clip``: a flow
    into or out of the film is taken one-way, its reversed layers (a Poiseuille back-flow at a
    pad's edge) set to zero and the rest scaled to the total."""
    out = couette[:, None] * c_l[None, :] + (total - couette)[:, None] * p_l[None, :]
    if clip:
        out = np.clip(out, 0.0, None)
        s = out.sum(axis=1)
        ok = s > 0
        out[ok] *= (total[ok] / s[ok])[:, None]
        out[~ok] = total[~ok, None] * c_l[None, :]
    return out


@dataclass
class _PadSolve:
    """One pad's energy balance across the film (flow coordinates; (cells, layers) arrays):
    its temperatures are ``t0 + T_in t1 + T_j t2``."""

    t0: NDArray
    t1: NDArray
    t2: NDArray
    drain: NDArray  # outflow at the trailing edge and out of cavities, per (cell, layer)
    side: NDArray
    inlet: NDArray  # inflow at T_in per (cell, layer) (inlet, and a pad's make-up)
    makeup_s: NDArray  # inflow at the supply temperature (a 360° film's make-up)
    leave: NDArray  # what leaves a 360° film's pressure zone, or the drain
    g_j: NDArray  # conductance to the journal body (W/K per cell)
    g_p: NDArray  # conductance to the oil behind the pad (W/K per cell)
    r_p: NDArray  # the pad-side half layer's resistance × the wetted area (m²K/W)

    def field(self, t_in: float, t_j: float) -> NDArray:
        return self.t0 + t_in * self.t1 + t_j * self.t2


def _pad_energy(model: ThermalModel, st: _PadState, rho_c: float, layers: tuple) -> _PadSolve:
    """The steady energy equation of one pad resolved across the film (module docstring): the
    pad's control volumes split into ``n`` layers; in-plane convection by each layer's share of
    the flows (upwind), the flow between layers that closes every layer's mass balance
    (upwind), conduction between layers and through the half layers to the walls, the
    dissipation of each layer's shear. An M-matrix: no temperature below the lowest of the
    inlet, supply and journal temperatures (maximum principle). One sparse LU, three
    right-hand sides (sources; unit inlet temperature; unit journal temperature)."""
    f = st.flow
    c_l, p_l, w_l, i1, i2 = layers
    n = len(c_l)
    size = f.fill.size
    t_s = model.supply_temperature
    k = model.lubricant.thermal_conductivity
    a_p, a_j = model.pad_heat_transfer, model.journal_heat_transfer
    idx = np.arange(size * n).reshape(size, n)
    # in-plane transfers, layer by layer (a reversed layer flows the other way)
    lt = _shares(f.flow, f.couette, c_l, p_l, clip=False)
    fwd = lt > 0
    src_u = np.where(fwd, idx[f.up], idx[f.down])
    dst_u = np.where(fwd, idx[f.down], idx[f.up])
    mag = np.abs(lt)
    src_u, dst_u, mag = src_u.ravel(), dst_u.ravel(), mag.ravel()
    # flows into and out of the film
    inlet = _shares(f.inlet, f.inlet_couette, c_l, p_l, clip=True)
    makeup = f.makeup[:, None] * c_l[None, :]
    drain = _shares(f.outlet, f.outlet_couette, c_l, p_l, clip=True) + f.spill[:, None] * c_l
    side = f.side[:, None] * p_l[None, :]
    ext_in = inlet + makeup
    ext_out = drain + side
    # the flow between layers that balances every layer: w[:, l] from layer l to l + 1
    net_out = (
        np.bincount(src_u, mag, size * n).reshape(size, n)
        - np.bincount(dst_u, mag, size * n).reshape(size, n)
        + ext_out
        - ext_in
    )
    w = -np.cumsum(net_out, axis=1)[:, :-1]
    up_v = np.where(w > 0, idx[:, :-1], idx[:, 1:]).ravel()
    dn_v = np.where(w > 0, idx[:, 1:], idx[:, :-1]).ravel()
    w_mag = np.abs(w).ravel()
    # conduction: between layers (h/n apart) and through the half layers to the walls
    wet = f.fill * f.area
    dy = st.film / n
    g_layer = np.repeat(k * wet / dy, n - 1)
    lo, hi = idx[:, :-1].ravel(), idx[:, 1:].ravel()
    r_half = dy / (2.0 * k)
    g_j = wet / (r_half + 1.0 / a_j) if a_j > 0 else np.zeros(size)
    g_p = wet / (r_half + 1.0 / a_p) if a_p > 0 else np.zeros(size)
    # outflow of every unknown (convective, W/K) and the conductances on the diagonal
    out_u = np.bincount(src_u, mag, size * n) + np.bincount(up_v, w_mag, size * n) + ext_out.ravel()
    diag = rho_c * out_u
    diag += np.bincount(lo, g_layer, size * n) + np.bincount(hi, g_layer, size * n)
    diag[idx[:, 0]] += g_j
    diag[idx[:, -1]] += g_p
    if not np.all(diag > 0):
        raise _no_flow(0)
    rows = np.concatenate([np.arange(size * n), dst_u, dn_v, lo, hi])
    cols = np.concatenate([np.arange(size * n), src_u, up_v, hi, lo])
    vals = np.concatenate([diag, -rho_c * mag, -rho_c * w_mag, -g_layer, -g_layer])
    mat = sp.csc_matrix((vals, (rows, cols)), shape=(size * n, size * n))
    try:
        lu = splu(mat)
    except RuntimeError:
        raise _no_flow(0) from None
    # dissipation of each layer: (μ/h) ∫ (∂u/∂η)² + (∂w/∂η)² dη, u = U(1 − η) + 6ū η(1 − η)
    ub, wb = st.poiseuille
    mu_h = f.fill * st.viscosity / st.film * f.area
    phi = mu_h[:, None] * (
        st.speed**2 * w_l[None, :]
        - 12.0 * (st.speed * ub)[:, None] * i1[None, :]
        + 36.0 * (ub**2 + wb**2)[:, None] * i2[None, :]
    )
    src = phi.copy()
    src[:, -1] += g_p * t_s
    rhs_s = np.zeros((size, n))
    rhs_in = rho_c * inlet
    if f.periodic:
        src += rho_c * makeup * t_s
        rhs_s = rho_c * makeup
    else:
        rhs_in = rhs_in + rho_c * makeup
    rhs_j = np.zeros((size, n))
    rhs_j[:, 0] = g_j
    sol = lu.solve(np.column_stack([src.ravel(), rhs_in.ravel(), rhs_j.ravel()]))
    t0, t1, t2 = (sol[:, i].reshape(size, n) for i in range(3))
    leave = drain + f.recirculated_from[:, None] * c_l[None, :] if f.periodic else drain
    return _PadSolve(
        t0,
        t1,
        t2,
        drain,
        side,
        inlet if f.periodic else inlet + makeup,
        rhs_s / rho_c,
        leave,
        g_j,
        g_p,
        r_half / np.where(wet > 0, wet, 1.0),
    )


def _thd_step(
    model: ThermalModel,
    states: list[_PadState],
    up: list[int],
    rho_c: float,
    t_journal: float | None,
) -> tuple[list[NDArray], list[dict], float]:
    """The energy equation of every pad across the film (:func:`_pad_energy`) with the inlet
    mixing and the journal: returns the film temperature fields (the mean across the film,
    flow coordinates, flattened), the pad outputs, and the journal temperature (given, or the
    one at which the journal takes no net heat, solved exactly: every field is affine in the
    inlet and journal temperatures; NaN without heat to the journal)."""
    t_s = model.supply_temperature
    layers = _layers(model.cross_film_layers)
    n = len(states)
    sols = []
    for k, st in enumerate(states):
        try:
            sols.append(_pad_energy(model, st, rho_c, layers))
        except SolverError:
            raise _no_flow(k) from None
    periodic = [st.flow.periodic for st in states]
    c, carried = _mixing(states, up, model.carry_over)

    def inlets(t_j: float) -> NDArray:
        # T_out,k = a_k + b_k T_in,k (at this journal temperature)
        a = np.zeros(n)
        b = np.zeros(n)
        for k, s in enumerate(sols):
            q_d = float(s.drain.sum())
            if not q_d > 0 and not periodic[k]:
                raise _no_flow(k)
            if q_d > 0:
                a[k] = float((s.drain * (s.t0 + t_j * s.t2)).sum()) / q_d
                b[k] = float((s.drain * s.t1).sum()) / q_d
        return _inlet_temperatures(c, up, a, b, t_s, periodic)

    has_journal = model.journal_heat_transfer > 0
    if t_journal is None and has_journal:
        # zero net heat into the journal: Σ g_j (T_0 − T_j) = 0, affine in T_j
        def journal_heat(t_j: float) -> float:
            t_in = inlets(t_j)
            return sum(
                float(s.g_j @ (s.field(t_in[k], t_j)[:, 0] - t_j)) for k, s in enumerate(sols)
            )

        h0, h1 = journal_heat(t_s), journal_heat(t_s + 1.0)
        t_j = t_s - h0 / (h1 - h0)
    else:
        t_j = t_s if t_journal is None else t_journal
    t_in = inlets(t_j)
    fields, outs = [], []
    for k, (st, s) in enumerate(zip(states, sols, strict=True)):
        f = st.flow
        temp3 = s.field(t_in[k], t_j)
        q_l = float(s.leave.sum())
        t_out = float((s.leave * temp3).sum()) / q_l if q_l > 0 else float("nan")
        heat = (
            2.0
            * rho_c
            * float(
                ((s.drain + s.side) * temp3).sum()
                - s.inlet.sum() * t_in[k]
                - s.makeup_s.sum() * t_s
            )
        )
        q_j = s.g_j * (temp3[:, 0] - t_j)
        q_p = s.g_p * (temp3[:, -1] - t_s)
        cond = 2.0 * float(q_j.sum() + q_p.sum())
        if f.periodic:
            t_inlet = (st.q_rec * t_out + st.q_make * t_s) / st.q_in if st.q_in > 0 else t_s
        else:
            t_inlet = float(t_in[k])
        # the pad surface: past the pad-side half layer (its centre's in an adiabatic pad)
        surface = temp3[:, -1] - q_p * s.r_p
        mean = temp3.mean(axis=1)
        fields.append(mean)
        outs.append(
            dict(
                surface=surface,
                layers=temp3,
                inlet_temperature=float(t_inlet),
                outlet_temperature=t_out,
                max_temperature=float(surface.max()),
                film_temperature=float(f.area @ mean / f.area.sum()),
                power_loss=st.power,
                inlet_flow=st.q_in,
                outlet_flow=st.q_out,
                side_flow=st.q_side,
                carried_flow=float(carried[k]),
                supply_flow=st.q_make if f.periodic else st.q_in - float(carried[k]),
                heat_conducted=cond,
                heat_carried=heat,
            )
        )
    return fields, outs, (t_j if has_journal or t_journal is not None else float("nan"))


# ---------------------------------------------------------------------------------------------
# The film–temperature iteration
# ---------------------------------------------------------------------------------------------

#: solve(u_start or None) → (u, BearingFilm, Newton iterations, status)
Solve = Callable[[NDArray | None], tuple[NDArray, Any, int, str]]


def _field_change(new: list[NDArray], old: list[NDArray], pressure: list[NDArray]) -> float:
    """How far the THD iteration is from its fixed point (K): the largest change of a pad's mean
    film temperature, and of a node's temperature weighted by its pressure / the bearing's peak
    pressure. (A node at the edge of a cavity may switch between cavitated and pressurised from
    one iteration to the next, and the oil it receives with it; it carries no pressure, so it
    does not move the film, and is not asked to settle.)"""
    p_max = max(float(np.max(p)) for p in pressure)
    out = 0.0
    for a, b, p in zip(new, old, pressure, strict=True):
        out = max(out, abs(float(np.mean(a)) - float(np.mean(b))))
        if p_max > 0:
            out = max(out, float(np.max(np.abs(a - b) * np.clip(p, 0.0, None) / p_max)))
    return out


def _pad_shape(mesh: Any) -> tuple[int, int]:
    return (len(mesh.theta), len(mesh.zeta))


def solve_thermal(
    ev: Any, solve: Solve, model: ThermalModel, start: ThermalResult | None = None
) -> tuple[NDArray, Any, int, str, ThermalResult]:
    """Iterate film and temperatures to a consistent state (module docstring).

    ``ev`` is the bearing's film evaluator (its ``viscosity`` per pad is set here), ``solve``
    the equilibrium solver at the evaluator's current viscosities. ``start``: a previous
    thermal state of the same bearing and grid to start from. Returns the equilibrium state
    (u, film, Newton iterations summed, status) and the :class:`ThermalResult`.
    """
    lub = model.lubricant
    t_s = model.supply_temperature
    n_pads = len(ev.bearing.pads)
    up = _upstream(ev)
    thd = model.model == "thd"
    shapes = [_pad_shape(m) for m in ev.meshes]
    if start is not None and start.model == model.model and len(start.pads) == n_pads:
        temps = (
            [np.array(p.temperature) for p in start.pads]
            if thd
            else [p.film_temperature for p in start.pads]
        )
        if thd and any(t.shape != s for t, s in zip(temps, shapes, strict=True)):
            temps = None
    else:
        temps = None
    if temps is None:
        temps = [np.full(s, t_s) for s in shapes] if thd else [t_s] * n_pads
    auto_journal = model.journal_temperature is None and model.journal_heat_transfer > 0
    t_j_prev = math.nan
    u = None
    newton = 0
    status = "converged"
    lo, hi = lub.pour_point, lub.max_temperature
    change = math.inf
    iterations = 0
    relax, history, since = model.relaxation, [], 0
    for iterations in range(1, model.max_iter + 1):  # noqa: B007 (reported below)
        ev.viscosity = [
            lub.viscosity(np.clip(t, lo, hi)) if thd else float(lub.viscosity(min(max(t, lo), hi)))
            for t in temps
        ]
        u, film, n_it, status = solve(u)
        newton += n_it
        states = [_pad_state(ev, k, film.pads[k], u) for k in range(n_pads)]
        t_mean = float(np.mean([np.mean(t) for t in temps]))
        rho_c = float(lub.density_at(t_mean) * lub.specific_heat_at(t_mean))
        if thd:
            flat, outs, t_j = _thd_step(model, states, up, rho_c, model.journal_temperature)
            new = [
                _from_flow_coords(f.reshape(st.flow.shape), st.reverse, st.flow.periodic)
                for f, st in zip(flat, states, strict=True)
            ]
            change = _field_change(new, temps, [f.pressure for f in film.pads])
            if auto_journal:
                # the journal (solved within every balance) settles with the film
                change = max(change, abs(t_j - t_j_prev)) if math.isfinite(t_j_prev) else math.inf
                t_j_prev = t_j
        else:
            t_eff, outs = _effective_step(model, states, up, rho_c)
            new = [float(t) for t in t_eff]
            change = max(abs(a - b) for a, b in zip(new, temps, strict=True))
        if change <= model.tol:
            break
        history.append(change)
        # stalled (a cavity edge switching back and forth): relax harder
        if len(history) >= since + 4 and change > 0.8 * min(history[-5:-1]):
            relax, since = max(0.5 * relax, 0.05), len(history)
        temps = [t + relax * (nw - t) for t, nw in zip(temps, new, strict=True)]
    else:
        raise SolverError(
            f"thermal iteration ({model.model}) did not converge: the temperatures still "
            f"changed by {change:.3g} K after {model.max_iter} iterations (tolerance "
            f"{model.tol:g} K); raise max_iterations or the tolerance"
        )
    t_max = max(o["max_temperature"] for o in outs)
    if t_max > hi:
        raise SolverError(
            f"the film reaches {t_max - CELSIUS:.4g} degC, above the lubricant's maximum "
            f"temperature {hi - CELSIUS:.4g} degC ({lub.name or 'lubricant'}): the bearing "
            "overheats at this load and speed"
        )
    surfaces = [
        _from_flow_coords(o.pop("surface").reshape(st.flow.shape), st.reverse, st.flow.periodic)
        if thd
        else None
        for o, st in zip(outs, states, strict=True)
    ]
    layered = [
        _from_flow_coords(o.pop("layers").reshape(*st.flow.shape, -1), st.reverse, st.flow.periodic)
        if thd
        else None
        for o, st in zip(outs, states, strict=True)
    ]
    pads = tuple(
        PadThermal(
            **o,
            temperature=new[k] if thd else None,
            viscosity=ev.viscosity[k],
            surface_temperature=surfaces[k],
            layer_temperature=layered[k],
        )
        for k, o in enumerate(outs)
    )
    result = ThermalResult(
        model=model.model,
        supply_temperature=t_s,
        pads=pads,
        journal_temperature=float(t_j) if thd else float("nan"),
        iterations=iterations,
        rho_c=rho_c,
    )
    return u, film, newton, status, result
