"""Modal reduction of the transient model (:class:`~.options.ModalRK4`): the static correction
shapes, the reduced basis (modes up to a cut-off, the free-shaft modes, the static shapes;
Ritz re-diagonalisation) and the harmonic accuracy check against the full model."""

from __future__ import annotations

import numpy as np
import scipy.linalg as la
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from numpy.typing import NDArray

from ...errors import ModelError

#: DOFs from which the setup solves its full-model problems sparsely: the modes below the
#: cut-off by shift-invert Lanczos instead of the dense generalised eigen solve of all of them
#: (O(n³)), and the static and harmonic responses by a sparse LU instead of a dense one.
#: Measured (issue 28, 0.2 s of a chain of SPEC 6.1 shafts, setup s dense/sparse): 252 DOF
#: 0.05/0.06, 492 DOF 0.22/0.09, 972 DOF 0.79/0.15; 1968 DOF 4.4 s dense. Below it (every
#: shipped example, ≤ 252 DOFs) the dense solves run as before, bit for bit.
SPARSE_FROM = 300


def _solve(A, b: NDArray) -> NDArray:
    """``A x = b`` for a full-model matrix: a dense LU of a dense A (below
    :data:`SPARSE_FROM` DOFs, where the setup keeps its matrices dense), else a sparse LU (the
    finite-element matrices are banded)."""
    if not sp.issparse(A):
        return la.solve(A, b)
    return spla.splu(sp.csc_array(A)).solve(np.asarray(b))


def _dense(A) -> NDArray:
    return A.toarray() if sp.issparse(A) else A


def _gyroscopic(system, like):
    """Σ_s Ω_s G_s at the nominal shaft speeds: dense (``system.gyroscopic()``) when ``like``
    is a dense array, else sparse."""
    if not sp.issparse(like):
        return system.gyroscopic()
    out = sp.csr_array(like.shape)
    for s, g in zip(system.nominal_speeds, system.G, strict=True):
        out = out + s * g
    return out


class Spectrum:
    """The undamped modes (ω², M-orthonormal V) of the pencil (Ks, M) below a frequency:
    all of them by the dense solve below :data:`SPARSE_FROM` DOFs, else the lowest ones by
    shift-invert Lanczos (ARPACK) about a shift just below zero (Ks is positive semidefinite:
    the rigid rotation has ω = 0), as many as the highest frequency asked for needs, solved
    again with more when a raised cut-off needs more; the Lanczos vectors are re-diagonalised
    on the pencil (Rayleigh–Ritz: M-orthonormal to round-off also in clusters of equal
    frequencies, as the identical shafts of a chain have)."""

    def __init__(self, Ks: NDArray, M: NDArray, what: str = "eigh"):
        from ...threads import limit as thread_limit

        self.n = M.shape[0]
        self.dense = self.n < SPARSE_FROM
        if self.dense:
            with thread_limit(self.n, what):
                self.w2, self.V = la.eigh(_dense(Ks), _dense(M))
            self.complete = True
            return
        self.Ks, self.M = sp.csc_array(Ks), sp.csc_array(M)
        self.w2, self.V = np.zeros(0), np.zeros((self.n, 0))
        self.complete = False
        self._k = 0
        self._lu = None

    def upto(self, omega: float) -> tuple[NDArray, NDArray]:
        """(ω², V) holding every mode with ω ≤ ``omega`` (rad/s), in ascending order (more
        modes may follow them)."""
        while not self.complete and not (len(self.w2) and self.w2[-1] > omega**2):
            self._solve(max(2 * self._k, 40))
        return self.w2, self.V

    @property
    def omega_max(self) -> float:
        """rad/s: the highest frequency of the model (its largest mode)."""
        if self.complete:
            return float(np.sqrt(max(self.w2[-1], 0.0)))
        if not hasattr(self, "_top"):
            top = spla.eigsh(self.Ks, k=1, M=self.M, which="LA", return_eigenvectors=False)
            self._top = float(np.sqrt(max(top[0], 0.0)))
        return self._top

    def _solve(self, k: int) -> None:
        n = self.n
        if k >= n // 2:  # most of the spectrum: the dense solve
            w2, V = la.eigh(self.Ks.toarray(), self.M.toarray())
            self.w2, self.V, self.complete = w2, V, True
            return
        if self._lu is None:
            # the shift: below the lowest eigenvalue (0 for the rigid rotation), scaled
            scale = float(abs(self.Ks.diagonal()).max() / max(abs(self.M.diagonal()).max(), 1e-300))
            self._sigma = -1e-6 * scale
            self._lu = spla.splu(sp.csc_array(self.Ks - self._sigma * self.M))
        op = spla.LinearOperator((n, n), matvec=self._lu.solve, dtype=float)
        w2, V = spla.eigsh(self.Ks, k=k, M=self.M, sigma=self._sigma, which="LM", OPinv=op, tol=0.0)
        # Rayleigh–Ritz on the pencil: exact M-orthonormality within clusters
        MV = self.M @ V
        w2r, Y = la.eigh(V.T @ (self.Ks @ V), V.T @ MV)
        self.w2, self.V, self._k = w2r, V @ Y, k


def full_model(system, *matrices):
    """The full-model matrices as the setup uses them: dense below :data:`SPARSE_FROM` DOFs,
    else sparse (their products with the basis and their solves O(n·m), not O(n²·m) and
    O(n³))."""
    if system.n < SPARSE_FROM:
        return matrices
    return tuple(sp.csr_array(x) for x in matrices)


def linear_damping(system, C):
    """The damping of the model linearised at the nominal speeds
    (:func:`~.step_limits._linearised`: the meshes' contact damping and the gyroscopic
    matrices added to C), dense for a dense C, else sparse."""
    if not sp.issparse(C):
        from .step_limits import _linearised

        return _linearised(system)[2]
    rows, cols, vals = [np.zeros(0, int)], [np.zeros(0, int)], [np.zeros(0)]
    for law, d in zip(system.meshes, system.mesh_dofs, strict=True):
        ok = d >= 0
        w = law.w[ok]
        rows.append(np.repeat(d[ok], len(w)))
        cols.append(np.tile(d[ok], len(w)))
        vals.append((law.damping * np.outer(w, w)).ravel())
    extra = sp.csr_array(
        (np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=C.shape
    )
    return C + extra + _gyroscopic(system, C)


def skew_block(Ka) -> tuple[NDArray, NDArray]:
    """(DOFs, dense block): the rows and columns where the skew stiffness ``Ka`` (dense or
    sparse) has entries, and ``Ka`` on them."""
    if sp.issparse(Ka):
        Ka = sp.csr_array(Ka)
        Ka.eliminate_zeros()
        k_dofs = np.flatnonzero(np.diff(Ka.indptr))
        return k_dofs, Ka[k_dofs[:, None], k_dofs].toarray()
    k_dofs = np.flatnonzero(np.any(Ka != 0, axis=1))
    return k_dofs, Ka[np.ix_(k_dofs, k_dofs)]


def reduced_gyroscopic(system, Phi: NDArray) -> NDArray:
    """(shafts, m, m): Φᵀ G_s Φ per shaft; with the dense products below
    :data:`SPARSE_FROM` DOFs (as before, bit for bit), else the sparse ones (O(n m²))."""
    m = Phi.shape[1]
    if system.n < SPARSE_FROM:
        return np.array([Phi.T @ g.toarray() @ Phi for g in system.G]).reshape(-1, m, m)
    return np.array([Phi.T @ (g @ Phi) for g in system.G]).reshape(-1, m, m)


class ModalBases:
    """The modal bases of :func:`_modal_basis` for a cut-off: the undamped modes of (Ks, M)
    below it (:class:`Spectrum`), and with ``separated`` those of the train without meshes
    (the free shafts' torsional ones only with ``"torsional"``: what the speeds do while the
    teeth are apart; their lateral modes only add Ritz vectors far above the cut-off, issue
    16)."""

    def __init__(self, system, M, Ks, separated):
        self.M, self.Ks, self.separated = M, Ks, separated
        self.spectrum = Spectrum(Ks, M)
        self.free = None
        if separated and system.meshes:
            _, Kf, _ = system.linear_matrices(meshes=False)
            (Kf,) = full_model(system, Kf)
            self.free = Spectrum(0.5 * (Kf + Kf.T), M)
            self.tors = system.assembly.dof_kind()[system.active] == 2

    @property
    def omega_max(self) -> float:
        """rad/s: the model's highest frequency (:attr:`Spectrum.omega_max`)."""
        return self.spectrum.omega_max

    def _free_modes(self, wcut: float):
        if self.free is None:
            return None
        w2s, Vs = self.free.upto(wcut)
        if self.separated == "torsional":
            M, tors = self.M, self.tors
            ke = np.einsum("ij,ij->j", Vs, M @ Vs)
            Mt = M[tors][:, tors] if sp.issparse(M) else M[np.ix_(tors, tors)]
            kt = np.einsum("ij,ij->j", Vs[tors], Mt @ Vs[tors])
            keep = kt > 0.5 * ke
            w2s, Vs = w2s[keep], Vs[:, keep]
        return w2s, Vs

    def basis(self, wcut: float, shapes: NDArray) -> tuple[NDArray, NDArray]:
        """(Φ, ω²) of :func:`_modal_basis` at the cut-off ``wcut`` (rad/s)."""
        w2, V = self.spectrum.upto(wcut)
        return _modal_basis(self.M, self.Ks, V, w2, wcut, self._free_modes(wcut), shapes)


def basis_stiffness(system, K: NDArray) -> NDArray:
    """The symmetric stiffness the modal basis is built from (its remainder ``K − Ks`` acts as
    a force on its few DOFs): the symmetric part of K, except on the tilting pads with pad
    dynamics, whose symmetric film block is indefinite (the Couette terms couple the journal
    and the pad tilts one-sidedly) and is replaced by its positive semidefinite part (negative
    eigenvalues of the block set to 0). A basis from an indefinite Ks would have modes of
    negative ω², which the reduced model cannot keep as oscillators."""
    Ks = 0.5 * (K + K.T)
    asm = system.assembly
    for b in asm.bearings:
        if b.pad_dofs is None:
            continue
        d, T = b.local()
        idx = np.array([system.index(int(g)) for g in d])
        on = idx >= 0
        kf = b.element.pads.at(system.nominal_speeds[b.shaft])[0]
        S = 0.5 * (kf + kf.T)
        mu, V = la.eigh(S)
        A = T.T @ ((V * np.clip(mu, 0.0, None)) @ V.T - S) @ T
        Ks[np.ix_(idx[on], idx[on])] += A[np.ix_(on, on)]
    return Ks


def _static_shapes(system, M, K) -> NDArray:
    """Static correction shapes (n, k): the deflection, in the frame of the train's rigid
    rotation, under each mesh's unit normal force pattern w and each external torque."""
    ratio = system.assembly.speed_ratio
    r = np.zeros(system.n)
    for s, a in enumerate(system.a_weights):
        r[a != 0] = ratio[s]
    Mr = M @ r
    pats = []
    for law, d in zip(system.meshes, system.mesh_dofs, strict=True):
        b = np.zeros(system.n)
        b[d[d >= 0]] = law.w[d >= 0]
        pats.append(b)
    for dof in system.torque_dof:
        b = np.zeros(system.n)
        b[dof] = 1.0
        pats.append(b)
    if getattr(system, "constant_force", None) is not None:
        pats.append(np.asarray(system.constant_force, float))
    if not pats:
        return np.zeros((system.n, 0))
    if sp.issparse(K):
        col = sp.csr_array(Mr[:, None])
        A = sp.block_array([[K, col], [col.T, None]], format="csc")
    else:
        A = np.block([[K, Mr[:, None]], [Mr[None, :], np.zeros((1, 1))]])
    rhs = np.vstack([np.array(pats).T, np.zeros((1, len(pats)))])
    return _solve(A, rhs)[:-1]


def _modal_basis(M, Ks, V, w2, wcut, separated, shapes):
    """M-orthonormal basis with Ks diagonal: the modes (V, w2 of (Ks, M)) up to ``wcut``
    (rad/s), extended by ``separated`` (w2, V of the train without meshes, or None: its modes up
    to the cut-off) and the static correction ``shapes`` (n, k).

    The extra vectors are made M-orthogonal to the kept modes and to each other, then
    re-diagonalised (Ritz) among themselves: the kept modes keep their exact frequencies (the
    rigid rotation stays at zero). Directions with less than 1e-5 of their M-norm outside the
    span of the others add nothing and are dropped. Returns (Φ, ω² in rad²/s²), by frequency."""
    om = np.sqrt(np.clip(w2, 0.0, None))
    keep = om <= wcut
    if not keep.any():
        raise ModelError("no mode below the modal cut-off", value=f"{wcut / 2 / np.pi:.4g} Hz")
    B = V[:, keep]
    E = shapes
    if separated is not None:
        w2s, Vs = separated
        E = np.hstack([Vs[:, np.sqrt(np.clip(w2s, 0.0, None)) <= wcut], E])
    if not E.shape[1]:
        return B, w2[keep]
    E = E / np.sqrt(np.einsum("ij,ij->j", E, M @ E))
    # two passes: the first loses orthogonality in proportion to the norm removed, the
    # second restores it to round-off ("twice is enough")
    for _ in range(2):
        E = E - B @ (B.T @ (M @ E))
        gw, gv = la.eigh(E.T @ M @ E)
        ok = gw > 1e-10
        E = E @ (gv[:, ok] / np.sqrt(gw[ok]))
    if not E.shape[1]:
        return B, w2[keep]
    w2e, Y = la.eigh(E.T @ Ks @ E)
    Phi = np.hstack([B, E @ Y])
    w2r = np.concatenate([w2[keep], w2e])
    order = np.argsort(w2r, kind="stable")
    return Phi[:, order], w2r[order]


def _unbalance_1x(system, M, K, C):
    """The linear 1x unbalance response of the full model, per distinct shaft speed: yields
    (Ω rad/s, F (n,) complex force, X (n,) complex response of K − Ω²M + iΩ(C + G))."""
    G = _gyroscopic(system, C)
    speeds = system.nominal_speeds
    for w in np.unique(np.round(np.abs(speeds), 9)):
        F = np.zeros(system.n, complex)
        for u, d in enumerate(system.unbalance_dofs):
            sh = system.shaft_of_row[d[0]]
            if abs(abs(speeds[sh]) - w) > 1e-6 * w:
                continue
            sig = np.sign(speeds[sh])
            f0 = system.unbalance_me[u] * w**2 * np.exp(1j * sig * system.unbalance_phase[u])
            F[d[0]] += f0
            F[d[1]] += -1j * sig * f0
        if not F.any():
            continue
        yield w, F, _solve(K - w**2 * M + 1j * w * (C + G), F)


def _harmonic_shapes(system, M, K, C) -> NDArray:
    """Real and imaginary parts (n, 2k) of the full model's linear responses to the two
    periodic excitations of a geared train: the 1x unbalance forces
    (:func:`_unbalance_1x`) and, per mesh, a force along its line of action w at its mesh
    frequency (stiffness variation and transmission error act there). With them in the basis
    the reduced model reproduces those responses exactly (a Galerkin projection is exact when
    the solution lies in its span), so the share of the modes above the cut-off in them
    (quasi-static compliance, heavily damped bearings) is kept without keeping those modes."""
    cols = [part for _, _, X in _unbalance_1x(system, M, K, C) for part in (X.real, X.imag)]
    G = _gyroscopic(system, C)
    for law, d, rate in zip(system.meshes, system.mesh_dofs, system.mesh_rates(), strict=True):
        w = abs(float(rate))
        b = np.zeros(system.n)
        b[d[d >= 0]] = law.w[d >= 0]
        X = _solve(K - w**2 * M + 1j * w * (C + G), b)
        cols += [X.real, X.imag]
    return np.array(cols).T.reshape(system.n, -1)


def _harmonic_error(system, M, K, C, Phi, w2r, out, Ka=None) -> float:
    """Largest relative error of the reduced model's linear 1x unbalance response at the
    recorded lateral DOFs (per distinct shaft speed), against the full model."""
    kind = system.assembly.dof_kind()[system.active]
    obs = out[kind[out] == 0]
    if not len(system.unbalance_dofs) or not len(obs):
        return 0.0
    G = _gyroscopic(system, C)
    err = 0.0
    for w, F, Xf in _unbalance_1x(system, M, K, C):
        X = Xf[obs]
        A = (
            np.diag(w2r)
            + Phi.T @ (0.5 * (K - K.T) if Ka is None else Ka) @ Phi
            - w**2 * np.eye(len(w2r))
            + 1j * w * (Phi.T @ (C + G) @ Phi)
        )
        Xr = Phi[obs] @ la.solve(A, Phi.T @ F)
        err = max(err, float(np.abs(Xr - X).max() / np.abs(X).max()))
    return err
