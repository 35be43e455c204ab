"""The pad solve's precomputed indices, band storage and direct LAPACK call
(gearrotor.bearings.reynolds.solve_pad) against a straightforward reference: the same
discretisation written plainly, with the face values gathered by (i, j), the band matrix
filled diagonal by diagonal and solved by ``scipy.linalg.solve_banded``, and the side flow and
friction power from ``np.gradient``. The two must agree bit for bit (np.array_equal): the fast
path only moves work out of the call (index arrays per grid), takes powers of the two distinct
films of a pocketed pad instead of every quadrature point's, and calls the LAPACK routine
(``gbsv``) that ``solve_banded`` calls itself; a periodic film's sparse blocks are built from
the stored pattern instead of by SciPy's indexing.
"""

import math
from pathlib import Path

import numpy as np
import pytest
import scipy.sparse as sp
from scipy.linalg import solve_banded
from scipy.sparse.linalg import splu

from gearrotor.bearings import Grid, load_bearing
from gearrotor.bearings.geometry import plain, tilting_pad
from gearrotor.bearings.reynolds import (
    _GAUSS_W,
    _along_theta,
    _free_block,
    _viscosity,
    pad_mesh,
    solve_pad,
)

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "bearings"
DEG = math.pi / 180.0


def _faces_ref(mesh, q, mubar):
    h_node = mesh.h0_node + np.tensordot(q, mesh.phi_node, axes=1)
    h_q = mesh.h0_q + np.tensordot(q, mesh.phi_q, axes=1)
    n1 = len(mesh.zeta)
    if mesh.pocket_q is None:
        if mubar is None:
            inv3 = _GAUSS_W @ (h_q**-3).T
            inv2 = _GAUSS_W @ (h_q**-2).T
            g_th = np.repeat((1.0 / inv3)[:, None], n1, axis=1)
            h_c = np.repeat((inv2 / inv3)[:, None], n1, axis=1)
            g_ze = np.repeat((h_node**3)[:, None], n1 - 1, axis=1)
        else:
            mu_q = _along_theta(mubar)
            inv3 = np.einsum("g,mgn->mn", _GAUSS_W, mu_q * (h_q**-3)[:, :, None])
            inv2 = np.einsum("g,mgn->mn", _GAUSS_W, mu_q * (h_q**-2)[:, :, None])
            g_th = 1.0 / inv3
            h_c = inv2 / inv3
            g_ze = (h_node**3)[:, None] / (0.5 * (mubar[:, 1:] + mubar[:, :-1]))
        return np.repeat(h_node[:, None], n1, axis=1), g_th, h_c, g_ze
    h_full = h_node[:, None] + mesh.pocket_node
    h_c = mesh.h0_c + np.tensordot(q, mesh.phi_c, axes=1)
    hq = h_q[:, :, None, None] + mesh.pocket_q
    hzq = h_c[:, :, None, None] + mesh.pocket_zq
    if mubar is None:
        inv3 = np.einsum("g,mgnz->mnz", _GAUSS_W, hq**-3)
        inv2 = np.einsum("g,mgnz->mnz", _GAUSS_W, hq**-2)
        g_ze = np.einsum("t,mtn->mn", _GAUSS_W, 1.0 / (hzq**-3 @ _GAUSS_W))
    else:
        mu_q = _along_theta(mubar)[:, :, :, None]
        inv3 = np.einsum("g,mgnz->mnz", _GAUSS_W, mu_q * hq**-3)
        inv2 = np.einsum("g,mgnz->mnz", _GAUSS_W, mu_q * hq**-2)
        mu_z = mubar[:, :-1, None] + np.array([0.5 - math.sqrt(15.0) / 10.0, 0.5, 0.5 + math.sqrt(15.0) / 10.0]) * (mubar[:, 1:] - mubar[:, :-1])[:, :, None]  # fmt: skip # noqa: E501
        g_ze = np.einsum("t,mtn->mn", _GAUSS_W, 1.0 / ((mu_z[:, None, :, :] * hzq**-3) @ _GAUSS_W))
    return h_full, (1.0 / inv3) @ _GAUSS_W, (inv2 / inv3) @ _GAUSS_W, g_ze


def _lcp_banded_ref(diag, off, nb, nz, f, active, clip):
    n = len(f)
    act = np.zeros(n, dtype=bool) if active is None else active.copy()
    if not clip:
        act[:] = False
    tol = 1e-13 * (np.abs(f).max() + 1e-300)
    ab = np.zeros((2 * nz + 1, n))
    for it in range(1, 61):
        keep = ~act
        ab[:] = 0.0
        ab[nz] = np.where(keep, diag, 1.0)
        for c, (o, nbr) in enumerate(zip((nz, -nz, 1, -1), nb, strict=True)):
            rows = np.nonzero(keep & (nbr < n))[0]
            ab[nz - o, rows + o] = -off[c, rows]
        p = solve_banded((nz, nz), ab, np.where(keep, f, 0.0), check_finite=False)
        if not clip:
            return p, act, it
        pe = np.append(p, 0.0)
        lam = diag * p - np.einsum("kn,kn->n", off, pe[nb]) - f
        new = (lam - diag * p) > tol
        if np.array_equal(new, act):
            return np.maximum(p, 0.0), act, it
        act = new
    raise AssertionError("no convergence")


def _lcp_active_set_ref(a, f, active):
    n = len(f)
    d = a.diagonal()
    act = np.zeros(n, dtype=bool) if active is None else active.copy()
    tol = 1e-13 * (np.abs(f).max() + 1e-300)
    a_csc = a.tocsc()
    for it in range(1, 61):
        free = ~act
        p = np.zeros(n)
        if free.any():
            sub = a_csc[free][:, free]
            p[free] = splu(sub.tocsc(), permc_spec="MMD_AT_PLUS_A").solve(f[free])
        lam = a @ p - f
        new = (lam - d * p) > tol
        if np.array_equal(new, act):
            return np.maximum(p, 0.0), act, it
        act = new
    raise AssertionError("no convergence")


def _solve_ref(mesh, q, qdot, omega, viscosity, radius, clearance, cavitation, active):
    """The pad solve as it was written before the fast path (every quantity per call)."""
    mu_ref, mubar = _viscosity(mesh, viscosity)
    h_full, g_th, h_c, g_ze = _faces_ref(mesh, q, mubar)
    m = len(mesh.theta) - 1
    i, j = mesh.unk_i, mesh.unk_j
    iw = (i - 1) % m if mesh.periodic else i - 1
    dzw = mesh.dzw[j]
    a_e = g_th[i, j] * dzw / mesh.dth
    a_w = g_th[iw, j] * dzw / mesh.dth
    n = len(mesh.zeta) - 1
    a_n = np.where(j < n, g_ze[i, np.minimum(j, n - 1)], 0.0) * mesh.dth / mesh.dze
    a_s = g_ze[i, j - 1] * mesh.dth / mesh.dze
    diag = a_e + a_w + a_n + a_s
    n_unk = len(i)
    hdot = qdot @ mesh.phi_node[:, i]
    rhs = -6.0 * omega * (h_c[i, j] - h_c[iw, j]) * dzw - 12.0 * hdot * mesh.w_area
    if not mesh.periodic:
        off = np.where(mesh.neighbours < n_unk, np.stack([a_e, a_w, a_n, a_s]), 0.0)
        clip = cavitation == "swift_stieber"
        p, act, iters = _lcp_banded_ref(diag, off, mesh.neighbours, n, rhs, active, clip)
        if cavitation == "half_sommerfeld":
            p = np.maximum(p, 0.0)
    else:
        data = [diag] + [
            -coef[mask]
            for coef, (_, _, mask) in zip((a_e, a_w, a_n, a_s), mesh.slots[1:], strict=True)
        ]
        amat = sp.csr_matrix((np.concatenate(data), (mesh.rows, mesh.cols)), shape=(n_unk, n_unk))
        if cavitation == "swift_stieber":
            p, act, iters = _lcp_active_set_ref(amat, rhs, active)
        else:
            p = splu(amat.tocsc()).solve(rhs)
            if cavitation == "half_sommerfeld":
                p = np.maximum(p, 0.0)
            act, iters = np.zeros(n_unk, dtype=bool), 1
    scale = mu_ref * (radius / clearance) ** 2
    pgrid = np.zeros((m + 1, n + 1))
    pgrid[i, j] = p
    if mesh.periodic:
        pgrid[m] = pgrid[0]
    forces = 2.0 * scale * radius**2 * (mesh.phi_node[:, i] @ (p * mesh.w_area))
    first = (j == 1) & (p > 0.0)
    side = 2.0 * clearance * radius**2 / 12.0 * float(np.sum(a_s[first] * p[first]) + 0.5 * np.sum(rhs[first]))  # fmt: skip # noqa: E501
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
    return {
        "pressure": scale * pgrid,
        "film": clearance * h_full,
        "forces": forces,
        "side_flow": side,
        "friction_power": abs(power),
        "active": act,
        "iterations": iters,
    }


def _cases():
    dam = load_bearing(EXAMPLES / "pinion_3lobe_dam.toml")
    tilt = load_bearing(EXAMPLES / "tilting_4pad.toml")
    flexible = tilting_pad(
        0.1, 0.07, 78.44e-6, 0.0277, [45 * DEG, 135 * DEG], 75 * DEG, 0.47, 0.5,
        inertia=2e-4, mass=0.5, thickness=0.02, pivot_stiffness=5e8,
    )  # fmt: skip
    return [
        ("pressure dam", dam.bearing, dam.options.grid, dam.speed, [0.1, -0.4, 0.0, 0.0]),
        ("tilting pad", tilt.bearing, tilt.options.grid, tilt.speed, [0.2, -0.3, 0.1, 0.0]),
        ("flexible pivot", flexible, Grid(20, 6), 420.0, [0.1, -0.3, -0.05, 0.08]),
        ("periodic", plain(0.1, 0.05, 100e-6, 0.02), Grid(16, 5), 800.0, [0.3, -0.5, 0, 0]),
    ]


@pytest.mark.parametrize("cavitation", ["swift_stieber", "half_sommerfeld", "none"])
@pytest.mark.parametrize("case", _cases(), ids=lambda c: c[0])
def test_fast_pad_solve_equals_the_reference_bit_for_bit(case, cavitation):
    name, b, grid, speed, q = case
    q = np.array(q)
    qdot = np.array([0.02, -0.01, 0.005, 0.003]) * speed
    for pad in b.pads:
        mesh = pad_mesh(pad, b.radius, b.length, b.clearance, grid)
        tt, zz = np.meshgrid(mesh.theta, mesh.zeta, indexing="ij")
        field = b.viscosity * (1.0 + 0.3 * np.sin(tt) * np.cos(zz / zz.max()))
        for visc in (b.viscosity, field):
            active = None
            for qq, qd, om in ((q, 0 * qdot, speed), (0.95 * q, qdot, speed), (q, qdot, -speed)):
                kw = dict(viscosity=visc, radius=b.radius, clearance=b.clearance)
                ref = _solve_ref(mesh, qq, qd, om, cavitation=cavitation, active=active, **kw)
                fast = solve_pad(mesh, qq, qd, om, cavitation=cavitation, active=active, **kw)
                for key, value in ref.items():
                    assert np.array_equal(getattr(fast, key), value), (name, key)
                active = fast.active  # the next state starts warm, as Newton's steps do


def test_free_block_is_scipys_submatrix():
    """The periodic film's free block, built from the stored pattern, is the matrix SciPy's
    ``a[free][:, free]`` gives: the same entries in the same order (so the same sparse LU)."""
    mesh = pad_mesh(plain(0.1, 0.05, 100e-6, 0.02).pads[0], 0.05, 0.05, 100e-6, Grid(12, 4))
    n = len(mesh.unk_i)
    rng = np.random.default_rng(7)
    data = rng.uniform(0.5, 2.0, len(mesh.rows))
    a = sp.csr_matrix((data, (mesh.rows, mesh.cols)), shape=(n, n)).tocsc()
    csc = mesh.fast.csc
    assert np.array_equal(a.data, data[csc.perm])
    for share in (1.0, 0.8, 0.5, 0.1):
        free = rng.uniform(size=n) < share
        free[rng.integers(n)] = True
        ref = a[free][:, free].tocsc()
        got = _free_block(csc, data[csc.perm], free)
        for attr in ("data", "indices", "indptr"):
            assert np.array_equal(getattr(got, attr), getattr(ref, attr)), attr
