"""Compiled (numba) kernels of the transient: forces, accelerations, RK4 loops.

No objects, only arrays; every work array is allocated by the caller once per run, the step loops
allocate nothing. Index conventions: ``sel`` indices address the vector of DOFs that carry
nonlinear forces (gathered from q or from Φ_sel η); ``−1`` marks an inactive DOF.

Parameter packs (all float64 / int64):

* meshes: ``m_sel (nm,12)``, ``m_w (nm,2,12)`` (drive line w, back-flank line w_b),
  ``m_par (nm,8)`` = kg, ka, b, c, teeth, kg_lin
  (stiffness already in the linear part on the drive line, subtracted), c_lin, kgb_lin (the
  same on the back line: the exact-linear scheme's operators with the back flank touching);
  ``m_ab (nm,S,2)``, ``m_ns (nm,)``;
  tables ``m_tptr (nm+1)``, ``m_tphi``, ``m_tk``; transmission error ``m_te (nm,Se,2)``,
  ``m_nte (nm,)``;
* unbalances: ``u_sel (nu,3)`` (x, y, θz), ``u_me``, ``u_ph``;
* torques: ``t_sel``, ``t_par (nt,3)`` = value, exponent, reference speed; table ``t_ptr``,
  ``t_time``, ``t_vals``;
* speed-dependent bearings: ``b_sel (nb,4)``, ``b_shaft``, table ``b_ptr``, ``b_speed``,
  ``b_coef (·,8)``, reference coefficients ``b_ref (nb,8)`` already in the linear part;
* drives and loads (``[torsional]``): one tuple ``drv`` = (``l_sel``, sense σ, sign, state
  (nl,2), then the arrays of :meth:`TorqueLaws.arrays`), evaluated by
  :func:`..torsional.drive_laws.law_torque` (the torsional transient's laws).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from ..jit import configure_cache
from ..torsional.drive_laws import advance_state, law_torque

configure_cache()  # before the first @njit(cache=True): numba's cache outside the package

__all__ = [
    "mesh_eval",
    "nl_forces",
    "rk4_physical",
    "rk4_modal",
    "etd_modal",
    "etd_coefficients",
    "outputs_kernel",
    "STATUS_OK",
    "STATUS_NONFINITE",
    "STATUS_BLOWUP",
]

STATUS_OK = 0
STATUS_NONFINITE = 1
STATUS_BLOWUP = 2

_CACHE = True
# reassociation/contraction only: no 'nnan'/'ninf', so divergence checks stay valid
_FAST = {"reassoc", "contract", "arcp", "nsz"}
# the exponential scheme without 'reassoc': with it, the code numba compiled in a process and
# the code it loaded from its cache gave different round-off (1e-13 relative without backlash,
# ~1 % in the chaotic impact metrics with backlash), so a rerun did not reproduce a result
_FAST_ETD = _FAST - {"reassoc"}


@njit(cache=_CACHE)
def _interp(x, xp, fp, lo, hi):
    """Linear interpolation in xp[lo:hi] (held at the ends)."""
    if x <= xp[lo]:
        return fp[lo]
    if x >= xp[hi - 1]:
        return fp[hi - 1]
    a, b = lo, hi - 1
    while b - a > 1:
        mid = (a + b) // 2
        if xp[mid] <= x:
            a = mid
        else:
            b = mid
    f = (x - xp[a]) / (xp[b] - xp[a])
    return fp[a] + f * (fp[b] - fp[a])


@njit(cache=_CACHE)
def mesh_deflections(k, qs, vs, m_sel, m_w, m_par, m_te, m_nte):
    """Mesh k: (δ, δ̇, δ_b, δ̇_b, φ_m): the deflections and rates along the drive line w
    (δ = w·q) and the back-flank line w_b, with the transmission error (δ → δ − e on the drive
    line, δ_b → δ_b + e on the back line), and the mesh angle φ_m = N θz of the pinion node."""
    delta = 0.0
    ddelta = 0.0
    db = 0.0
    ddb = 0.0
    for j in range(12):
        i = m_sel[k, j]
        if i >= 0:
            delta += m_w[k, 0, j] * qs[i]
            ddelta += m_w[k, 0, j] * vs[i]
            db += m_w[k, 1, j] * qs[i]
            ddb += m_w[k, 1, j] * vs[i]
    teeth = m_par[k, 4]
    it = m_sel[k, 5]
    phi = teeth * qs[it] if it >= 0 else 0.0
    dphi = teeth * vs[it] if it >= 0 else 0.0
    # transmission error: δ → δ − e on the drive line, δ_b → δ_b + e on the back line
    for s in range(m_nte[k]):
        sp = (s + 1) * phi
        c, sn = np.cos(sp), np.sin(sp)
        e = m_te[k, s, 0] * c + m_te[k, s, 1] * sn
        de = (s + 1) * dphi * (-m_te[k, s, 0] * sn + m_te[k, s, 1] * c)
        delta -= e
        ddelta -= de
        db += e
        ddb += de
    return delta, ddelta, db, ddb, phi


@njit(cache=_CACHE)
def mesh_eval(k, qs, vs, m_sel, m_w, m_par, m_ab, m_ns, m_tptr, m_tphi, m_tk, m_te, m_nte):
    """Mesh k: returns (F_d, F_b, stiffness, δ_e, δ̇_e, state, φ_m).

    ``m_w[k, 0]`` is the drive line w (δ = w·q), ``m_w[k, 1]`` the back-flank line w_b
    (``−w`` for SPEC 2.4's law, the mirrored line of action otherwise). F_d ≥ 0 acts along
    −w, F_b ≥ 0 along −w_b (both N, damping included while in contact); state +1 drive,
    −1 back, +2 both flanks, 0 separated."""
    delta, ddelta, db, ddb, phi = mesh_deflections(k, qs, vs, m_sel, m_w, m_par, m_te, m_nte)
    lo, hi = m_tptr[k], m_tptr[k + 1]
    if hi > lo:
        ph = phi - 2.0 * np.pi * np.floor(phi / (2.0 * np.pi))
        stiff = _interp(ph, m_tphi, m_tk, lo, hi)
    else:
        stiff = m_par[k, 0]
        ka2 = 2.0 * m_par[k, 1]
        ns = m_ns[k]
        if ns > 0:
            s1, c1 = np.sin(phi), np.cos(phi)
            sn, cn = s1, c1
            for s in range(ns):
                stiff += ka2 * (m_ab[k, s, 0] * sn + m_ab[k, s, 1] * cn)
                sn, cn = sn * c1 + cn * s1, cn * c1 - sn * s1
    b = m_par[k, 2]
    state = 0
    Fd = 0.0
    Fb = 0.0
    if delta > b:
        state = 1
        Fd = stiff * (delta - b) + m_par[k, 3] * ddelta
    if db > b:
        state = 2 if state == 1 else -1
        Fb = stiff * (db - b) + m_par[k, 3] * ddb
    return Fd, Fb, stiff, delta, ddelta, state, phi


@njit(cache=_CACHE)
def nl_forces(
    t,
    qs,
    vs,
    Om,
    fs,
    m_sel,
    m_w,
    m_par,
    m_ab,
    m_ns,
    m_tptr,
    m_tphi,
    m_tk,
    m_te,
    m_nte,
    u_sel,
    u_me,
    u_ph,
    t_sel,
    t_par,
    t_ptr,
    t_time,
    t_vals,
    b_sel,
    b_shaft,
    b_ptr,
    b_speed,
    b_coef,
    b_ref,
    drv,
):
    """Generalised forces on the ``sel`` DOFs (overwrites fs): meshes (minus their linear part
    kg_lin δ + c_lin δ̇), unbalance centrifugal part m e θ̇² r_u, external torques,
    speed-dependent bearings (minus their reference coefficients), drives and loads.

    A synchronous motor pulls into step at the first evaluation with its slip at or below the
    pull-in slip (its state in ``drv`` changes there, within the step: an event located to
    one step, as in the torsional transient)."""
    for i in range(fs.shape[0]):
        fs[i] = 0.0
    for k in range(m_sel.shape[0]):
        Fd, Fb, stiff, delta, ddelta, state, phi = mesh_eval(
            k, qs, vs, m_sel, m_w, m_par, m_ab, m_ns, m_tptr, m_tphi, m_tk, m_te, m_nte
        )
        # the linear part kept in the modal basis uses the geometric δ (no TE)
        dl = 0.0
        vl = 0.0
        for j in range(12):
            i = m_sel[k, j]
            if i >= 0:
                dl += m_w[k, 0, j] * qs[i]
                vl += m_w[k, 0, j] * vs[i]
        Fd -= m_par[k, 5] * dl + m_par[k, 6] * vl
        if m_par[k, 7] != 0.0:
            bl = 0.0
            for j in range(12):
                i = m_sel[k, j]
                if i >= 0:
                    bl += m_w[k, 1, j] * qs[i]
            Fb -= m_par[k, 7] * bl
        for j in range(12):
            i = m_sel[k, j]
            if i >= 0:
                fs[i] -= Fd * m_w[k, 0, j] + Fb * m_w[k, 1, j]
    for u in range(u_sel.shape[0]):
        it = u_sel[u, 2]
        th = qs[it] + u_ph[u]
        w2 = u_me[u] * vs[it] * vs[it]
        fs[u_sel[u, 0]] += w2 * np.cos(th)
        fs[u_sel[u, 1]] += w2 * np.sin(th)
    for j in range(t_sel.shape[0]):
        lo, hi = t_ptr[j], t_ptr[j + 1]
        val = t_par[j, 0] if hi == lo else _interp(t, t_time, t_vals, lo, hi)
        if t_par[j, 1] != 0.0:
            val *= (abs(vs[t_sel[j]]) / t_par[j, 2]) ** t_par[j, 1]
        fs[t_sel[j]] += val
    for j in range(b_sel.shape[0]):
        lo, hi = b_ptr[j], b_ptr[j + 1]
        w = abs(Om[b_shaft[j]])
        kxx = _interp(w, b_speed, b_coef[:, 0], lo, hi) - b_ref[j, 0]
        kxy = _interp(w, b_speed, b_coef[:, 1], lo, hi) - b_ref[j, 1]
        kyx = _interp(w, b_speed, b_coef[:, 2], lo, hi) - b_ref[j, 2]
        kyy = _interp(w, b_speed, b_coef[:, 3], lo, hi) - b_ref[j, 3]
        cxx = _interp(w, b_speed, b_coef[:, 4], lo, hi) - b_ref[j, 4]
        cxy = _interp(w, b_speed, b_coef[:, 5], lo, hi) - b_ref[j, 5]
        cyx = _interp(w, b_speed, b_coef[:, 6], lo, hi) - b_ref[j, 6]
        cyy = _interp(w, b_speed, b_coef[:, 7], lo, hi) - b_ref[j, 7]
        x, y = qs[b_sel[j, 0]], qs[b_sel[j, 1]]
        vx, vy = vs[b_sel[j, 0]], vs[b_sel[j, 1]]
        if b_sel[j, 2] >= 0:
            x -= qs[b_sel[j, 2]]
            y -= qs[b_sel[j, 3]]
            vx -= vs[b_sel[j, 2]]
            vy -= vs[b_sel[j, 3]]
        fx = -(kxx * x + kxy * y + cxx * vx + cxy * vy)
        fy = -(kyx * x + kyy * y + cyx * vx + cyy * vy)
        fs[b_sel[j, 0]] += fx
        fs[b_sel[j, 1]] += fy
        if b_sel[j, 2] >= 0:
            fs[b_sel[j, 2]] -= fx
            fs[b_sel[j, 3]] -= fy
    (l_sel, l_rot, l_sign, l_state, l_par, lt_ptr, lt_x, lt_y, lt_z, lv_ptr, lv_t, lv_f, ls_ptr,
     ls_t, ls_f) = drv  # fmt: skip
    for j in range(l_sel.shape[0]):
        i = l_sel[j]
        th = l_rot[j] * qs[i]
        om = l_rot[j] * vs[i]
        advance_state(j, t, th, om, l_state, l_par)
        tq = law_torque(
            j, t, th, om, l_state, l_par, lt_ptr, lt_x, lt_y, lt_z, lv_ptr, lv_t, lv_f, ls_ptr,
            ls_t, ls_f,
        )  # fmt: skip
        fs[i] += l_rot[j] * l_sign[j] * tq


@njit(cache=_CACHE)
def _lu_solve(A, b, piv):
    """Solve A x = b in place (b ← x) by Gaussian elimination with partial pivoting; A is
    overwritten. Returns False when A is singular."""
    n = A.shape[0]
    for k in range(n):
        p = k
        big = abs(A[k, k])
        for i in range(k + 1, n):
            if abs(A[i, k]) > big:
                big = abs(A[i, k])
                p = i
        if big == 0.0:
            return False
        piv[k] = p
        if p != k:
            for j in range(n):
                A[k, j], A[p, j] = A[p, j], A[k, j]
            b[k], b[p] = b[p], b[k]
        for i in range(k + 1, n):
            f = A[i, k] / A[k, k]
            if f != 0.0:
                for j in range(k + 1, n):
                    A[i, j] -= f * A[k, j]
                b[i] -= f * b[k]
    for k in range(n - 1, -1, -1):
        s = b[k]
        for j in range(k + 1, n):
            s -= A[k, j] * b[j]
        b[k] = s / A[k, k]
    return True


# ------------------------------------------------------------------------------------------
# physical coordinates
# ------------------------------------------------------------------------------------------
@njit(cache=_CACHE)
def _csr_mv(indptr, indices, data, x, out, scale_rows, Om, row_shaft, accumulate_sign):
    """out += sign · A x (rows optionally scaled by the speed of the row's shaft)."""
    n = indptr.shape[0] - 1
    for i in range(n):
        s = 0.0
        for p in range(indptr[i], indptr[i + 1]):
            s += data[p] * x[indices[p]]
        if scale_rows:
            sh = row_shaft[i]
            s = s * Om[sh] if sh >= 0 else 0.0
        out[i] += accumulate_sign * s


@njit(cache=_CACHE)
def _msolve(perm, Lp, Li, Ld, Up, Ui, Ud, x, out, y):
    """out = M⁻¹ x with the sparse Cholesky factor of the permuted mass matrix
    ``M[perm][:, perm] = L Lᵀ`` (L rows: diagonal last; U = Lᵀ rows: diagonal first)."""
    n = perm.shape[0]
    for i in range(n):
        y[i] = x[perm[i]]
    for i in range(n):
        acc = y[i]
        d = Lp[i + 1] - 1
        for p in range(Lp[i], d):
            acc -= Ld[p] * y[Li[p]]
        y[i] = acc / Ld[d]
    for i in range(n - 1, -1, -1):
        acc = y[i]
        d = Up[i]
        for p in range(d + 1, Up[i + 1]):
            acc -= Ud[p] * y[Ui[p]]
        y[i] = acc / Ud[d]
    for i in range(n):
        out[perm[i]] = y[i]


@njit(cache=_CACHE)
def _accel_physical(t, q, v, a, P, W):
    """Accelerations of the physical model (a ← q̈). P: parameter tuple, W: work tuple.

    The low-rank implicit part M + P Qᵀ is solved by Woodbury: a = y − Z (I + QᵀZ)⁻¹ Qᵀ y with
    y = M⁻¹F and the rows of Zᵀ = (M⁻¹P)ᵀ, each nonzero only on its support (z_ptr/z_idx)."""
    (
        Kp,
        Ki,
        Kd,
        Cp,
        Ci,
        Cd,
        Gp,
        Gi,
        Gd,
        row_shaft,
        perm,
        Lp,
        Li,
        Ld,
        Up,
        Ui,
        Ud,
        a_idx,
        a_w,
        a_ptr,
        torsion_idx,
        frozen,
        reactions,
        sel,
        m_sel,
        m_w,
        m_par,
        m_ab,
        m_ns,
        m_tptr,
        m_tphi,
        m_tk,
        m_te,
        m_nte,
        u_sel,
        u_me,
        u_ph,
        t_sel,
        t_par,
        t_ptr,
        t_time,
        t_vals,
        b_sel,
        b_shaft,
        b_ptr,
        b_speed,
        b_coef,
        b_ref,
        drv,
        Minv_a,
        Minv_ux,
        Minv_uy,
        Minv_ut,
        u_full,
        z_ptr,
        z_idx,
        g_ptr,
        g_idx,
    ) = P
    (F, gq, zq, qs, vs, fs, Om, Z, S, rhs, piv, y) = W
    n = q.shape[0]
    ns = a_ptr.shape[0] - 1
    for s in range(ns):
        o = 0.0
        for p in range(a_ptr[s], a_ptr[s + 1]):
            o += a_w[p] * v[a_idx[p]]
        Om[s] = o
    for i in range(n):
        F[i] = 0.0
    _csr_mv(Kp, Ki, Kd, q, F, False, Om, row_shaft, -1.0)
    _csr_mv(Cp, Ci, Cd, v, F, False, Om, row_shaft, -1.0)
    _csr_mv(Gp, Gi, Gd, v, F, True, Om, row_shaft, -1.0)
    for i in range(sel.shape[0]):
        qs[i] = q[sel[i]]
        vs[i] = v[sel[i]]
    nl_forces(
        t,
        qs,
        vs,
        Om,
        fs,
        m_sel,
        m_w,
        m_par,
        m_ab,
        m_ns,
        m_tptr,
        m_tphi,
        m_tk,
        m_te,
        m_nte,
        u_sel,
        u_me,
        u_ph,
        t_sel,
        t_par,
        t_ptr,
        t_time,
        t_vals,
        b_sel,
        b_shaft,
        b_ptr,
        b_speed,
        b_coef,
        b_ref,
        drv,
    )
    for i in range(sel.shape[0]):
        F[sel[i]] += fs[i]
    _msolve(perm, Lp, Li, Ld, Up, Ui, Ud, F, a, y)
    if frozen:
        for i in range(torsion_idx.shape[0]):
            a[torsion_idx[i]] = 0.0
        return
    # ---- exact solve of the low-rank implicit terms (Woodbury) ----------------------------
    for i in range(n):
        gq[i] = 0.0
    _csr_mv(Gp, Gi, Gd, q, gq, False, Om, row_shaft, 0.5)  # g = ½ G q (all shafts)
    _msolve(perm, Lp, Li, Ld, Up, Ui, Ud, gq, zq, y)
    nu = u_sel.shape[0]
    per_s = 2 if reactions else 1
    r = per_s * (ns + nu)
    # rows of Zᵀ = (M⁻¹ P)ᵀ on their supports
    for s in range(ns):
        c = per_s * s
        for p in range(z_ptr[c], z_ptr[c + 1]):
            Z[c, z_idx[p]] = zq[z_idx[p]]
        if reactions:
            for p in range(z_ptr[c + 1], z_ptr[c + 2]):
                Z[c + 1, z_idx[p]] = Minv_a[s, z_idx[p]]
    for u in range(nu):
        c = per_s * (ns + u)
        th = q[u_full[u, 2]] + u_ph[u]
        sn, cs = np.sin(th), np.cos(th)
        me = u_me[u]
        for p in range(z_ptr[c], z_ptr[c + 1]):
            i = z_idx[p]
            Z[c, i] = me * (-sn * Minv_ux[u, i] + cs * Minv_uy[u, i])
        if reactions:
            for p in range(z_ptr[c + 1], z_ptr[c + 2]):
                i = z_idx[p]
                Z[c + 1, i] = me * Minv_ut[u, i]
    for row in range(r):
        rhs[row] = _qdot(row, a, q, ns, per_s, a_ptr, a_idx, a_w, g_ptr, g_idx, gq, u_full, u_ph)
        for col in range(r):
            S[row, col] = (1.0 if row == col else 0.0) + _qdot(
                row, Z[col], q, ns, per_s, a_ptr, a_idx, a_w, g_ptr, g_idx, gq, u_full, u_ph
            )
    _lu_solve(S, rhs, piv)
    for c in range(r):
        f = rhs[c]
        for p in range(z_ptr[c], z_ptr[c + 1]):
            i = z_idx[p]
            a[i] -= Z[c, i] * f


@njit(cache=_CACHE)
def _qdot(row, x, q, ns, per_s, a_ptr, a_idx, a_w, g_ptr, g_idx, gq, u_full, u_ph):
    """Q[:, row]ᵀ x for the low-rank factor Q of the implicit terms (physical model)."""
    acc = 0.0
    if row < ns * per_s:
        s = row // per_s
        if row % per_s == 0:  # Q = a_s
            for p in range(a_ptr[s], a_ptr[s + 1]):
                acc += a_w[p] * x[a_idx[p]]
        else:  # Q = g_s, nonzero on the rows of G_s
            for p in range(g_ptr[s], g_ptr[s + 1]):
                acc += gq[g_idx[p]] * x[g_idx[p]]
        return acc
    u = (row - ns * per_s) // per_s
    if (row - ns * per_s) % per_s == 0:  # Q = c_u
        return x[u_full[u, 2]]
    th = q[u_full[u, 2]] + u_ph[u]  # Q = s_u
    return -np.sin(th) * x[u_full[u, 0]] + np.cos(th) * x[u_full[u, 1]]


@njit(cache=_CACHE)
def rk4_physical(
    t0,
    dt,
    n_steps,
    q,
    v,
    save_every,
    out_idx,
    rec_q,
    rec_v,
    rec_a,
    rec_om,
    rec_t,
    rec_start,
    blowup,
    P,
    W,
    K1,
):
    """Classical RK4 on (q, q̇) for ``n_steps`` steps from t0 (q, v updated in place).

    Every ``save_every`` steps (starting with the first) the state at the step start is recorded
    at row ``rec_start + j``. Returns (status, steps done)."""
    n = q.shape[0]
    (k1q, k1v, k2q, k2v, k3q, k3v, k4q, k4v, qt, vt) = K1
    Om = W[6]
    j = rec_start
    for step in range(n_steps):
        t = t0 + step * dt
        _accel_physical(t, q, v, k1v, P, W)
        if step % save_every == 0:
            for i in range(out_idx.shape[0]):
                rec_q[j, i] = q[out_idx[i]]
                rec_v[j, i] = v[out_idx[i]]
                rec_a[j, i] = k1v[out_idx[i]]
            for s in range(Om.shape[0]):
                rec_om[j, s] = Om[s]
            rec_t[j] = t
            j += 1
            bad = False
            big = 0.0
            for i in range(n):
                if not (np.isfinite(q[i]) and np.isfinite(v[i])):
                    bad = True
            for i in range(out_idx.shape[0]):
                x = abs(rec_q[j - 1, i]) * blowup[i]
                if x > big:
                    big = x
            if bad:
                return STATUS_NONFINITE, step
            if big > 1.0:
                return STATUS_BLOWUP, step
        for i in range(n):
            k1q[i] = v[i]
            qt[i] = q[i] + 0.5 * dt * k1q[i]
            vt[i] = v[i] + 0.5 * dt * k1v[i]
        _accel_physical(t + 0.5 * dt, qt, vt, k2v, P, W)
        for i in range(n):
            k2q[i] = vt[i]
            qt[i] = q[i] + 0.5 * dt * k2q[i]
            vt[i] = v[i] + 0.5 * dt * k2v[i]
        _accel_physical(t + 0.5 * dt, qt, vt, k3v, P, W)
        for i in range(n):
            k3q[i] = vt[i]
            qt[i] = q[i] + dt * k3q[i]
            vt[i] = v[i] + dt * k3v[i]
        _accel_physical(t + dt, qt, vt, k4v, P, W)
        for i in range(n):
            k4q[i] = vt[i]
            q[i] += dt / 6.0 * (k1q[i] + 2.0 * k2q[i] + 2.0 * k3q[i] + k4q[i])
            v[i] += dt / 6.0 * (k1v[i] + 2.0 * k2v[i] + 2.0 * k3v[i] + k4v[i])
    return STATUS_OK, n_steps


# ------------------------------------------------------------------------------------------
# modal coordinates
# ------------------------------------------------------------------------------------------
@njit(cache=_CACHE, fastmath=_FAST)
def _accel_modal(t, e, de, a, P, W):
    """Modal accelerations (a ← η̈) with M_r = I. ``PhiT_sel`` is Φ_selᵀ (m, nsel); the
    stiffness is ``diag(lam)`` (the symmetric part) plus the skew part ``k_skew`` (nk, nk) on the
    ``sel`` DOFs ``k_idx``, applied as a force; work array ``Z`` (2r, m) holds the Woodbury
    factors P (rows 0..r−1) and Q (rows r..2r−1)."""
    (
        lam,
        Cr,
        Gr,
        alpha,
        Phi_sel,
        PhiT_sel,
        reactions,
        k_idx,
        k_skew,
        m_sel,
        m_w,
        m_par,
        m_ab,
        m_ns,
        m_tptr,
        m_tphi,
        m_tk,
        m_te,
        m_nte,
        u_sel,
        u_me,
        u_ph,
        t_sel,
        t_par,
        t_ptr,
        t_time,
        t_vals,
        b_sel,
        b_shaft,
        b_ptr,
        b_speed,
        b_coef,
        b_ref,
        drv,
    ) = P
    (qs, vs, fs, Om, Z, S, rhs, piv, gq) = W
    m = e.shape[0]
    ns = alpha.shape[0]
    nsel = Phi_sel.shape[0]
    for s in range(ns):
        o = 0.0
        for i in range(m):
            o += alpha[s, i] * de[i]
        Om[s] = o
    for i in range(nsel):
        x = 0.0
        y = 0.0
        for j in range(m):
            x += Phi_sel[i, j] * e[j]
            y += Phi_sel[i, j] * de[j]
        qs[i] = x
        vs[i] = y
    nl_forces(
        t,
        qs,
        vs,
        Om,
        fs,
        m_sel,
        m_w,
        m_par,
        m_ab,
        m_ns,
        m_tptr,
        m_tphi,
        m_tk,
        m_te,
        m_nte,
        u_sel,
        u_me,
        u_ph,
        t_sel,
        t_par,
        t_ptr,
        t_time,
        t_vals,
        b_sel,
        b_shaft,
        b_ptr,
        b_speed,
        b_coef,
        b_ref,
        drv,
    )
    nk = k_idx.shape[0]
    for i in range(nk):
        f = 0.0
        for j in range(nk):
            f += k_skew[i, j] * qs[k_idx[j]]
        fs[k_idx[i]] -= f
    for i in range(m):
        acc = -lam[i] * e[i]
        c0 = 0.0
        for j in range(m):
            c0 += Cr[i, j] * de[j]
        acc -= c0
        for s in range(ns):
            g1 = 0.0
            g2 = 0.0
            for j in range(m):
                g1 += Gr[s, i, j] * de[j]
                g2 += Gr[s, i, j] * e[j]
            acc -= Om[s] * g1
            gq[s, i] = 0.5 * g2
        f = 0.0
        for p in range(nsel):
            f += PhiT_sel[i, p] * fs[p]
        a[i] = acc + f
    # Woodbury on I + P Qᵀ
    nu = u_sel.shape[0]
    per_s = 2 if reactions else 1
    r = per_s * (ns + nu)
    for s in range(ns):
        c = per_s * s
        for i in range(m):
            Z[c, i] = gq[s, i]
            Z[r + c, i] = alpha[s, i]
        if reactions:
            for i in range(m):
                Z[c + 1, i] = alpha[s, i]
                Z[r + c + 1, i] = gq[s, i]
    for u in range(nu):
        c = per_s * (ns + u)
        th = qs[u_sel[u, 2]] + u_ph[u]
        sn, cs = np.sin(th), np.cos(th)
        me = u_me[u]
        ix, iy, it = u_sel[u, 0], u_sel[u, 1], u_sel[u, 2]
        for i in range(m):
            su = -sn * Phi_sel[ix, i] + cs * Phi_sel[iy, i]
            Z[c, i] = me * su
            Z[r + c, i] = Phi_sel[it, i]
            if reactions:
                Z[c + 1, i] = me * Phi_sel[it, i]
                Z[r + c + 1, i] = su
    for row in range(r):
        acc = 0.0
        for i in range(m):
            acc += Z[r + row, i] * a[i]
        rhs[row] = acc
        for col in range(r):
            acc = 1.0 if row == col else 0.0
            for i in range(m):
                acc += Z[r + row, i] * Z[col, i]
            S[row, col] = acc
    _lu_solve(S, rhs, piv)
    for c in range(r):
        f = rhs[c]
        for i in range(m):
            a[i] -= Z[c, i] * f


@njit(cache=_CACHE, fastmath=_FAST)
def rk4_modal(
    t0,
    dt,
    n_steps,
    e,
    de,
    save_every,
    Phi_out,
    rec_q,
    rec_v,
    rec_a,
    rec_om,
    rec_t,
    rec_start,
    blowup,
    P,
    W,
    K1,
):
    """Classical RK4 on the reduced modal system; records physical output DOFs Φ_out η."""
    m = e.shape[0]
    (k1q, k1v, k2q, k2v, k3q, k3v, k4q, k4v, qt, vt) = K1
    Om = W[3]
    j = rec_start
    nout = Phi_out.shape[0]
    for step in range(n_steps):
        t = t0 + step * dt
        _accel_modal(t, e, de, k1v, P, W)
        if step % save_every == 0:
            big = 0.0
            bad = False
            for i in range(nout):
                x = 0.0
                y = 0.0
                z = 0.0
                for c in range(m):
                    x += Phi_out[i, c] * e[c]
                    y += Phi_out[i, c] * de[c]
                    z += Phi_out[i, c] * k1v[c]
                rec_q[j, i] = x
                rec_v[j, i] = y
                rec_a[j, i] = z
                if not (np.isfinite(x) and np.isfinite(y)):
                    bad = True
                if abs(x) * blowup[i] > big:
                    big = abs(x) * blowup[i]
            for s in range(Om.shape[0]):
                rec_om[j, s] = Om[s]
            rec_t[j] = t
            j += 1
            if bad:
                return STATUS_NONFINITE, step
            if big > 1.0:
                return STATUS_BLOWUP, step
        for i in range(m):
            k1q[i] = de[i]
            qt[i] = e[i] + 0.5 * dt * k1q[i]
            vt[i] = de[i] + 0.5 * dt * k1v[i]
        _accel_modal(t + 0.5 * dt, qt, vt, k2v, P, W)
        for i in range(m):
            k2q[i] = vt[i]
            qt[i] = e[i] + 0.5 * dt * k2q[i]
            vt[i] = de[i] + 0.5 * dt * k2v[i]
        _accel_modal(t + 0.5 * dt, qt, vt, k3v, P, W)
        for i in range(m):
            k3q[i] = vt[i]
            qt[i] = e[i] + dt * k3q[i]
            vt[i] = de[i] + dt * k3v[i]
        _accel_modal(t + dt, qt, vt, k4v, P, W)
        for i in range(m):
            k4q[i] = vt[i]
            e[i] += dt / 6.0 * (k1q[i] + 2.0 * k2q[i] + 2.0 * k3q[i] + k4q[i])
            de[i] += dt / 6.0 * (k1v[i] + 2.0 * k2v[i] + 2.0 * k3v[i] + k4v[i])
    return STATUS_OK, n_steps


# ------------------------------------------------------------------------------------------
# outputs from recorded states
# ------------------------------------------------------------------------------------------
@njit(cache=_CACHE)
def outputs_kernel(
    rec_q, rec_v, m_sel, m_w, m_par, m_ab, m_ns, m_tptr, m_tphi, m_tk, m_te, m_nte, mesh_out
):
    """Per record and mesh: F = F_d − F_b (N), k (N/m), δ_e (m), δ̇_e, state, φ_m, F_d, F_b
    into mesh_out (nt, nm, 8). ``m_sel`` indexes the recorded output DOFs here."""
    for j in range(rec_q.shape[0]):
        for k in range(m_sel.shape[0]):
            Fd, Fb, stiff, delta, ddelta, state, phi = mesh_eval(
                k,
                rec_q[j],
                rec_v[j],
                m_sel,
                m_w,
                m_par,
                m_ab,
                m_ns,
                m_tptr,
                m_tphi,
                m_tk,
                m_te,
                m_nte,
            )
            mesh_out[j, k, 0] = Fd - Fb
            mesh_out[j, k, 6] = Fd
            mesh_out[j, k, 7] = Fb
            mesh_out[j, k, 1] = stiff
            mesh_out[j, k, 2] = delta
            mesh_out[j, k, 3] = ddelta
            mesh_out[j, k, 4] = state
            mesh_out[j, k, 5] = phi


# ------------------------------------------------------------------------------------------
# modal coordinates, linear part exact (integrating factor), contact changes located
# ------------------------------------------------------------------------------------------
@njit(cache=_CACHE)
def mesh_gaps(k, qs, vs, m_sel, m_w, m_par, m_te, m_nte, g):
    """Gap functions of mesh k into g[0:4]: δ − b, δ̇ (drive line), δ_b − b, δ̇_b (back line),
    with the transmission error, as :func:`mesh_eval` forms them (> 0: that flank touches)."""
    delta, ddelta, db, ddb, _ = mesh_deflections(k, qs, vs, m_sel, m_w, m_par, m_te, m_nte)
    b = m_par[k, 2]
    g[0] = delta - b
    g[1] = ddelta
    g[2] = db - b
    g[3] = ddb


@njit(cache=_CACHE, fastmath=_FAST)
def _gaps_of(e, de, Phi_sel, qs, vs, m_sel, m_w, m_par, m_te, m_nte, G):
    """G[k, 0:4] = :func:`mesh_gaps` of every mesh at the modal state (e, de)."""
    m = e.shape[0]
    for i in range(Phi_sel.shape[0]):
        x = 0.0
        y = 0.0
        for j in range(m):
            x += Phi_sel[i, j] * e[j]
            y += Phi_sel[i, j] * de[j]
        qs[i] = x
        vs[i] = y
    for k in range(m_sel.shape[0]):
        mesh_gaps(k, qs, vs, m_sel, m_w, m_par, m_te, m_nte, G[k])


@njit(cache=_CACHE)
def _op_code(G, pat, stride):
    """Index of the linear operator for the contact state of every mesh (gaps G)."""
    code = 0
    for k in range(G.shape[0]):
        s = (1 if G[k, 0] > 0.0 else 0) + (2 if G[k, 2] > 0.0 else 0)
        code += pat[k, s] * stride[k]
    return code


@njit(cache=_CACHE)
def _hermite(g0, d0, g1, d1, h, s):
    """Cubic Hermite interpolant on [0, h] at s·h (values g, slopes d per second)."""
    s2 = s * s
    s3 = s2 * s
    return (
        (2 * s3 - 3 * s2 + 1) * g0
        + (s3 - 2 * s2 + s) * h * d0
        + (-2 * s3 + 3 * s2) * g1
        + (s3 - s2) * h * d1
    )


@njit(cache=_CACHE)
def _line_crossing(g0, d0, g1, d1, h, n_probe):
    """First zero crossing in (0, 1] (fraction of h) of the cubic Hermite interpolant through
    a gap g and its rate d at both ends of a step h, probed at ``n_probe`` points and bisected;
    2.0 for none."""
    prev = g0
    lo = 0.0
    for p in range(1, n_probe + 1):
        s = p / n_probe
        gs = g1 if p == n_probe else _hermite(g0, d0, g1, d1, h, s)
        if (prev > 0.0) != (gs > 0.0):
            a, b = lo, s
            for _ in range(40):
                mid = 0.5 * (a + b)
                if (_hermite(g0, d0, g1, d1, h, mid) > 0.0) == (g0 > 0.0):
                    a = mid
                else:
                    b = mid
            return b
        prev = gs
        lo = s
    return 2.0


@njit(cache=_CACHE)
def _first_event(G0, G1, h, n_probe, pat, stride, code, Gs):
    """Earliest contact change within a step h that changes the linear operator: returns the
    fraction of h and the operator code just after it, or (2.0, code) for none. A crossing
    that leaves the operator unchanged (e.g. δ through 0 without backlash: drive to back flank,
    the same stiffness) is no event. ``Gs`` (nm, 4) work array."""
    nm = G0.shape[0]
    best = 2.0
    best_code = code
    done = 0.0
    for _ in range(2 * nm):
        # the next crossing after ``done``
        nxt = 2.0
        for k in range(nm):
            for line in range(2):
                c = _line_crossing(
                    G0[k, 2 * line], G0[k, 2 * line + 1], G1[k, 2 * line], G1[k, 2 * line + 1],
                    h, n_probe,
                )  # fmt: skip
                if done < c < nxt:
                    nxt = c
        if nxt > 1.0:
            break
        # the state just after it, every line from its interpolant
        s = min(nxt + 1e-9, 1.0)
        for k in range(nm):
            for line in range(2):
                g = _hermite(
                    G0[k, 2 * line], G0[k, 2 * line + 1], G1[k, 2 * line], G1[k, 2 * line + 1],
                    h, s,
                )  # fmt: skip
                c = _line_crossing(
                    G0[k, 2 * line], G0[k, 2 * line + 1], G1[k, 2 * line], G1[k, 2 * line + 1],
                    h, n_probe,
                )  # fmt: skip
                # the side of a line crossing now is the one it crosses to
                if abs(c - nxt) < 1e-12:
                    g = -G0[k, 2 * line]
                Gs[k, 2 * line] = g
        new = _op_code(Gs, pat, stride)
        if new != code:
            best = nxt
            best_code = new
            break
        done = nxt
    return best, best_code


@njit(cache=_CACHE)
def _phis(z):
    """(e^z, φ1, φ2, φ3)(z) of a complex z, φ_k(z) = Σ_j z^j/(j+k)!: one series for |z| < 0.5
    (terms until they stop changing the sums; no cancellation), else the recurrence
    φ_{k+1} = (φ_k − 1/k!)/z from e^z (cancellation at most ε/|z|³ ≈ 1e-15)."""
    if abs(z) < 0.5:
        p1 = 1.0 + 0.0j
        p2 = 0.5 + 0.0j
        p3 = 1.0 / 6.0 + 0.0j
        zj = 1.0 + 0.0j
        f = 1.0  # 1/(j+1)!
        for j in range(1, 30):
            zj = zj * z
            f = f / (j + 1)
            t1 = zj * f
            t2 = t1 / (j + 2)
            t3 = t2 / (j + 3)
            p1 += t1
            p2 += t2
            p3 += t3
            if abs(t1) < 1e-17 * abs(p1) and abs(t3) < 1e-17 * abs(p3):
                break
        return 1.0 + z * p1, p1, p2, p3
    e = np.exp(z)
    p1 = (e - 1.0) / z
    p2 = (p1 - 1.0) / z
    p3 = (p2 - 0.5) / z
    return e, p1, p2, p3


@njit(cache=_CACHE)
def etd_coefficients(om, tau, C):
    """Weights of one exponential RK4 step (Cox & Matthews 2002, ETDRK4) of length τ for
    oscillators ζ̈ + ω²ζ = g, into C (12, m). A function F of the block L = [[0, 1], [−ω², 0]]
    is F(L) = α I + β L with α = Re F(iω), β = Im F(iω)/ω (F(0), F'(0) at ω = 0: L² = 0);
    rows (α, β) of: E(τ/2) = e^{Lτ/2}, (τ/2)φ1(Lτ/2), E(τ), τ(φ1 − 3φ2 + 4φ3),
    τ(φ2 − 2φ3), τ(4φ3 − φ2) (the last three at Lτ)."""
    for i in range(om.shape[0]):
        w = om[i]
        if w == 0.0:
            C[0, i], C[1, i] = 1.0, 0.5 * tau
            C[2, i], C[3, i] = 0.5 * tau, tau * tau / 8.0
            C[4, i], C[5, i] = 1.0, tau
            C[6, i], C[7, i] = tau / 6.0, tau * tau / 6.0
            C[8, i], C[9, i] = tau / 6.0, tau * tau / 12.0
            C[10, i], C[11, i] = tau / 6.0, 0.0
            continue
        F2, p1, p2, p3 = _phis(1j * w * tau)
        F0, q1, _, _ = _phis(0.5j * w * tau)
        F1 = 0.5 * tau * q1
        F3 = tau * (p1 - 3.0 * p2 + 4.0 * p3)
        F4 = tau * (p2 - 2.0 * p3)
        F5 = tau * (4.0 * p3 - p2)
        C[0, i], C[1, i] = F0.real, F0.imag / w
        C[2, i], C[3, i] = F1.real, F1.imag / w
        C[4, i], C[5, i] = F2.real, F2.imag / w
        C[6, i], C[7, i] = F3.real, F3.imag / w
        C[8, i], C[9, i] = F4.real, F4.imag / w
        C[10, i], C[11, i] = F5.real, F5.imag / w


@njit(cache=_CACHE, fastmath=_FAST_ETD, inline="always")
def _etd_rhs(t, z, v, g, om, P, W):
    """N = ζ̈ + μζ: everything but the operator's oscillators (``P`` the modal system in the
    operator's coordinates, its stiffness diag(μ))."""
    _accel_modal(t, z, v, g, P, W)
    for i in range(z.shape[0]):
        g[i] += om[i] * om[i] * z[i]


@njit(cache=_CACHE, fastmath=_FAST_ETD)
def _etd_substep(t, tau, z, v, om, coef, P, W, L, out_z, out_v):
    """One exponential RK4 step (ETDRK4, Cox & Matthews 2002) of length tau from (z, v) at t
    in the coordinates of a linear operator diag(μ = om²): the oscillators ζ̈ + μζ are
    integrated exactly, the rest N (damping, gyroscopics, the mesh beyond the operator's
    stiffness, unbalance, torques) enters through the φ-functions (:func:`etd_coefficients`;
    exact for a constant N, so the quasi-static response of a high mode is right at any step).
    ``coef`` (12, m): the weights of the full step, or an empty array to compute them for this
    τ. Writes ζ, ζ̇ at t + tau to out_z, out_v."""
    (x, y, acc, g1, g2, g3, g4, ax, av, C) = L
    m = z.shape[0]
    if coef.shape[0] == 12:
        C = coef
    else:
        etd_coefficients(om, tau, C)
    # F(L)(ζ, v) = (αζ + βv, αv − ω²βζ); the forcing (0, g) gives (βg, αg)
    _etd_rhs(t, z, v, g1, om, P, W)
    for i in range(m):
        w2 = om[i] * om[i]
        ez = C[0, i] * z[i] + C[1, i] * v[i]  # E(τ/2) x
        ev = C[0, i] * v[i] - w2 * C[1, i] * z[i]
        ax[i] = ez + C[3, i] * g1[i]
        av[i] = ev + C[2, i] * g1[i]
        x[i] = ez
        y[i] = ev
    _etd_rhs(t + 0.5 * tau, ax, av, g2, om, P, W)
    for i in range(m):
        x[i] += C[3, i] * g2[i]
        y[i] += C[2, i] * g2[i]
    _etd_rhs(t + 0.5 * tau, x, y, g3, om, P, W)
    for i in range(m):
        w2 = om[i] * om[i]
        f = 2.0 * g3[i] - g1[i]
        x[i] = C[0, i] * ax[i] + C[1, i] * av[i] + C[3, i] * f
        y[i] = C[0, i] * av[i] - w2 * C[1, i] * ax[i] + C[2, i] * f
    _etd_rhs(t + tau, x, y, g4, om, P, W)
    for i in range(m):
        w2 = om[i] * om[i]
        g23 = g2[i] + g3[i]
        out_z[i] = (
            C[4, i] * z[i] + C[5, i] * v[i] + C[7, i] * g1[i] + 2.0 * C[9, i] * g23
            + C[11, i] * g4[i]
        )  # fmt: skip
        out_v[i] = (
            C[4, i] * v[i] - w2 * C[5, i] * z[i] + C[6, i] * g1[i] + 2.0 * C[8, i] * g23
            + C[10, i] * g4[i]
        )  # fmt: skip


@njit(cache=_CACHE)
def _op_system(P, X, op):
    """The modal parameter tuple of :func:`_accel_modal` in the coordinates of operator op."""
    lams, Crs, Grs, alphas, Phis, PhiTs, m_pars = X[9], X[10], X[11], X[12], X[13], X[14], X[15]
    return (
        (lams[op], Crs[op], Grs[op], alphas[op], Phis[op], PhiTs[op])
        + P[6:11]
        + (m_pars[op],)
        + P[12:]
    )


@njit(cache=_CACHE)
def _rotate(Ya, Yb, z, v, tz, tv):
    """(z, v) ← Y_bᵀ Y_a (z, v): coordinates of operator a to those of operator b."""
    m = z.shape[0]
    for i in range(m):
        a = 0.0
        b = 0.0
        for j in range(m):
            a += Ya[i, j] * z[j]
            b += Ya[i, j] * v[j]
        tz[i] = a
        tv[i] = b
    for i in range(m):
        a = 0.0
        b = 0.0
        for j in range(m):
            a += Yb[j, i] * tz[j]
            b += Yb[j, i] * tv[j]
        z[i] = a
        v[i] = b


@njit(cache=_CACHE, fastmath=_FAST_ETD)
def _record_etd(j, t, z, v, g1, om, Po, alpha, rec_q, rec_v, rec_a, rec_om, rec_t, blowup):
    """Record row j of the outputs Φ_out η, η̇, η̈ (η̈ = N − μζ, ``g1`` the first stage's N)
    and the shaft speeds at t, in an operator's coordinates; returns the divergence status."""
    m = z.shape[0]
    big = 0.0
    bad = False
    for i in range(Po.shape[0]):
        x = 0.0
        y = 0.0
        zz = 0.0
        for c in range(m):
            x += Po[i, c] * z[c]
            y += Po[i, c] * v[c]
            zz += Po[i, c] * (g1[c] - om[c] * om[c] * z[c])
        rec_q[j, i] = x
        rec_v[j, i] = y
        rec_a[j, i] = zz
        if not (np.isfinite(x) and np.isfinite(y)):
            bad = True
        if abs(x) * blowup[i] > big:
            big = abs(x) * blowup[i]
    for s in range(alpha.shape[0]):
        o = 0.0
        for c in range(m):
            o += alpha[s, c] * v[c]
        rec_om[j, s] = o
    rec_t[j] = t
    if bad:
        return STATUS_NONFINITE
    if big > 1.0:
        return STATUS_BLOWUP
    return STATUS_OK


@njit(cache=_CACHE, fastmath=_FAST_ETD)
def etd_modal(
    t0,
    dt,
    n_steps,
    e,
    de,
    save_every,
    Phi_out,
    rec_q,
    rec_v,
    rec_a,
    rec_om,
    rec_t,
    rec_start,
    blowup,
    P,
    W,
    K1,
    X,
):
    """Exponential RK4 on the reduced modal system with the contact changes located.

    ``X`` holds one linear operator per combination of the meshes' contact states: diag(Λ)
    with each mesh's stiffness Kg w wᵀ on the lines that touch (none while the teeth are
    apart), its eigenvectors ``Ys`` (orthonormal, η = Y ζ) and frequencies ``oms``, the step's
    ETD weights ``coefs``, and the modal system in its coordinates (``lams`` … ``m_pars``,
    ``Phi_outs``); ``pat``/``stride`` map the contact states to an operator. Each step runs in
    the coordinates of the operator of the contact state at its start, whose oscillators it
    integrates exactly (:func:`_etd_substep`). When a gap function changes sign within the step
    in a way that changes the operator (cubic Hermite through its values and rates at both
    ends) the step is redone up to the crossing and continued from there with the new
    operator, so each piece of a step sees one smooth law. Records Φ_out η every
    ``save_every`` steps as :func:`rk4_modal`; (e, de) in and out are modal coordinates η.
    Returns (status, steps done, substeps added by contact changes)."""
    (Ys, idents, oms, coefs, pat, stride, op_of, n_probe, max_sub, lams, Crs, Grs, alphas,
     Phis, PhiTs, m_pars, Phi_outs) = X  # fmt: skip
    m = e.shape[0]
    (k1q, k1v, k2q, k2v, k3q, k3v, k4q, k4v, qt, vt) = K1
    L = (k1q, k1v, k2q, k2v, k3q, k3v, k4q, k4v, qt, np.zeros((12, m)))
    none = np.zeros((0, m))
    m_sel, m_w, m_par = P[9], P[10], P[11]
    m_te, m_nte = P[17], P[18]
    qs, vs = W[0], W[1]
    nm = m_sel.shape[0]
    G0 = np.zeros((nm, 4))
    G1 = np.zeros((nm, 4))
    Gs = np.zeros((nm, 4))
    z = np.zeros(m)
    v = np.zeros(m)
    z1 = np.zeros(m)
    v1 = np.zeros(m)
    extra = 0
    code = 0
    # start in the coordinates of the initial contact state's operator
    _gaps_of(e, de, P[4], qs, vs, m_sel, m_w, m_par, m_te, m_nte, G0)
    new = op_of[_op_code(G0, pat, stride)]
    for i in range(m):
        z[i] = 0.0
        v[i] = 0.0
        for j in range(m):
            z[i] += Ys[new, j, i] * e[j]
            v[i] += Ys[new, j, i] * de[j]
    cur = new
    Pc = _op_system(P, X, cur)
    j = rec_start
    status = STATUS_OK
    done = n_steps
    for step in range(n_steps):
        t = t0 + step * dt
        left = dt
        forced = -1
        if n_probe > 0:
            _gaps_of(z, v, Phis[cur], qs, vs, m_sel, m_w, m_par, m_te, m_nte, G0)
        for sub in range(max_sub):
            if n_probe > 0:
                code = forced if forced >= 0 else _op_code(G0, pat, stride)
                new = op_of[code]
                if new != cur:
                    _rotate(Ys[cur], Ys[new], z, v, z1, v1)
                    cur = new
                    Pc = _op_system(P, X, cur)
            om = oms[cur]
            _etd_substep(t, left, z, v, om, coefs[cur] if sub == 0 else none, Pc, W, L, z1, v1)
            if sub == 0 and step % save_every == 0:
                # the step's start: η̈ = N − μζ from the first stage (no extra evaluation)
                status = _record_etd(
                    j, t, z, v, L[3], om, Phi_outs[cur], alphas[cur], rec_q, rec_v, rec_a,
                    rec_om, rec_t, blowup,
                )  # fmt: skip
                j += 1
                if status != STATUS_OK:
                    done = step
                    break
            if sub == max_sub - 1 or n_probe == 0:
                break
            _gaps_of(z1, v1, Phis[cur], qs, vs, m_sel, m_w, m_par, m_te, m_nte, G1)
            frac, code = _first_event(G0, G1, left, n_probe, pat, stride, code, Gs)
            if frac > 1.0:
                break
            # redo up to the crossing, then continue with the new state's operator
            tau = frac * left
            _etd_substep(t, tau, z, v, om, none, Pc, W, L, z1, v1)
            for i in range(m):
                z[i] = z1[i]
                v[i] = v1[i]
            t += tau
            left -= tau
            extra += 1
            _gaps_of(z, v, Phis[cur], qs, vs, m_sel, m_w, m_par, m_te, m_nte, G0)
            # the state the crossing leads to, whatever round-off says at the crossing itself
            forced = code
        if status != STATUS_OK:
            break
        for i in range(m):
            z[i] = z1[i]
            v[i] = v1[i]
    # back to modal coordinates η = Y ζ
    Y = Ys[cur]
    for i in range(m):
        a = 0.0
        b = 0.0
        for c in range(m):
            a += Y[i, c] * z[c]
            b += Y[i, c] * v[c]
        e[i] = a
        de[i] = b
    return status, done, extra
