"""Finite-volume solution of the incompressible Reynolds equation on one pad.

Equation (θ circumferential angle, ζ = z/R, H = h/c, p = μ_ref (R/c)² P, μ̄ = μ/μ_ref)::

    ∂θ(H³/μ̄ ∂θP) + ∂ζ(H³/μ̄ ∂ζP) = 6 ω ∂θH + 12 ∂H/∂t

The viscosity is one number (isoviscous, μ̄ = 1) or a nodal field μ(θ, ζ) (thermal models,
:mod:`gearrotor.bearings.thermal`): the temperature, hence the viscosity, is taken uniform
across the film. A uniform field takes the isoviscous path, so it gives the isoviscous results
bit for bit.

Discretisation
--------------
Node-centred finite volumes on a uniform (θ, ζ) grid of ``n_theta`` intervals per pad and
``n_z`` intervals from the bearing edge to the mid-plane (pockets are axially centred, so the
film is symmetric about the mid-plane, which is a zero-flux boundary). Face conductances are
the exact one-dimensional values between two nodes, ``G = Δ / ∫ μ̄ H⁻³``, and the Couette flux
uses ``H_c = ∫ μ̄ H⁻² / ∫ μ̄ H⁻³`` (3-point Gauss per face, μ̄ linear between the nodes). For a
smooth film this is the usual second-order scheme; at a pressure-dam step it is the exact
Rayleigh-step flux of the face, so steps need not fall on grid lines. Pad edges and bearing
ends are at ambient pressure (p = 0); a 360° ``periodic`` pad closes on itself.

Cavitation
----------
``"swift_stieber"`` (Reynolds / Swift–Stieber, default): the linear complementarity problem
``M P − f ≥ 0, P ≥ 0, Pᵀ(M P − f) = 0`` with the M-matrix M of the discretisation, solved by a
primal–dual active-set method (each iteration one sparse LU on the uncavitated nodes; the
iteration is monotone for M-matrices and ends in a few steps). ``"half_sommerfeld"`` solves
the full film and clips negative pressures; ``"none"`` keeps them (full Sommerfeld).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import lru_cache
from typing import Literal

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray
from scipy.linalg import solve_banded
from scipy.sparse.linalg import splu

from ..errors import SolverError
from .geometry import Pad, TiltingPad

__all__ = [
    "Grid",
    "Cavitation",
    "PadFilm",
    "WorkCounter",
    "pad_mesh",
    "solve_pad",
    "pad_fluxes",
]

Cavitation = Literal["swift_stieber", "half_sommerfeld", "none"]

_GAUSS_X = np.array([0.5 - math.sqrt(15.0) / 10.0, 0.5, 0.5 + math.sqrt(15.0) / 10.0])
_GAUSS_W = np.array([5.0, 8.0, 5.0]) / 18.0


class FilmContact(SolverError):
    """The journal (or a pad) touches the bearing surface: h ≤ 0 somewhere."""


@dataclass(frozen=True)
class Grid:
    """Finite-volume grid of every pad.

    Attributes
    ----------
    n_theta
        Intervals along each pad's arc (a 360° pad uses ``n_theta`` over the circle × 2).
    n_z
        Intervals from the bearing edge to the mid-plane (half the length).
    """

    n_theta: int = 36
    n_z: int = 8

    def __post_init__(self) -> None:
        from ..errors import ModelError

        for name in ("n_theta", "n_z"):
            v = getattr(self, name)
            if not isinstance(v, int) or v < 2:
                raise ModelError(
                    "grid size too small", field=f"grid.{name}", value=v, expected="an integer ≥ 2"
                )


@dataclass
class WorkCounter:
    """Work done by the film solver: film solves, active-set iterations (= sparse LUs)."""

    film_solves: int = 0
    factorizations: int = 0

    def add(self, other: WorkCounter) -> None:
        self.film_solves += other.film_solves
        self.factorizations += other.factorizations


@dataclass(frozen=True)
class _Mesh:
    """Precomputed, state-independent arrays of one pad's grid (internal)."""

    periodic: bool
    theta: NDArray  # (m+1,) node angles, rad
    zeta: NDArray  # (n+1,) ζ = z/R of nodes, 0 at the edge, n at the mid-plane
    dth: float
    dze: float
    dzw: NDArray  # (n+1,) axial width of node control volumes (half at mid-plane)
    h0_node: NDArray  # (m+1,) film at zero state (preload profile), /c
    phi_node: NDArray  # (4, m+1) ∂H/∂q at nodes for q = (X, Y, tilt, radial)
    h0_q: NDArray  # (m, g) film at θ-face quadrature points
    phi_q: NDArray  # (4, m, g)
    pocket_node: NDArray | None  # (m+1, n+1) pocket depth /c at nodes
    pocket_q: NDArray | None  # (m, g, n+1, g) θ-face points × z points across each row's volume
    pocket_zq: NDArray | None  # (m+1, g, n, g) θ points across each column × ζ-face points
    h0_c: NDArray | None  # (m+1, g) film at θ points across each column's volume
    phi_c: NDArray | None  # (4, m+1, g)
    unk_i: NDArray  # (N,) node i of each unknown
    unk_j: NDArray  # (N,) node j of each unknown
    rows: NDArray  # COO pattern
    cols: NDArray
    slots: tuple  # slices of the COO data: diag, E, W, N, S
    neighbours: NDArray  # (4, N) unknown index of the E, W, N, S neighbour, or N (none)
    w_area: NDArray  # (N,) Δθ·Δζ_j weights of the unknowns (half bearing)


def _pad_profile(pad: Pad | TiltingPad, theta: NDArray) -> tuple[NDArray, NDArray]:
    """Zero-state film H0 (/c) and ∂H/∂q (4, …) at angles ``theta``."""
    m = pad.preload
    cp = 1.0 / (1.0 - m)
    tp = pad.pivot if isinstance(pad, TiltingPad) else pad.reference_angle
    h0 = cp - (cp - 1.0) * np.cos(theta - tp)
    phi = np.stack([-np.cos(theta), -np.sin(theta), -np.sin(theta - tp), np.cos(theta - tp)])
    return h0, phi


def _in_pocket(
    pad: Pad | TiltingPad,
    theta: NDArray,
    z: NDArray,
    length: float,
    radius: float,
    clearance: float,
) -> NDArray:
    """Pocket depth /c at (theta, z) (broadcast), z measured from the edge (m)."""
    pocket = getattr(pad, "pocket", None)
    if pocket is None:
        return np.zeros(np.broadcast_shapes(theta.shape, z.shape))
    a = pad.start + pocket.start
    b = a + pocket.arc
    in_t = (theta >= a) & (theta <= b)
    in_z = z >= 0.5 * (length - pocket.width) - 1e-12 * length
    return np.where(in_t & in_z, pocket.depth / clearance, 0.0)


@lru_cache(maxsize=256)
def pad_mesh(
    pad: Pad | TiltingPad, radius: float, length: float, clearance: float, grid: Grid
) -> _Mesh:
    """Build (and cache) the state-independent grid data of one pad."""
    periodic = bool(getattr(pad, "periodic", False))
    m = grid.n_theta * (2 if periodic else 1)
    n = grid.n_z
    theta = pad.start + np.linspace(0.0, pad.arc, m + 1)
    dth = pad.arc / m
    dze = 0.5 * length / radius / n
    zeta = np.arange(n + 1) * dze
    dzw = np.full(n + 1, dze)
    dzw[-1] = 0.5 * dze
    h0_node, phi_node = _pad_profile(pad, theta)
    tq = theta[:-1, None] + dth * _GAUSS_X[None, :]
    h0_q, phi_q = _pad_profile(pad, tq)
    z_node = zeta * radius
    if getattr(pad, "pocket", None) is not None:
        # A pocket edge may cross a control volume: conductances of parallel strips are
        # averaged across the volume, those of strips in series harmonically along the flow.
        pocket_node = _in_pocket(pad, theta[:, None], z_node[None, :], length, radius, clearance)
        z_lo = np.maximum(z_node - 0.5 * dze * radius, 0.0)
        z_hi = np.minimum(z_node + 0.5 * dze * radius, 0.5 * length)
        z_cv = z_lo[:, None] + (z_hi - z_lo)[:, None] * _GAUSS_X[None, :]  # (n+1, g)
        pocket_q = _in_pocket(
            pad, tq[:, :, None, None], z_cv[None, None, :, :], length, radius, clearance
        )
        t_lo = np.maximum(theta - 0.5 * dth, theta[0])
        t_hi = np.minimum(theta + 0.5 * dth, theta[-1])
        t_cv = t_lo[:, None] + (t_hi - t_lo)[:, None] * _GAUSS_X[None, :]  # (m+1, g)
        h0_c, phi_c = _pad_profile(pad, t_cv)
        zq = (zeta[:-1, None] + dze * _GAUSS_X[None, :]) * radius  # (n, g)
        pocket_zq = _in_pocket(
            pad, t_cv[:, :, None, None], zq[None, None, :, :], length, radius, clearance
        )
    else:
        pocket_node = pocket_q = pocket_zq = h0_c = phi_c = None

    # unknowns: i in 1..m-1 (or 0..m-1 periodic), j in 1..n
    irange = np.arange(0, m) if periodic else np.arange(1, m)
    ni = len(irange)
    ii, jj = np.meshgrid(irange, np.arange(1, n + 1), indexing="ij")
    unk_i = ii.ravel()
    unk_j = jj.ravel()
    idx = -np.ones((m + 1, n + 1), dtype=np.int64)
    idx[unk_i, unk_j] = np.arange(ni * n)
    if periodic:
        idx[m, 1:] = idx[0, 1:]
    k = np.arange(ni * n)
    e_nb = idx[unk_i + 1, unk_j]
    w_nb = idx[(unk_i - 1) % m if periodic else unk_i - 1, unk_j]
    n_nb = idx[unk_i, np.minimum(unk_j + 1, n)]
    n_nb = np.where(unk_j < n, n_nb, -1)
    s_nb = idx[unk_i, unk_j - 1]
    rows, cols, slots = [k], [k], [slice(0, len(k))]
    start = len(k)
    for nb in (e_nb, w_nb, n_nb, s_nb):
        mask = nb >= 0
        rows.append(k[mask])
        cols.append(nb[mask])
        slots.append((start, start + int(mask.sum()), mask))
        start += int(mask.sum())
    return _Mesh(
        periodic=periodic,
        theta=theta,
        zeta=zeta,
        dth=dth,
        dze=dze,
        dzw=dzw,
        h0_node=h0_node,
        phi_node=phi_node,
        h0_q=h0_q,
        phi_q=phi_q,
        pocket_node=pocket_node,
        pocket_q=pocket_q,
        pocket_zq=pocket_zq,
        h0_c=h0_c,
        phi_c=phi_c,
        unk_i=unk_i,
        unk_j=unk_j,
        rows=np.concatenate(rows),
        cols=np.concatenate(cols),
        slots=tuple(slots),
        w_area=dth * dzw[unk_j],
        neighbours=np.where(
            np.stack([e_nb, w_nb, n_nb, s_nb]) >= 0, np.stack([e_nb, w_nb, n_nb, s_nb]), ni * n
        ),
    )


@dataclass(frozen=True)
class PadFilm:
    """Film solution of one pad (half bearing from the edge to the mid-plane stored).

    Attributes
    ----------
    theta
        Node angles (rad), shape (m+1,).
    z
        Node axial positions from the bearing edge to the mid-plane (m), shape (n+1,).
    pressure
        Pressure (Pa), shape (m+1, n+1).
    film
        Film thickness (m), shape (m+1, n+1).
    forces
        Generalised film forces on (x, y, tilt lever, radial) of the pad, ``∫ p ∂h/∂q dA``:
        journal forces Fx, Fy (N) (the bearing reaction on the journal), the tilt force
        (N; times R + t is the pad moment, N·m) and the radial pivot force (N).
    side_flow
        Axial flow out of both bearing ends (m³/s).
    friction_power
        Viscous power loss on the pad (W), full-film shear over the pad area.
    active
        Cavitated-node mask of the unknowns (for a warm start).
    iterations
        Active-set iterations (sparse factorisations) used.
    """

    theta: NDArray
    z: NDArray
    pressure: NDArray
    film: NDArray
    forces: NDArray
    side_flow: float
    friction_power: float
    active: NDArray = field(repr=False)
    iterations: int = 0


def _film_faces(
    mesh: _Mesh, q: NDArray, mubar: NDArray | None = None
) -> tuple[NDArray, NDArray, NDArray, NDArray]:
    """Node film, θ-face conductance G_θ, Couette film H_c, ζ-face conductance G_ζ (all /c).

    ``mubar``: nodal viscosity field / μ_ref, shape (m+1, n+1), or None (isoviscous). It is
    taken linear between two nodes on each face."""
    h_node = mesh.h0_node + np.tensordot(q, mesh.phi_node, axes=1)
    h_q = mesh.h0_q + np.tensordot(q, mesh.phi_q, axes=1)  # (m, g)
    n1 = len(mesh.zeta)
    if mesh.pocket_q is None:
        h_min = min(h_node.min(), h_q.min())
        if h_min <= 0.0:
            raise _contact(h_min)
        if mubar is None:
            inv3 = _GAUSS_W @ (h_q**-3).T  # (m,)
            inv2 = _GAUSS_W @ (h_q**-2).T
            g_th = np.repeat((1.0 / inv3)[:, None], n1, axis=1)
            h_c = np.repeat((inv2 / inv3)[:, None], n1, axis=1)
            g_ze = np.repeat((h_node**3)[:, None], n1 - 1, axis=1)
        else:
            mu_q = _along_theta(mubar)  # (m, g, n+1)
            inv3 = np.einsum("g,mgn->mn", _GAUSS_W, mu_q * (h_q**-3)[:, :, None])
            inv2 = np.einsum("g,mgn->mn", _GAUSS_W, mu_q * (h_q**-2)[:, :, None])
            g_th = 1.0 / inv3
            h_c = inv2 / inv3
            g_ze = (h_node**3)[:, None] / (0.5 * (mubar[:, 1:] + mubar[:, :-1]))
        h_full = np.repeat(h_node[:, None], n1, axis=1)
        return h_full, g_th, h_c, g_ze
    h_full = h_node[:, None] + mesh.pocket_node
    h_c = mesh.h0_c + np.tensordot(q, mesh.phi_c, axes=1)  # (m+1, g)
    h_min = min(h_node.min(), h_q.min(), h_c.min())
    if h_min <= 0.0:
        raise _contact(h_min)
    hq = h_q[:, :, None, None] + mesh.pocket_q  # (m, g, n+1, gz)
    hzq = h_c[:, :, None, None] + mesh.pocket_zq  # (m+1, gt, n, g)
    if mubar is None:
        inv3 = np.einsum("g,mgnz->mnz", _GAUSS_W, hq**-3)
        inv2 = np.einsum("g,mgnz->mnz", _GAUSS_W, hq**-2)
        g_ze = np.einsum("t,mtn->mn", _GAUSS_W, 1.0 / (hzq**-3 @ _GAUSS_W))
    else:
        mu_q = _along_theta(mubar)[:, :, :, None]  # (m, g, n+1, 1)
        inv3 = np.einsum("g,mgnz->mnz", _GAUSS_W, mu_q * hq**-3)
        inv2 = np.einsum("g,mgnz->mnz", _GAUSS_W, mu_q * hq**-2)
        mu_z = mubar[:, :-1, None] + _GAUSS_X * (mubar[:, 1:] - mubar[:, :-1])[:, :, None]
        g_ze = np.einsum("t,mtn->mn", _GAUSS_W, 1.0 / ((mu_z[:, None, :, :] * hzq**-3) @ _GAUSS_W))
    g_th = (1.0 / inv3) @ _GAUSS_W
    couette = (inv2 / inv3) @ _GAUSS_W
    return h_full, g_th, couette, g_ze


def _along_theta(mubar: NDArray) -> NDArray:
    """The nodal field at the θ-face Gauss points, linear between nodes: shape (m, g, n+1)."""
    return mubar[:-1, None, :] + _GAUSS_X[None, :, None] * (mubar[1:] - mubar[:-1])[:, None, :]


def _viscosity(mesh: _Mesh, viscosity: float | NDArray) -> tuple[float, NDArray | None]:
    """(μ_ref, μ/μ_ref nodal field or None): a uniform field is the isoviscous case."""
    if np.ndim(viscosity) == 0:
        return float(viscosity), None
    field = np.asarray(viscosity, dtype=float)
    shape = (len(mesh.theta), len(mesh.zeta))
    if field.shape != shape:
        raise ValueError(f"viscosity field of shape {field.shape}, expected {shape}")
    mu_ref = float(field.flat[0])
    if np.all(field == mu_ref):
        return mu_ref, None
    return mu_ref, field / mu_ref


def _contact(h_min: float) -> FilmContact:
    return FilmContact(f"the journal touches a pad (film thickness ≤ 0, min h/c = {h_min:.3g})")


def _lcp_active_set(
    a: sp.csr_matrix, f: NDArray, active: NDArray | None, max_iter: int = 60
) -> tuple[NDArray, NDArray, int]:
    """Solve the M-matrix LCP ``A p − f ≥ 0, p ≥ 0, complementary`` by primal–dual active set.

    General sparse version (periodic pads): one sparse LU of the free block per iteration.
    """
    n = len(f)
    d = a.diagonal()
    act = np.zeros(n, dtype=bool) if active is None else active.copy()
    tol = 1e-13 * (np.abs(f).max() + 1e-300)
    a_csc = a.tocsc()
    for it in range(1, max_iter + 1):
        free = ~act
        p = np.zeros(n)
        if free.any():
            sub = a_csc[free][:, free]
            p[free] = splu(sub.tocsc(), permc_spec="MMD_AT_PLUS_A").solve(f[free])
        lam = a @ p - f
        # active where the multiplier is positive (active nodes) or the pressure negative
        new = (lam - d * p) > tol
        if np.array_equal(new, act):
            return np.maximum(p, 0.0), act, it
        act = new
    raise _no_lcp_convergence(max_iter)


def _no_lcp_convergence(max_iter: int) -> SolverError:
    return SolverError(
        f"cavitation active-set iteration did not converge in {max_iter} iterations; "
        "refine the grid or use cavitation='half_sommerfeld'"
    )


def _lcp_banded(
    diag: NDArray,
    off: NDArray,
    nb: NDArray,
    nz: int,
    f: NDArray,
    active: NDArray | None,
    clip: bool,
    max_iter: int = 60,
) -> tuple[NDArray, NDArray, int]:
    """Banded version for non-periodic pads (unknowns ordered ζ fastest, bandwidth ``nz``).

    ``off`` (4, N) are the positive conductances to the E, W, N, S neighbours ``nb`` (index N
    = none). Cavitated rows are replaced by ``p = 0``. With ``clip`` False a single linear
    solve is done (no cavitation).
    """
    n = len(f)
    offsets = (nz, -nz, 1, -1)  # column offset of E, W, N, S
    act = np.zeros(n, dtype=bool) if active is None else active.copy()
    if not clip:
        act[:] = False
    tol = 1e-13 * (np.abs(f).max() + 1e-300)
    ab = np.zeros((2 * nz + 1, n))
    for it in range(1, max_iter + 1):
        keep = ~act
        ab[:] = 0.0
        ab[nz] = np.where(keep, diag, 1.0)
        for c, (o, nbr) in enumerate(zip(offsets, nb, strict=True)):
            rows = np.nonzero(keep & (nbr < n))[0]
            ab[nz - o, rows + o] = -off[c, rows]
        rhs = np.where(keep, f, 0.0)
        p = solve_banded(
            (nz, nz), ab, rhs, overwrite_ab=False, overwrite_b=True, check_finite=False
        )
        if not clip:
            return p, act, it
        pe = np.append(p, 0.0)
        lam = diag * p - np.einsum("kn,kn->n", off, pe[nb]) - f
        new = (lam - diag * p) > tol
        if np.array_equal(new, act):
            return np.maximum(p, 0.0), act, it
        act = new
    raise _no_lcp_convergence(max_iter)


def solve_pad(
    mesh: _Mesh,
    q: NDArray,
    qdot: NDArray,
    omega: float,
    *,
    viscosity: float | NDArray,
    radius: float,
    clearance: float,
    cavitation: Cavitation = "swift_stieber",
    active: NDArray | None = None,
    work: WorkCounter | None = None,
) -> PadFilm:
    """Solve the film of one pad.

    Parameters
    ----------
    mesh
        From :func:`pad_mesh`.
    q
        Pad state (X, Y, A, S) divided by the clearance: journal displacement x/c, y/c; tilt
        δ(R+t)/c; outward radial pivot displacement ξ/c (the last two are 0 for fixed pads).
    qdot
        Time derivative of ``q`` (1/s).
    omega
        Journal speed (rad/s, signed).
    viscosity
        μ (Pa·s): one number, or a nodal field of shape (m+1, n+1) (the pad's nodes,
        :attr:`PadFilm.theta` × :attr:`PadFilm.z`). A uniform field is the isoviscous case (same
        floating-point results as the number).
    radius, clearance
        R (m), c (m).
    cavitation
        Cavitation model (see module docstring).
    active
        Warm-start cavitated set (from a previous :class:`PadFilm`).
    work
        Optional counter to increment.
    """
    q = np.asarray(q, dtype=float)
    qdot = np.asarray(qdot, dtype=float)
    mu_ref, mubar = _viscosity(mesh, viscosity)
    h_full, g_th, h_c, g_ze = _film_faces(mesh, q, mubar)
    m = len(mesh.theta) - 1
    i, j = mesh.unk_i, mesh.unk_j
    iw = (i - 1) % m if mesh.periodic else i - 1
    dzw = mesh.dzw[j]
    a_e = g_th[i, j] * dzw / mesh.dth
    a_w = g_th[iw, j] * dzw / mesh.dth
    n = len(mesh.zeta) - 1
    a_n = np.where(j < n, g_ze[i, np.minimum(j, n - 1)], 0.0) * mesh.dth / mesh.dze
    a_s = g_ze[i, j - 1] * mesh.dth / mesh.dze
    diag = a_e + a_w + a_n + a_s  # includes the conductances to ambient-pressure neighbours
    n_unk = len(i)
    hdot = qdot @ mesh.phi_node[:, i]
    rhs = -6.0 * omega * (h_c[i, j] - h_c[iw, j]) * dzw - 12.0 * hdot * mesh.w_area

    if not mesh.periodic:
        off = np.where(mesh.neighbours < n_unk, np.stack([a_e, a_w, a_n, a_s]), 0.0)
        p, act, iters = _lcp_banded(
            diag, off, mesh.neighbours, n, rhs, active, clip=cavitation == "swift_stieber"
        )
        if cavitation == "half_sommerfeld":
            p = np.maximum(p, 0.0)
    else:
        data = [diag]
        for coef, (_, _, mask) in zip((a_e, a_w, a_n, a_s), mesh.slots[1:], strict=True):
            data.append(-coef[mask])
        amat = sp.csr_matrix((np.concatenate(data), (mesh.rows, mesh.cols)), shape=(n_unk, n_unk))
        if cavitation == "swift_stieber":
            p, act, iters = _lcp_active_set(amat, rhs, active)
        else:
            p = splu(amat.tocsc()).solve(rhs)
            if cavitation == "half_sommerfeld":
                p = np.maximum(p, 0.0)
            act, iters = np.zeros(n_unk, dtype=bool), 1
    if work is not None:
        work.film_solves += 1
        work.factorizations += iters

    scale = mu_ref * (radius / clearance) ** 2  # Pa per unit P
    pgrid = np.zeros((m + 1, n + 1))
    pgrid[i, j] = p
    if mesh.periodic:
        pgrid[m] = pgrid[0]
    # generalised forces (both halves)
    phi_u = mesh.phi_node[:, i]
    forces = 2.0 * scale * radius**2 * (phi_u @ (p * mesh.w_area))
    # side flow out of both ends: the flux through the faces j = 1/2 plus the net Couette and
    # squeeze source of the half cell between them and the edge (second order in Δζ)
    first = (j == 1) & (p > 0.0)
    side = (
        2.0
        * clearance
        * radius**2
        / 12.0
        * float(np.sum(a_s[first] * p[first]) + 0.5 * np.sum(rhs[first]))
    )
    # friction power (full-film shear on the pad)
    wt = np.full(m + 1, mesh.dth)
    if not mesh.periodic:
        wt[[0, -1]] *= 0.5
    else:
        wt[-1] = 0.0
    wz = mesh.dzw.copy()
    wz[0] *= 0.5
    dp_dth = np.gradient(pgrid, mesh.dth, axis=0)
    if mesh.periodic:
        dp_dth[0] = dp_dth[-1] = (pgrid[1] - pgrid[m - 1]) / (2 * mesh.dth)
    couette = omega / h_full if mubar is None else mubar * omega / h_full
    dens = omega * (couette + 0.5 * h_full * dp_dth)
    power = 2.0 * mu_ref * radius**4 / clearance * float(wt @ dens @ wz)
    return PadFilm(
        theta=mesh.theta,
        z=mesh.zeta * radius,
        pressure=scale * pgrid,
        film=clearance * h_full,
        forces=forces,
        side_flow=side,
        friction_power=abs(power),
        active=act,
        iterations=iters,
    )


def pad_fluxes(
    mesh: _Mesh,
    film: PadFilm,
    q: NDArray,
    omega: float,
    *,
    viscosity: float | NDArray,
    radius: float,
    clearance: float,
) -> tuple[NDArray, NDArray]:
    """Volume flow through every face of a pad's control volumes implied by a steady film.

    The same face conductances and Couette films as :func:`solve_pad`, so at every node with
    a pressure (uncavitated unknown) the flows balance to round-off.

    Returns
    -------
    theta_flow
        Shape (m, n+1): flow (m³/s, half bearing) from node (i, j) to (i+1, j), positive in
        +θ. Row j spans the axial width of node j's control volume (half a cell at the bearing
        edge, j = 0, and at the mid-plane, j = n).
    axial_flow
        Shape (m+1, n): flow from node (i, j) to (i, j+1) (towards the mid-plane), over the
        circumferential width of node i's control volume (half a cell at the ends of a
        non-periodic pad).
    """
    q = np.asarray(q, dtype=float)
    mu_ref, mubar = _viscosity(mesh, viscosity)
    _, g_th, h_c, g_ze = _film_faces(mesh, q, mubar)
    p = film.pressure / (mu_ref * (radius / clearance) ** 2)
    k = clearance * radius**2 / 12.0
    wz = mesh.dzw.copy()
    wz[0] = 0.5 * mesh.dze
    theta_flow = k * (6.0 * omega * h_c - g_th * np.diff(p, axis=0) / mesh.dth) * wz
    wt = np.full(len(mesh.theta), mesh.dth)
    if not mesh.periodic:
        wt[[0, -1]] *= 0.5
    axial_flow = -k * g_ze * np.diff(p, axis=1) / mesh.dze * wt[:, None]
    return theta_flow, axial_flow
