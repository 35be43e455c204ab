"""Timoshenko shaft element: 2 nodes, 6 DOFs per node.

Local DOF order (the global order of every node): ``x, y, z, θx, θy, θz`` of node 1, then of node 2.

Sign conventions (right-handed frame, shaft along +z):

* bending in the x-z plane uses ``x`` and ``θy`` with ``θy = +dx/dz``;
* bending in the y-z plane uses ``y`` and ``θx`` with ``θx = -dy/dz``.

Both planes share one plane-beam formulation with DOFs ``(w1, φ1, w2, φ2)`` and ``φ = dw/dz``
(Przemieniecki / Nelson 1980 / Friswell et al. 2010, ch. 5). The element matrices are derived
by Gauss quadrature of the Timoshenko interpolation functions (in which the shear strain is constant
along the element), not transcribed: stiffness ``∫EI ψ'ᵀψ' + κGA γᵀγ``, translational mass
``∫ρA NᵀN``, rotary inertia ``∫ρI N_ψᵀN_ψ`` and the gyroscopic matrix ``∫ρIp (θxᵀθy − θyᵀθx)``.
The axial bar and the torsional rod use linear shape functions (consistent mass).

Material damping is Rayleigh damping ``C = α M + β K`` of the element. When it rotates with the
shaft (internal damping), the bending part C_b acts on the velocities seen in the frame spinning
at Ω: with the complex plane coordinates ``p = p_x + i p_y`` (``p_x = (x, θy, ...)``,
``p_y = (y, −θx, ...)``, the plane-beam DOFs of the two planes), the rotating-frame velocity is
``(ṗ − iΩp) e^{−iΩt}``, so the fixed-frame force is ``−C_b (ṗ − iΩ p)``: the damping C plus the
circulatory stiffness ``Ω Kc`` with ``Kc p = C_b (p_y, −p_x)`` (skew), see :meth:`ShaftElement.Kc`.

Convergence: the stiffness is exact for a uniform element; frequencies converge as h⁴ while
elements are slender (Φ ≪ 1) and as h² once elements are shorter than about the diameter
(Φ ≳ 1), where the interpolation tends to linear displacements (see tests/test_shaft_element.py).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np
from numpy.typing import NDArray

__all__ = ["ShaftElement", "shear_coefficient"]

# DOF indices inside one node
X, Y, Z, TX, TY, TZ = range(6)
#: the plane-beam DOFs (w, ψ at both nodes) of the x-z plane (x, θy) and the y-z plane (y, θx),
#: and the sign change T = diag(1, −1, 1, −1) between them (θx = −ψ in the y-z plane)
_IX = [X, TY, 6 + X, 6 + TY]
_IY = [Y, TX, 6 + Y, 6 + TX]
_T = np.diag([1.0, -1.0, 1.0, -1.0])

# Gauss-Legendre rule on [0, 1]: 4 points integrate the degree-6 products of cubics exactly.
_GP, _GW = np.polynomial.legendre.leggauss(4)
_XI = 0.5 * (_GP + 1.0)
_WXI = 0.5 * _GW


def shear_coefficient(
    inner_diameter: float, outer_diameter: float, poisson: float, method: str = "hutchinson"
) -> float:
    """Shear coefficient κ of a (hollow) circular section.

    ``"hutchinson"`` is Hutchinson's (2001) result as used by Friswell et al. (2010), ``"cowper"``
    Cowper's (1966). ``m = inner/outer`` diameter ratio.
    """
    m2 = (inner_diameter / outer_diameter) ** 2
    nu = poisson
    if method == "hutchinson":
        a = (1.0 + m2) ** 2
        return (
            6.0
            * a
            * (1.0 + nu) ** 2
            / (a * (7.0 + 12.0 * nu + 4.0 * nu**2) + 4.0 * m2 * (5.0 + 6.0 * nu + 2.0 * nu**2))
        )
    if method == "cowper":
        a = (1.0 + m2) ** 2
        return 6.0 * a * (1.0 + nu) / (a * (7.0 + 6.0 * nu) + m2 * (20.0 + 12.0 * nu))
    raise ValueError(
        f"unknown shear coefficient method {method!r}; expected 'hutchinson' or 'cowper'"
    )


def _plane_shape(phi: float, length: float, xi: float) -> tuple[NDArray, NDArray, NDArray]:
    """Timoshenko interpolation at ``xi = z/L``: (N_w, N_ψ, dN_ψ/dz), each of length 4."""
    L = length
    d = 1.0 + phi
    nw = (
        np.array(
            [
                1.0 - 3 * xi**2 + 2 * xi**3 + phi * (1 - xi),
                L * (xi - 2 * xi**2 + xi**3 + 0.5 * phi * (xi - xi**2)),
                3 * xi**2 - 2 * xi**3 + phi * xi,
                L * (-(xi**2) + xi**3 + 0.5 * phi * (xi**2 - xi)),
            ]
        )
        / d
    )
    npsi = (
        np.array(
            [
                6.0 / L * (xi**2 - xi),
                1.0 - 4 * xi + 3 * xi**2 + phi * (1 - xi),
                6.0 / L * (xi - xi**2),
                -2 * xi + 3 * xi**2 + phi * xi,
            ]
        )
        / d
    )
    dnpsi = (
        np.array(
            [
                6.0 / L**2 * (2 * xi - 1),
                (-4 + 6 * xi - phi) / L,
                6.0 / L**2 * (1 - 2 * xi),
                (-2 + 6 * xi + phi) / L,
            ]
        )
        / d
    )
    return nw, npsi, dnpsi


@dataclass(frozen=True)
class ShaftElement:
    """A uniform hollow or solid circular Timoshenko shaft element.

    Parameters (SI)
    ----------
    length : m
    outer_diameter, inner_diameter : m, structural section
    E : Pa, Young's modulus;  shear_modulus : Pa;  density : kg/m³
    mass_outer_diameter, mass_inner_diameter : m, section used for inertia (non-structural
        mass such as a shrunk-on sleeve); default: the structural section
    shear_method : ``"hutchinson"`` or ``"cowper"``; ``shear=False`` gives Euler–Bernoulli (Φ = 0)
    alpha : 1/s, beta : s, material damping ``C = α M + β K``; ``rotating_damping`` makes it
        act in the spinning frame (adds the circulatory stiffness :meth:`Kc`)
    torsional_stiffness : N·m/rad, polar_mass : kg·m², torsional_damping : N·m·s/rad — the
        torsional rod given directly (this element's: stiffness k, polar inertia J spread as
        the consistent rod mass J/6 [[2, 1], [1, 2]], a dashpot c between its nodes) instead of
        GJ/L and ρ J_p L; the bending, axial and gyroscopic parts keep the diameters
    """

    length: float
    outer_diameter: float
    inner_diameter: float
    E: float
    shear_modulus: float
    density: float
    mass_outer_diameter: float | None = None
    mass_inner_diameter: float | None = None
    shear_method: str = "hutchinson"
    shear: bool = True
    rotary_inertia: bool = True
    alpha: float = 0.0
    beta: float = 0.0
    rotating_damping: bool = False
    torsional_stiffness: float | None = None
    polar_mass: float | None = None
    torsional_damping: float | None = None

    # --- section properties -------------------------------------------------------------
    @property
    def area(self) -> float:
        return np.pi / 4 * (self.outer_diameter**2 - self.inner_diameter**2)

    @property
    def inertia(self) -> float:
        """Diametral second moment of area I (m⁴)."""
        return np.pi / 64 * (self.outer_diameter**4 - self.inner_diameter**4)

    def _mass_section(self) -> tuple[float, float]:
        do = (
            self.mass_outer_diameter
            if self.mass_outer_diameter is not None
            else self.outer_diameter
        )
        di = (
            self.mass_inner_diameter
            if self.mass_inner_diameter is not None
            else self.inner_diameter
        )
        return np.pi / 4 * (do**2 - di**2), np.pi / 64 * (do**4 - di**4)

    @property
    def poisson(self) -> float:
        return self.E / (2 * self.shear_modulus) - 1.0

    @property
    def phi(self) -> float:
        """Shear parameter Φ = 12 EI / (κ G A L²)."""
        if not self.shear:
            return 0.0
        kappa = shear_coefficient(
            self.inner_diameter, self.outer_diameter, self.poisson, self.shear_method
        )
        return (
            12 * self.E * self.inertia / (kappa * self.shear_modulus * self.area * self.length**2)
        )

    @property
    def mass(self) -> float:
        return self.density * self._mass_section()[0] * self.length

    @property
    def rod_stiffness(self) -> float:
        """Torsional stiffness of the element (N·m/rad): given, or G J_p / L."""
        if self.torsional_stiffness is not None:
            return self.torsional_stiffness
        return self.shear_modulus * 2 * self.inertia / self.length

    @property
    def rod_inertia(self) -> float:
        """Polar mass moment of inertia of the element (kg·m²): given, or ρ J_p L of the mass
        section."""
        if self.polar_mass is not None:
            return self.polar_mass
        return self.density * 2 * self._mass_section()[1] * self.length

    # --- plane-beam matrices (w1, φ1, w2, φ2) ---------------------------------------------
    @cached_property
    def _plane(self) -> dict[str, NDArray]:
        L, phi = self.length, self.phi
        EI = self.E * self.inertia
        kga = (12 * EI / (phi * L**2)) if phi > 0 else 0.0  # κGA recovered from Φ
        A_m, I_m = self._mass_section()
        k = np.zeros((4, 4))
        mt = np.zeros((4, 4))
        mr = np.zeros((4, 4))
        for xi, wq in zip(_XI, _WXI, strict=True):
            nw, npsi, dnpsi = _plane_shape(phi, L, xi)
            # shear strain γ = w' − ψ, constant over the element
            dnw = _dnw(phi, L, xi)
            gamma = dnw - npsi
            k += wq * L * (EI * np.outer(dnpsi, dnpsi) + kga * np.outer(gamma, gamma))
            mt += wq * L * self.density * A_m * np.outer(nw, nw)
            mr += wq * L * self.density * I_m * np.outer(npsi, npsi)
        if not self.rotary_inertia:
            mr[:] = 0.0
        return {"k": k, "mt": mt, "mr": mr, "rot": mr / max(self.density * I_m, 1e-300)}

    # --- 12x12 matrices --------------------------------------------------------------------
    def K(self) -> NDArray:
        """Stiffness matrix (12×12, N/m, N, N·m)."""
        out = np.zeros((12, 12))
        self._scatter_bending(out, self._plane["k"])
        A, J = self.area, 2 * self.inertia
        _scatter_rod(out, Z, self.E * A / self.length)
        _scatter_rod(
            out,
            TZ,
            self.shear_modulus * J / self.length
            if self.torsional_stiffness is None
            else self.torsional_stiffness,
        )
        return out

    def M(self) -> NDArray:
        """Consistent mass matrix (12×12, kg, kg·m, kg·m²)."""
        out = np.zeros((12, 12))
        p = self._plane
        self._scatter_bending(out, p["mt"] + p["mr"])
        A_m, I_m = self._mass_section()
        m_rod = np.array([[2.0, 1.0], [1.0, 2.0]]) * self.length / 6
        for dof, coef in ((Z, self.density * A_m), (TZ, self.density * 2 * I_m)):
            idx = [dof, 6 + dof]
            if dof == TZ and self.polar_mass is not None:
                out[np.ix_(idx, idx)] += self.polar_mass / 6 * np.array([[2.0, 1.0], [1.0, 2.0]])
            else:
                out[np.ix_(idx, idx)] += coef * m_rod
        return out

    def G(self) -> NDArray:
        """Gyroscopic matrix per unit spin speed (12×12, skew-symmetric, kg·m²).

        Enters the equations as ``Ω G q̇``; built from the polar inertia per length ρIp = 2ρI.
        """
        _, I_m = self._mass_section()
        # ∫ N_ψᵀ N_ψ dz without the ρI factor
        base = self._plane["rot"] if I_m > 0 else np.zeros((4, 4))
        ip = self.density * 2 * I_m
        # θy(z) = N_ψ q_xz ; θx(z) = −N_ψ T q_yz with T = diag(1,−1,1,−1)
        gxy = ip * (-_T @ base)  # block (y-plane rows, x-plane cols): ∫ρIp θxᵀ θy
        out = np.zeros((12, 12))
        out[np.ix_(_IY, _IX)] += gxy
        out[np.ix_(_IX, _IY)] -= gxy.T
        return out

    @property
    def damped(self) -> bool:
        """True when the element has material damping (α or β non-zero) or a torsional
        dashpot."""
        return self.alpha != 0.0 or self.beta != 0.0 or bool(self.torsional_damping)

    def C(self) -> NDArray:
        """Damping matrix ``α M + β K`` (material) plus the torsional dashpot (12×12, N·s/m,
        N·s, N·m·s)."""
        out = self.alpha * self.M() + self.beta * self.K()
        if self.torsional_damping:
            _scatter_rod(out, TZ, self.torsional_damping)
        return out

    def Kc(self) -> NDArray:
        """Circulatory stiffness per unit spin speed of rotating damping (12×12, skew, N·s/m,
        N·s, N·m·s; zero without ``rotating_damping``).

        Enters the equations as ``Ω Kc q``. From the fixed-frame force ``−C_b (ṗ − iΩ p)`` of
        the bending damping (plane matrix ``c = α(m_t + m_r) + β k``): the x-plane rows get
        ``c p_y = c T q_y`` and the y-plane rows (``p_y = T q_y``) get ``−T c p_x``, with
        ``T = diag(1, −1, 1, −1)``. Axial and torsional damping have no circulatory part.
        """
        out = np.zeros((12, 12))
        if not self.rotating_damping:
            return out
        p = self._plane
        c = self.alpha * (p["mt"] + p["mr"]) + self.beta * p["k"]
        out[np.ix_(_IX, _IY)] = c @ _T
        out[np.ix_(_IY, _IX)] = -_T @ c
        return out

    def _scatter_bending(self, out: NDArray, plane: NDArray) -> None:
        out[np.ix_(_IX, _IX)] += plane
        out[np.ix_(_IY, _IY)] += _T @ plane @ _T


def _dnw(phi: float, L: float, xi: float) -> NDArray:
    """dN_w/dz of the Timoshenko interpolation."""
    return np.array(
        [
            (-6 * xi + 6 * xi**2 - phi) / L,
            1 - 4 * xi + 3 * xi**2 + 0.5 * phi * (1 - 2 * xi),
            (6 * xi - 6 * xi**2 + phi) / L,
            -2 * xi + 3 * xi**2 + 0.5 * phi * (2 * xi - 1),
        ]
    ) / (1.0 + phi)


def _scatter_rod(out: NDArray, dof: int, k: float) -> None:
    idx = [dof, 6 + dof]
    out[np.ix_(idx, idx)] += k * np.array([[1.0, -1.0], [-1.0, 1.0]])
