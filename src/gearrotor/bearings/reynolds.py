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
from collections.abc import Callable
from dataclasses import dataclass, field
from functools import cached_property, lru_cache, partial
from typing import Literal

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray
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
    fast: _Fast  # index arrays and weights of the solve, fixed per grid


@dataclass(frozen=True)
class _Fast:
    """State-independent index arrays and weights of :func:`solve_pad` (internal).

    Everything the solve would otherwise rebuild per call from the unknowns' (i, j): gathers
    of face values, masks, quadrature weights and the positions of the matrix entries in
    LAPACK's band storage. Used as they are, they give the same floating-point results."""

    unk_iw: NDArray  # (N,) node i of each unknown's west neighbour
    dzw_u: NDArray  # (N,) dzw[j] of each unknown
    phi_u: NDArray  # (4, N) phi_node at the unknowns
    phi_node2: NDArray  # phi_node as the (4, ·) matrix q multiplies
    phi_q2: NDArray  # phi_q as a (4, m·g) matrix
    phi_c2: NDArray | None  # phi_c as a (4, (m+1)·g) matrix
    ij_th: NDArray  # (N,) flat index of (i, j) in an (m, n+1) or (m+1, n+1) array
    iwj_th: NDArray  # (N,) flat index of (iw, j)
    ij_ze: NDArray  # (N,) flat index of (i, min(j, n−1)) in an (m+1, n) array
    ijs_ze: NDArray  # (N,) flat index of (i, j−1) in an (m+1, n) array
    north: NDArray  # (N,) j < n: the unknown has a north face inside the film
    has_nb: NDArray  # (4, N) the E, W, N, S neighbour is an unknown
    first_row: NDArray  # indices of the unknowns with j == 1 (next to the bearing edge)
    wt: NDArray  # (m+1,) θ quadrature weights of the friction power
    wz: NDArray  # (n+1,) ζ quadrature weights of the friction power
    pocket_depth: float  # pocket depth /c (0 without a pocket)
    spread_q: NDArray | None  # (m, g, n+1, gz) index of each point's film in [H_q, H_q + d]
    spread_zq: NDArray | None  # (m+1, gt, n, g) index of each point's film in [H_c, H_c + d]
    band: _Band | None  # band storage (non-periodic pads)
    csc: _Csc | None  # compressed sparse column pattern (periodic pads)


@dataclass(frozen=True)
class _Csc:
    """The film matrix' pattern in compressed sparse column form, rows sorted in each column,
    as SciPy orders it (internal). ``perm`` takes the COO data (:attr:`_Mesh.rows`,
    :attr:`_Mesh.cols` order) to it."""

    perm: NDArray  # (nnz,)
    rows: NDArray  # (nnz,) row of each entry
    cols: NDArray  # (nnz,) column of each entry
    indptr: NDArray  # (N+1,)


@dataclass(frozen=True)
class _Band:
    """Positions of the matrix entries in LAPACK ``gbsv`` band storage (internal).

    The work array is C-ordered (N, 3 nz + 1), passed transposed (Fortran order, the layout
    ``gbsv`` takes in place): row r of the matrix, column r + o sits at flat index
    (r + o)·(3 nz + 1) + 2 nz − o."""

    nz: int
    diag_flat: NDArray  # (N,) flat index of each diagonal entry
    ent_row: NDArray  # (E,) matrix row of each off-diagonal entry
    ent_flat: NDArray  # (E,) its flat index in the work array
    ent_src: NDArray  # (E,) its flat index in the (4, N) conductances


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
    n_unk = ni * n
    rows_all, cols_all = np.concatenate(rows), np.concatenate(cols)
    nbrs = np.stack([e_nb, w_nb, n_nb, s_nb])
    iw = (unk_i - 1) % m if periodic else unk_i - 1
    wt = np.full(m + 1, dth)
    if not periodic:
        wt[[0, -1]] *= 0.5
    else:
        wt[-1] = 0.0
    wz = dzw.copy()
    wz[0] *= 0.5
    band = None
    if not periodic:
        rows_e, flat_e, src_e = [], [], []
        for c, o in enumerate((n, -n, 1, -1)):  # column offsets of E, W, N, S
            r = np.nonzero(nbrs[c] >= 0)[0]
            rows_e.append(r)
            flat_e.append((r + o) * (3 * n + 1) + 2 * n - o)
            src_e.append(c * n_unk + r)
        band = _Band(
            nz=n,
            diag_flat=k * (3 * n + 1) + 2 * n,
            ent_row=np.concatenate(rows_e),
            ent_flat=np.concatenate(flat_e),
            ent_src=np.concatenate(src_e),
        )
    has_pocket = pocket_q is not None
    fast = _Fast(
        unk_iw=iw,
        dzw_u=dzw[unk_j],
        phi_u=phi_node[:, unk_i],
        phi_node2=phi_node.reshape(4, -1),
        phi_q2=phi_q.reshape(4, -1),
        phi_c2=phi_c.reshape(4, -1) if has_pocket else None,
        ij_th=unk_i * (n + 1) + unk_j,
        iwj_th=iw * (n + 1) + unk_j,
        ij_ze=unk_i * n + np.minimum(unk_j, n - 1),
        ijs_ze=unk_i * n + unk_j - 1,
        north=unk_j < n,
        has_nb=nbrs >= 0,
        first_row=np.nonzero(unk_j == 1)[0],
        wt=wt,
        wz=wz,
        pocket_depth=pad.pocket.depth / clearance if has_pocket else 0.0,
        spread_q=_spread_index(pocket_q) if has_pocket else None,
        spread_zq=_spread_index(pocket_zq) if has_pocket else None,
        band=band,
        csc=_csc(rows_all, cols_all, n_unk) if periodic else None,
    )
    return _Mesh(
        fast=fast,
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
        rows=rows_all,
        cols=cols_all,
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

    ``side_flow`` and ``friction_power`` are evaluated when first read (most solves, those of
    the Jacobians and the Newton steps, need only the forces); their values do not depend on
    when they are read.
    """

    theta: NDArray
    z: NDArray
    pressure: NDArray
    film: NDArray
    forces: NDArray
    active: NDArray = field(repr=False)
    _side_flow: Callable[[], float] = field(repr=False, compare=False)
    _friction_power: Callable[[], float] = field(repr=False, compare=False)
    iterations: int = 0

    @cached_property
    def side_flow(self) -> float:
        return self._side_flow()

    @cached_property
    def friction_power(self) -> float:
        return self._friction_power()


def _faces(
    mesh: _Mesh, q: NDArray, mubar: NDArray | None
) -> tuple[NDArray, NDArray, NDArray, NDArray, bool]:
    """:func:`_film_faces`, with the film along θ (shape (m+1,), :func:`_full_film` spreads
    it) and the isoviscous pocketless faces left compact (last item True): G_θ, H_c of shape
    (m,) and G_ζ of shape (m+1,), the same along ζ."""
    fa = mesh.fast
    q2 = q.reshape(1, 4)
    h_node = mesh.h0_node + np.dot(q2, fa.phi_node2).reshape(mesh.h0_node.shape)
    h_q = mesh.h0_q + np.dot(q2, fa.phi_q2).reshape(mesh.h0_q.shape)  # (m, g)
    if mesh.pocket_q is None:
        h_min = min(h_node.min(), h_q.min())
        if h_min <= 0.0:
            raise _contact(h_min)
        if mubar is None:
            inv3 = _GAUSS_W @ (h_q**-3).T  # (m,)
            inv2 = _GAUSS_W @ (h_q**-2).T
            return h_node, 1.0 / inv3, inv2 / inv3, h_node**3, True
        mu_q = _along_theta(mubar)  # (m, g, n+1)
        inv3 = np.einsum("g,mgn->mn", _GAUSS_W, mu_q * (h_q**-3)[:, :, None])
        inv2 = np.einsum("g,mgn->mn", _GAUSS_W, mu_q * (h_q**-2)[:, :, None])
        g_th = 1.0 / inv3
        h_c = inv2 / inv3
        g_ze = (h_node**3)[:, None] / (0.5 * (mubar[:, 1:] + mubar[:, :-1]))
        return h_node, g_th, h_c, g_ze, False
    h_c = mesh.h0_c + np.dot(q2, fa.phi_c2).reshape(mesh.h0_c.shape)  # (m+1, g)
    h_min = min(h_node.min(), h_q.min(), h_c.min())
    if h_min <= 0.0:
        raise _contact(h_min)
    # The film at a quadrature point is H or H + pocket depth (H + 0 = H exactly): the powers
    # are taken of those two values and spread over the (m, g, n+1, gz) points, the same
    # numbers as the powers of the spread films.
    d = fa.pocket_depth
    hq3 = np.concatenate((h_q**-3, (h_q + d) ** -3)).take(fa.spread_q)  # (m, g, n+1, gz)
    hq2 = np.concatenate((h_q**-2, (h_q + d) ** -2)).take(fa.spread_q)
    hzq3 = np.concatenate((h_c**-3, (h_c + d) ** -3)).take(fa.spread_zq)  # (m+1, gt, n, g)
    if mubar is None:
        inv3 = np.einsum("g,mgnz->mnz", _GAUSS_W, hq3)
        inv2 = np.einsum("g,mgnz->mnz", _GAUSS_W, hq2)
        g_ze = np.einsum("t,mtn->mn", _GAUSS_W, 1.0 / (hzq3 @ _GAUSS_W))
    else:
        mu_q = _along_theta(mubar)[:, :, :, None]  # (m, g, n+1, 1)
        inv3 = np.einsum("g,mgnz->mnz", _GAUSS_W, mu_q * hq3)
        inv2 = np.einsum("g,mgnz->mnz", _GAUSS_W, mu_q * hq2)
        mu_z = mubar[:, :-1, None] + _GAUSS_X * (mubar[:, 1:] - mubar[:, :-1])[:, :, None]
        g_ze = np.einsum("t,mtn->mn", _GAUSS_W, 1.0 / ((mu_z[:, None, :, :] * hzq3) @ _GAUSS_W))
    g_th = (1.0 / inv3) @ _GAUSS_W
    couette = (inv2 / inv3) @ _GAUSS_W
    return h_node, g_th, couette, g_ze, False


def _full_film(mesh: _Mesh, h_node: NDArray) -> NDArray:
    """The film H (/c) at every node, shape (m+1, n+1), from its values along θ."""
    if mesh.pocket_node is None:
        return np.repeat(h_node[:, None], len(mesh.zeta), axis=1)
    return h_node[:, None] + mesh.pocket_node


def _spread_index(pocket: NDArray) -> NDArray:
    """For a pocket depth field of shape (a, b, c, d): the index of each point's film in the
    films (a, b) without, then (a, b) with the pocket, raveled."""
    a, b = pocket.shape[:2]
    base = np.arange(a * b).reshape(a, b, 1, 1)
    return np.where(pocket != 0.0, base + a * b, base)


def _film_faces(
    mesh: _Mesh, q: NDArray, mubar: NDArray | None = None
) -> tuple[NDArray, NDArray, NDArray, NDArray]:
    """Node film, θ-face conductance G_θ, Couette film H_c, ζ-face conductance G_ζ (all /c).

    ``mubar``: nodal viscosity field / μ_ref, shape (m+1, n+1), or None (isoviscous). It is
    taken linear between two nodes on each face."""
    h_node, g_th, h_c, g_ze, compact = _faces(mesh, q, mubar)
    h_full = _full_film(mesh, h_node)
    if compact:
        n1 = h_full.shape[1]
        g_th = np.repeat(g_th[:, None], n1, axis=1)
        h_c = np.repeat(h_c[:, None], n1, axis=1)
        g_ze = np.repeat(g_ze[:, None], n1 - 1, axis=1)
    return h_full, g_th, h_c, g_ze


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


def _csc(rows: NDArray, cols: NDArray, n: int) -> _Csc:
    perm = np.lexsort((rows, cols))
    indptr = np.concatenate([[0], np.cumsum(np.bincount(cols, minlength=n))])
    return _Csc(
        perm=perm,
        rows=rows[perm].astype(np.intc),
        cols=cols[perm].astype(np.intc),
        indptr=indptr.astype(np.intc),
    )


def _free_block(csc: _Csc, data: NDArray, free: NDArray) -> sp.csc_array:
    """The block of the free rows and columns, as ``a[free][:, free]`` of the CSC matrix gives
    it (the entries in the same order, rows renumbered)."""
    keep = free[csc.rows] & free[csc.cols]
    rank = (np.cumsum(free) - 1).astype(np.intc)
    nf = int(rank[-1]) + 1
    cols = rank[csc.cols[keep]]
    indptr = np.concatenate([[0], np.cumsum(np.bincount(cols, minlength=nf))]).astype(np.intc)
    return sp.csc_array((data[keep], rank[csc.rows[keep]], indptr), shape=(nf, nf))


def _lcp_active_set(
    a: sp.csc_array, csc: _Csc, f: NDArray, active: NDArray | None, max_iter: int = 60
) -> tuple[NDArray, NDArray, int]:
    """Solve the M-matrix LCP ``A p − f ≥ 0, p ≥ 0, complementary`` by primal–dual active set.

    General sparse version (periodic pads): one sparse LU of the free block per iteration.
    ``a`` in CSC form with the pattern ``csc``.
    """
    n = len(f)
    d = a.diagonal()
    act = np.zeros(n, dtype=bool) if active is None else active.copy()
    tol = 1e-13 * (np.abs(f).max() + 1e-300)
    for it in range(1, max_iter + 1):
        free = ~act
        p = np.zeros(n)
        if free.any():
            sub = _free_block(csc, a.data, free)
            p[free] = splu(sub, permc_spec="MMD_AT_PLUS_A").solve(f[free])
        # the row sums in ascending column order, as the CSR product of the sorted matrix
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
    band: _Band,
    f: NDArray,
    active: NDArray | None,
    clip: bool,
    max_iter: int = 60,
) -> tuple[NDArray, NDArray, int]:
    """Banded version for non-periodic pads (unknowns ordered ζ fastest, bandwidth ``nz``).

    ``off`` (4, N) are the positive conductances to the E, W, N, S neighbours ``nb`` (index N
    = none). Cavitated rows are replaced by ``p = 0``. With ``clip`` False a single linear
    solve is done (no cavitation). Each iteration is one LAPACK ``gbsv`` (banded LU with
    partial pivoting) on the matrix written straight into its band storage.
    """
    n = len(f)
    nz = band.nz
    width = 3 * nz + 1
    act = np.zeros(n, dtype=bool) if active is None else active.copy()
    if not clip:
        act[:] = False
    tol = 1e-13 * (np.abs(f).max() + 1e-300)
    full = np.zeros(n * width)  # the matrix with every row kept
    full[band.diag_flat] = diag
    full[band.ent_flat] = -off.ravel()[band.ent_src]
    for it in range(1, max_iter + 1):
        work = full.copy()
        if act.any():  # cavitated rows: p = 0
            work[band.diag_flat[act]] = 1.0
            work[band.ent_flat[act[band.ent_row]]] = 0.0
        rhs = np.where(act, 0.0, f)
        _, _, p, info = _gbsv()(
            nz, nz, work.reshape(n, width).T, rhs, overwrite_ab=True, overwrite_b=True
        )
        if info != 0:
            raise np.linalg.LinAlgError(f"banded film matrix: LAPACK gbsv info = {info}")
        if not clip:
            return p, act, it
        pe = np.append(p, 0.0)
        lam = diag * p - np.einsum("kn,kn->n", off, pe[nb]) - f
        new = (lam - diag * p) > tol
        if np.array_equal(new, act):
            return np.maximum(p, 0.0), act, it
        act = new
    raise _no_lcp_convergence(max_iter)


@lru_cache(maxsize=1)
def _gbsv():
    """LAPACK's double-precision ``gbsv``, the routine ``scipy.linalg.solve_banded`` calls."""
    from scipy.linalg import get_lapack_funcs

    return get_lapack_funcs(("gbsv",), (np.zeros((1, 1)), np.zeros(1)))[0]


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
    fa = mesh.fast
    h_node, g_th, h_c, g_ze, compact = _faces(mesh, q, mubar)
    m = len(mesh.theta) - 1
    n = len(mesh.zeta) - 1
    if compact:  # the face values are the same along ζ: gather by node i
        i, iw = mesh.unk_i, fa.unk_iw
        g_e, g_w, hc_e, hc_w = g_th[i], g_th[iw], h_c[i], h_c[iw]
        g_n = g_s = g_ze[i]
    else:
        g_e, g_w = np.take(g_th, fa.ij_th), np.take(g_th, fa.iwj_th)
        hc_e, hc_w = np.take(h_c, fa.ij_th), np.take(h_c, fa.iwj_th)
        g_n, g_s = np.take(g_ze, fa.ij_ze), np.take(g_ze, fa.ijs_ze)
    dzw = fa.dzw_u
    a_e = g_e * dzw / mesh.dth
    a_w = g_w * dzw / mesh.dth
    a_n = np.where(fa.north, g_n, 0.0) * mesh.dth / mesh.dze
    a_s = g_s * mesh.dth / mesh.dze
    diag = a_e + a_w + a_n + a_s  # includes the conductances to ambient-pressure neighbours
    n_unk = len(diag)
    hdot = qdot @ fa.phi_u
    rhs = -6.0 * omega * (hc_e - hc_w) * dzw - 12.0 * hdot * mesh.w_area

    if not mesh.periodic:
        off = np.where(fa.has_nb, np.stack([a_e, a_w, a_n, a_s]), 0.0)
        p, act, iters = _lcp_banded(
            diag, off, mesh.neighbours, fa.band, rhs, active, clip=cavitation == "swift_stieber"
        )
        if cavitation == "half_sommerfeld":
            p = np.maximum(p, 0.0)
    else:
        data = [diag]
        for coef, (_, _, mask) in zip((a_e, a_w, a_n, a_s), mesh.slots[1:], strict=True):
            data.append(-coef[mask])
        csc = fa.csc
        amat = sp.csc_array(
            (np.concatenate(data)[csc.perm], csc.rows, csc.indptr), shape=(n_unk, n_unk)
        )
        if cavitation == "swift_stieber":
            p, act, iters = _lcp_active_set(amat, csc, rhs, active)
        else:
            p = splu(amat).solve(rhs)
            if cavitation == "half_sommerfeld":
                p = np.maximum(p, 0.0)
            act, iters = np.zeros(n_unk, dtype=bool), 1
    if work is not None:
        work.film_solves += 1
        work.factorizations += iters

    scale = mu_ref * (radius / clearance) ** 2  # Pa per unit P
    pgrid = np.zeros((m + 1, n + 1))
    np.put(pgrid, fa.ij_th, p)
    if mesh.periodic:
        pgrid[m] = pgrid[0]
    # generalised forces (both halves)
    forces = 2.0 * scale * radius**2 * (fa.phi_u @ (p * mesh.w_area))
    return PadFilm(
        theta=mesh.theta,
        z=mesh.zeta * radius,
        pressure=scale * pgrid,
        film=clearance * _full_film(mesh, h_node),
        forces=forces,
        active=act,
        iterations=iters,
        _side_flow=partial(
            _side_flow, a_s[fa.first_row], p[fa.first_row], rhs[fa.first_row], radius, clearance
        ),
        _friction_power=partial(
            _friction_power, mesh, pgrid, h_node, mubar, omega, mu_ref, radius, clearance
        ),
    )


def _side_flow(a_s: NDArray, p: NDArray, rhs: NDArray, radius: float, clearance: float) -> float:
    """Side flow (m³/s) out of both ends: the flux through the faces j = 1/2 plus the net
    Couette and squeeze source of the half cell between them and the edge (second order in
    Δζ). ``a_s``, ``p``, ``rhs``: the conductances to the edge, the pressures and the sources
    of the unknowns next to the edge (j = 1)."""
    first = p > 0.0
    return (
        2.0
        * clearance
        * radius**2
        / 12.0
        * float(np.sum(a_s[first] * p[first]) + 0.5 * np.sum(rhs[first]))
    )


def _friction_power(
    mesh: _Mesh,
    pgrid: NDArray,
    h_node: NDArray,
    mubar: NDArray | None,
    omega: float,
    mu_ref: float,
    radius: float,
    clearance: float,
) -> float:
    """Friction power (W), full-film shear on the pad; ∂P/∂θ central inside, one-sided at the
    ends of a non-periodic pad."""
    m = len(mesh.theta) - 1
    dp_dth = np.empty_like(pgrid)
    dp_dth[1:-1] = (pgrid[2:] - pgrid[:-2]) / (2.0 * mesh.dth)
    if mesh.periodic:
        dp_dth[0] = dp_dth[-1] = (pgrid[1] - pgrid[m - 1]) / (2 * mesh.dth)
    else:
        dp_dth[0] = (pgrid[1] - pgrid[0]) / mesh.dth
        dp_dth[-1] = (pgrid[-1] - pgrid[-2]) / mesh.dth
    h_full = _full_film(mesh, h_node)
    couette = omega / h_full if mubar is None else mubar * omega / h_full
    dens = omega * (couette + 0.5 * h_full * dp_dth)
    fa = mesh.fast
    power = 2.0 * mu_ref * radius**4 / clearance * float(fa.wt @ dens @ fa.wz)
    return abs(power)


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
