"""The fluids of the seal models: an ideal gas, a real gas through CoolProp, a liquid.

The seal models need, along a seal at its inlet temperature, the density ρ(P), its isothermal
derivative ∂ρ/∂P|_T (the bulk flow is isothermal: Childs & Scharrer 1986 for labyrinths,
Kleynhans & Childs' ISOTSEAL for damper seals), the isentropic derivative 1/a² (the gas stored
in the cells of a damper seal is compressed faster than heat crosses a cell), the viscosity and
the ratio of specific heats γ at the inlet. SI units throughout.

``RealGas`` tabulates the properties of a CoolProp (HEOS) mixture once, at the inlet temperature
over the seal's pressure range, and interpolates in log P; CoolProp is an optional dependency
(``pip install "gearrotor[seals]"``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from ..errors import ModelError

__all__ = ["R_UNIVERSAL", "Fluid", "IdealGas", "RealGas", "Liquid", "coolprop_available"]

#: Universal gas constant, J/(kmol K) (CODATA 2018).
R_UNIVERSAL = 8314.462618


class Fluid:
    """What a seal model asks of its fluid (all at the seal's inlet temperature)."""

    compressible = True

    def density(self, p):  # pragma: no cover - interface
        raise NotImplementedError

    def drho_dp(self, p):  # pragma: no cover - interface
        """∂ρ/∂P at constant temperature, s²/m²."""
        raise NotImplementedError

    def drho_dp_isentropic(self, p):  # pragma: no cover - interface
        """∂ρ/∂P at constant entropy, 1/a², s²/m²."""
        raise NotImplementedError

    def viscosity(self, p):  # pragma: no cover - interface
        raise NotImplementedError

    def pv(self, p):
        """P/ρ (= Z R T for a gas), J/kg."""
        return p / self.density(p)

    def props(self, p: float) -> tuple[float, float, float]:
        """(ρ, ∂ρ/∂P|_T, μ) at one pressure, as floats (the marching solvers' inner loop)."""
        return float(self.density(p)), float(self.drho_dp(p)), float(self.viscosity(p))


@dataclass(frozen=True)
class IdealGas(Fluid):
    """Ideal gas of molar mass ``molar_mass`` (kg/kmol), ratio of specific heats ``gamma``,
    constant dynamic viscosity ``mu`` (Pa·s), at temperature ``temperature`` (K)."""

    molar_mass: float
    gamma: float
    mu: float
    temperature: float

    @property
    def R(self) -> float:
        """Specific gas constant, J/(kg K)."""
        return R_UNIVERSAL / self.molar_mass

    def density(self, p):
        return p / (self.R * self.temperature)

    def drho_dp(self, p):
        return np.ones_like(np.asarray(p, float)) / (self.R * self.temperature)

    def drho_dp_isentropic(self, p):
        return np.ones_like(np.asarray(p, float)) / (self.gamma * self.R * self.temperature)

    def viscosity(self, p):
        return np.full_like(np.asarray(p, float), self.mu)

    def pv(self, p):
        return np.full_like(np.asarray(p, float), self.R * self.temperature)

    def props(self, p: float) -> tuple[float, float, float]:
        rt = self.R * self.temperature
        return p / rt, 1.0 / rt, self.mu


@dataclass(frozen=True)
class Liquid(Fluid):
    """Incompressible liquid: ``rho`` (kg/m³) and dynamic viscosity ``mu`` (Pa·s)."""

    rho: float
    mu: float
    compressible = False
    gamma = math.inf
    temperature = math.nan

    def density(self, p):
        return np.full_like(np.asarray(p, float), self.rho)

    def drho_dp(self, p):
        return np.zeros_like(np.asarray(p, float))

    def drho_dp_isentropic(self, p):
        return np.zeros_like(np.asarray(p, float))

    def viscosity(self, p):
        return np.full_like(np.asarray(p, float), self.mu)

    def props(self, p: float) -> tuple[float, float, float]:
        return self.rho, 0.0, self.mu


def coolprop_available() -> bool:
    """Whether CoolProp can be imported (the ``seals`` extra)."""
    try:
        import CoolProp  # noqa: F401
    except ImportError:
        return False
    return True


@dataclass(frozen=True)
class RealGas(Fluid):
    """A gas mixture through CoolProp's HEOS backend, tabulated at ``temperature`` (K) between
    ``p_min`` and ``p_max`` (Pa). ``composition`` maps CoolProp fluid names to mole fractions
    (normalised to a sum of 1). ``mu`` (Pa·s), when given, replaces CoolProp's viscosity (which
    some mixtures lack)."""

    composition: tuple[tuple[str, float], ...]
    temperature: float
    p_min: float
    p_max: float
    mu: float | None = None
    n_points: int = 40
    _table: dict = field(default_factory=dict, compare=False, repr=False)

    def __post_init__(self) -> None:
        try:
            import CoolProp.CoolProp as CP
        except ImportError:
            raise ModelError(
                "a gas composition needs CoolProp, which is not installed",
                field="gas.composition",
                expected='pip install "gearrotor[seals]", or the ideal gas: [gas] molar_mass, '
                "gamma and viscosity",
            ) from None
        names = [n for n, _ in self.composition]
        x = np.array([f for _, f in self.composition], float)
        try:
            st = CP.AbstractState("HEOS", "&".join(names))
        except ValueError as exc:
            known = set(CP.get_global_param_string("FluidsList").split(","))
            bad = [n for n in names if n not in known]
            raise ModelError(
                "unknown fluid in the gas composition"
                if bad
                else f"CoolProp cannot mix these fluids: {str(exc).splitlines()[0][:100]}",
                field="gas.composition",
                value=bad or names,
                expected="CoolProp fluid names such as Nitrogen, Oxygen, Argon, CarbonDioxide, "
                "Methane, Ethane, Hydrogen, Water",
            ) from None
        if len(names) > 1:
            st.set_mole_fractions(list(x / x.sum()))
        p = np.geomspace(self.p_min, self.p_max, self.n_points)
        # the phase at both ends by a full flash (an isotherm whose ends are gas is gas
        # throughout); the table then skips the phase analysis (a hundred times faster)
        phase = None
        for pk in (self.p_min, self.p_max):
            self._flash(CP, st, pk)
            phase = st.phase()
            if phase in (CP.iphase_liquid, CP.iphase_twophase):
                raise ModelError(
                    "the gas is not a gas at the seal's conditions (CoolProp: liquid or two-phase)",
                    field="gas.composition",
                    value=f"{pk:.6g} Pa, {self.temperature:.6g} K",
                    expected="a single-phase gas or supercritical fluid",
                )
        gamma = st.cpmass() / st.cvmass()  # at the inlet pressure
        st.specify_phase(phase)
        rho, drho, drho_s, mu = (np.empty_like(p) for _ in range(4))
        for k, pk in enumerate(p):
            self._flash(CP, st, pk)
            rho[k] = st.rhomass()
            drho[k] = st.first_partial_deriv(CP.iDmass, CP.iP, CP.iT)
            drho_s[k] = 1.0 / st.speed_sound() ** 2
            if self.mu is None:
                try:
                    mu[k] = st.viscosity()
                except ValueError as exc:
                    raise ModelError(
                        "CoolProp has no viscosity model for this gas: "
                        f"{str(exc).splitlines()[0][:80]}",
                        field="gas.viscosity",
                        expected="[gas] viscosity given with the composition",
                    ) from None
        object.__setattr__(self, "gamma", float(gamma))
        self._table.update(
            logp=np.log(p), rho=rho, drho=drho, drho_s=drho_s, mu=mu if self.mu is None else None
        )

    def _flash(self, CP, st, p: float) -> None:
        try:
            st.update(CP.PT_INPUTS, float(p), self.temperature)
        except ValueError as exc:
            raise ModelError(
                f"CoolProp cannot evaluate the gas at {p:.6g} Pa, {self.temperature:.6g} K: "
                f"{str(exc).splitlines()[0][:100]}",
                field="gas.composition",
                expected="a single-phase gas over the seal's pressure range",
            ) from None

    def _interp(self, name: str, p) -> NDArray:
        t = self._table
        return np.interp(np.log(np.clip(p, self.p_min, self.p_max)), t["logp"], t[name])

    def density(self, p):
        return self._interp("rho", p)

    def drho_dp(self, p):
        return self._interp("drho", p)

    def drho_dp_isentropic(self, p):
        return self._interp("drho_s", p)

    def viscosity(self, p):
        if self.mu is not None:
            return np.full_like(np.asarray(p, float), self.mu)
        return self._interp("mu", p)
