"""Damped eigenvalues of the linear train at a speed (SPEC 3.1).

State-space form with z = [q, q̇]:

    A z = λ B z,   A = [[0, I], [−K, −(C + G)]],   B = [[I, 0], [0, M]].

Eigensolver: for models up to ``DENSE_LIMIT`` DOFs the dense QR algorithm (LAPACK ``geev``) on
``B⁻¹A`` (M is factored once by Cholesky) gives every eigenvalue; larger models use sparse
shift-invert Arnoldi (ARPACK) about a small negative real shift, increasing the number of
requested modes until every mode below ``max_frequency`` is enclosed. Dense is chosen for small
models because it is exact (no missed modes) and fast: 504 states take ~0.1 s.

Classification, all documented in :class:`ModalResult`:

* **rigid-body**: a mode that strains nothing: its strain-energy frequency
  ``√(|φᴴKφ| / φᴴMφ)`` is below ``rigid_tol`` (free torsion of a geared pair, free axial
  motion). Judging by strain energy rather than by |λ| is robust: a zero eigenvalue of a free
  mode is a defective (Jordan) pair that round-off splits by ~√ε‖A‖ into two small, possibly
  complex, eigenvalues, while its eigenvector stays accurate;
* **over-damped**: a real eigenvalue (listed in ``real_eigenvalues``) or a complex pair with a
  damping ratio ζ ≥ ``overdamped_zeta`` (such a pair decays by e^{-2π ζ/√(1-ζ²)} per period,
  i.e. it never completes one oscillation visibly; listed in the modes with ``overdamped``);
* **whirl** per shaft: the sense of the orbits of the shaft's nodes, weighted by amplitude,
  relative to that shaft's spin (``F`` forward, ``B`` backward, ``-`` no lateral motion);
* **type**: kinetic-energy fractions in lateral (x, y, θx, θy), torsional (θz) and axial (z)
  DOFs; every group with at least ``type_threshold`` of the energy is named: ``L``, ``T``,
  ``A``, ``L-T``, ...
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import scipy.linalg as la
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from numpy.typing import NDArray

from ..assembly import Assembly, assemble
from ..errors import ModelError, SolverError
from ..model import Train

__all__ = ["ModalResult", "modal", "DENSE_LIMIT", "state_matrices"]

DENSE_LIMIT = 2000
KIND_NAMES = ("L", "A", "T")  # index = Assembly.dof_kind() code


@dataclass(frozen=True)
class ModalResult:
    """Damped modes with positive damped frequency, sorted by frequency.

    Frequencies in rad/s (``*_rpm`` / ``*_hz`` properties convert); ``mode_shapes`` (n_modes,
    n_dof) complex, normalised so the largest physical displacement (translations, and rotations
    times the node's radius) equals 1 with zero phase.
    """

    speed: float  # reference-shaft speed, rad/s
    shaft_speeds: NDArray  # rad/s per shaft
    eigenvalues: NDArray  # complex (n,)
    mode_shapes: NDArray  # complex (n, n_dof)
    whirl_per_shaft: tuple[tuple[str, ...], ...]  # (n, n_shafts)
    whirl: tuple[str, ...]
    energy_fractions: NDArray  # (n, 3): lateral, axial, torsional kinetic-energy fractions
    mode_type: tuple[str, ...]
    overdamped: NDArray  # bool (n,)
    real_eigenvalues: NDArray  # real eigenvalues (over-damped / rigid-body), 1/s
    rigid_body: NDArray  # bool per real eigenvalue
    n_rigid_body: int
    method: str
    n_eigenvalues: int  # eigenvalues with |λ| ≤ max_frequency (all returned if none given)
    shaft_names: tuple[str, ...]
    assembly: Assembly = field(repr=False)

    @property
    def damped_frequency(self) -> NDArray:
        return self.eigenvalues.imag

    @property
    def natural_frequency(self) -> NDArray:
        return np.abs(self.eigenvalues)

    @property
    def damping_ratio(self) -> NDArray:
        return -self.eigenvalues.real / np.abs(self.eigenvalues)

    @property
    def log_dec(self) -> NDArray:
        return -2 * np.pi * self.eigenvalues.real / self.eigenvalues.imag

    @property
    def frequency_rpm(self) -> NDArray:
        return self.damped_frequency * 30 / np.pi

    @property
    def frequency_hz(self) -> NDArray:
        return self.damped_frequency / (2 * np.pi)

    @property
    def stable(self) -> bool:
        return not bool(np.any(self.unstable)) and not bool(
            np.any(self.real_eigenvalues[~self.rigid_body] > 0)
        )

    @property
    def unstable(self) -> NDArray:
        """Growing modes: Re λ > 1e-9 |λ| (round-off of a conservative mode stays below)."""
        return self.eigenvalues.real > 1e-9 * np.abs(self.eigenvalues)

    def __len__(self) -> int:
        return len(self.eigenvalues)

    def shape_dict(self, i: int) -> dict:
        """Mode i along every shaft: node z (m) and each DOF's complex amplitude (re, im)."""
        layout = self.assembly.train.layout()
        out = {}
        phi = self.mode_shapes[i]
        for si, sl in enumerate(layout.shafts):
            offs = self.assembly.node_offset[si]
            d = {"z": sl.z.tolist()}
            for k, name in enumerate(("x", "y", "z", "tx", "ty", "tz")):
                v = phi[offs + k]
                d[name] = {"re": v.real.tolist(), "im": v.imag.tolist()}
            out[sl.name] = d
        return out

    def to_dict(self, shapes: bool = False) -> dict:
        """JSON-ready summary; ``shapes=True`` adds each mode's shape (see :meth:`shape_dict`)."""
        modes = []
        for i in range(len(self)):
            d = {
                "index": i,
                "frequency_rpm": float(self.frequency_rpm[i]),
                "frequency_hz": float(self.frequency_hz[i]),
                "log_dec": float(self.log_dec[i]),
                "damping_ratio": float(self.damping_ratio[i]),
                "whirl": self.whirl[i],
                "whirl_per_shaft": dict(
                    zip(self.shaft_names, self.whirl_per_shaft[i], strict=True)
                ),
                "type": self.mode_type[i],
                "energy_lateral": float(self.energy_fractions[i, 0]),
                "energy_axial": float(self.energy_fractions[i, 1]),
                "energy_torsional": float(self.energy_fractions[i, 2]),
                "stable": not bool(self.unstable[i]),
                "overdamped": bool(self.overdamped[i]),
            }
            if shapes:
                d["shape"] = self.shape_dict(i)
            modes.append(d)
        real = [
            {
                "eigenvalue": float(v),
                "rigid_body": bool(r),
                "decay_time_s": (float(-1 / v) if v < 0 else None),
            }
            for v, r in zip(self.real_eigenvalues, self.rigid_body, strict=True)
        ]
        return {
            "speed_rpm": float(self.speed * 30 / np.pi),
            "shaft_speeds_rpm": dict(
                zip(
                    self.shaft_names,
                    (float(s * 30 / np.pi) for s in self.shaft_speeds),
                    strict=True,
                )
            ),
            "n_dof": int(self.assembly.n_dof),
            "method": self.method,
            "stable": self.stable,
            "n_rigid_body_modes": int(self.n_rigid_body),
            "modes": modes,
            "real_modes": real,
        }

    def table(self) -> str:
        """A plain-text table of the modes."""
        head = (
            f"{'#':>3} {'freq rpm':>12} {'freq Hz':>10} {'log dec':>9} {'zeta':>7} "
            f"{'whirl':>6} {'type':>6}  notes"
        )
        rows = [head, "-" * len(head)]
        for i in range(len(self)):
            notes = []
            if self.overdamped[i]:
                notes.append("over-damped")
            if self.unstable[i]:
                notes.append("UNSTABLE")
            whirl = (
                "/".join(self.whirl_per_shaft[i]) if len(self.shaft_names) > 1 else self.whirl[i]
            )
            rows.append(
                f"{i:>3} {self.frequency_rpm[i]:>12.2f} {self.frequency_hz[i]:>10.3f} "
                f"{self.log_dec[i]:>9.4g} {self.damping_ratio[i]:>7.4f} {whirl:>6} "
                f"{self.mode_type[i]:>6}  {' '.join(notes)}"
            )
        if len(self.real_eigenvalues):
            nr = int(np.sum(self.rigid_body))
            rows.append(
                f"real eigenvalues: {len(self.real_eigenvalues)} "
                f"({nr} rigid-body, {len(self.real_eigenvalues) - nr} over-damped)"
            )
        return "\n".join(rows)


def state_matrices(M, C, K) -> tuple[NDArray, NDArray]:
    """Dense A, B of the first-order form (for tests and small models)."""
    n = M.shape[0]
    I, Z = np.eye(n), np.zeros((n, n))
    A = np.block([[Z, I], [-_dense(K), -_dense(C)]])
    B = np.block([[I, Z], [Z, _dense(M)]])
    return A, B


def _dense(a) -> NDArray:
    return a.toarray() if sp.issparse(a) else np.asarray(a)


def _check_mass(M: NDArray, asm: Assembly):
    """Cholesky factor of M, or a ModelError naming the massless DOFs."""
    try:
        return la.cho_factor(M, lower=True)
    except la.LinAlgError:
        raise _singular_mass(asm) from None


def _singular_mass(asm: Assembly) -> ModelError:
    diag = asm.M.diagonal()
    bad = [asm.dof_labels[i] for i in np.flatnonzero(diag <= 1e-12 * diag.max())][:10]
    return ModelError(
        "singular model: the mass matrix is not positive definite",
        field="shafts / disks / supports",
        value=bad or "(no zero diagonal; check densities)",
        expected="mass or inertia on every degree of freedom",
    )


def _solve_dense(M, Cg, K, asm) -> tuple[NDArray, NDArray]:
    cho = _check_mass(M, asm)
    n = M.shape[0]
    A = np.zeros((2 * n, 2 * n))
    A[:n, n:] = np.eye(n)
    A[n:, :n] = -la.cho_solve(cho, K)
    A[n:, n:] = -la.cho_solve(cho, Cg)
    if not np.isfinite(A).all():
        raise SolverError(
            "the state matrix M⁻¹[K, C + G] overflows (non-finite entries): a stiffness or "
            "damping value is far beyond the physical range (check the model's largest values)"
        )
    lam, V = la.eig(A, overwrite_a=True, check_finite=False)
    return lam, V[:n]


def _solve_sparse(M, Cg, K, asm, max_frequency, n_modes, k0=None) -> tuple[NDArray, NDArray]:
    n = M.shape[0]
    I = sp.identity(n, format="csc")
    A = sp.block_array([[None, I], [-K, -Cg]], format="csc")
    B = sp.block_array([[I, None], [None, M]], format="csc")
    scale = max_frequency if max_frequency else 1.0
    sigma = -1e-3 * scale
    k = min(k0 or max(n_modes or 20, 10), 2 * n - 2)
    while True:
        try:
            lam, V = spla.eigs(A, k=k, M=B, sigma=sigma, which="LM")
        except spla.ArpackNoConvergence as exc:
            raise SolverError(f"sparse eigensolver did not converge for {k} modes: {exc}") from None
        except RuntimeError:  # SuperLU could not factor the shifted matrix: M is singular
            raise _singular_mass(asm) from None
        if max_frequency is None or k >= 2 * n - 2:
            return lam, V[:n]
        if np.max(np.abs(lam - sigma)) > max_frequency + abs(sigma):
            return lam, V[:n]
        k = min(2 * k, 2 * n - 2)


def _scale_vector(asm: Assembly) -> NDArray:
    """Per DOF: 1 for translations, the node radius for rotations (m)."""
    s = np.ones(asm.n_dof)
    train = asm.train
    radius = [sl.outer_radius.copy() for sl in train.layout().shafts]
    for m in asm.meshes:
        ri, rj = m.geometry.radius_i, m.geometry.radius_j
        for side, r in ((0, ri), (1, rj)):
            si = m.shafts[side]
            node = int(np.flatnonzero(asm.node_offset[si] == m.dofs[6 * side])[0])
            radius[si][node] = max(radius[si][node], r)
    for si, offs in enumerate(asm.node_offset):
        for d in (3, 4, 5):
            s[offs + d] = radius[si]
    return s


def _classify(lam, V, asm, speeds, K, *, rigid_tol, overdamped_zeta, type_threshold, max_frequency):
    lam = np.asarray(lam)
    mag = np.abs(lam)
    KV = K @ V
    strain = np.abs(np.einsum("ij,ij->j", V.conj(), KV))
    kinetic = np.real(np.einsum("ij,ij->j", V.conj(), asm.M @ V))
    rigid = np.sqrt(strain / np.maximum(kinetic, 1e-300)) < rigid_tol
    imag_tol = 1e-9 * np.maximum(mag, 1.0)
    is_real = (np.abs(lam.imag) <= imag_tol) | rigid
    real_vals = lam[is_real].real
    real_rigid = rigid[is_real]
    order_r = np.argsort(real_vals)[::-1]
    real_vals, real_rigid = real_vals[order_r], real_rigid[order_r]
    n_rigid = int(np.sum(rigid))
    sel = (~is_real) & (lam.imag > 0)
    if max_frequency is not None:
        sel &= lam.imag <= max_frequency
    idx = np.flatnonzero(sel)
    idx = idx[np.argsort(lam[idx].imag, kind="stable")]
    lam_m, phi = lam[idx], V[:, idx].T  # (m,), (m, n_dof)

    # normalise: largest physical displacement = 1 at zero phase
    scale = _scale_vector(asm)
    phys = np.abs(phi) * scale
    kmax = np.argmax(phys, axis=1)
    ref = phi[np.arange(len(idx)), kmax] * scale[kmax]
    phi = phi / ref[:, None]

    # kinetic-energy fractions by DOF kind
    Md = asm.M
    kind = asm.dof_kind()
    frac = np.zeros((len(idx), 3))
    for k in range(3):
        mask = (kind == k).astype(float)
        Mk = Md.multiply(mask[:, None]).multiply(mask[None, :]).tocsr()
        frac[:, k] = np.real(np.einsum("mi,mi->m", phi.conj(), (Mk @ phi.T).T))
    frac = np.maximum(frac, 0.0)
    frac /= np.maximum(frac.sum(axis=1, keepdims=True), 1e-300)
    order = (0, 2, 1)  # L, T, A
    types = []
    for f in frac:
        names = [KIND_NAMES[k] for k in order if f[k] >= type_threshold]
        types.append("-".join(names) if names else KIND_NAMES[int(np.argmax(f))])

    # whirl per shaft
    whirl_ps = []
    whirl = []
    nominal = asm.speed_ratio
    for p in phi:
        per_shaft, lat_amp = [], []
        for si, offs in enumerate(asm.node_offset):
            X, Y = p[offs], p[offs + 1]
            amp = np.sum(np.abs(X) ** 2 + np.abs(Y) ** 2)
            lat_amp.append(amp)
            ccw = np.sum(np.imag(X * np.conj(Y)))
            spin = np.sign(speeds[si]) if speeds[si] != 0 else np.sign(nominal[si]) or 1.0
            if amp < 1e-12:
                per_shaft.append("-")
            else:
                per_shaft.append("F" if ccw * spin > 0 else "B")
        whirl_ps.append(tuple(per_shaft))
        whirl.append(per_shaft[int(np.argmax(lat_amp))])

    zeta = -lam_m.real / np.abs(lam_m)
    overdamped = zeta >= overdamped_zeta
    return dict(
        eigenvalues=lam_m,
        mode_shapes=phi,
        whirl_per_shaft=tuple(whirl_ps),
        whirl=tuple(whirl),
        energy_fractions=frac,
        mode_type=tuple(types),
        overdamped=overdamped,
        real_eigenvalues=real_vals,
        rigid_body=real_rigid,
        n_rigid_body=n_rigid,
    )


def modal(
    model: Train | Assembly,
    *,
    speed: float | None = None,
    max_frequency: float | None = None,
    n_modes: int | None = None,
    method: str = "auto",
    rigid_tol: float | None = None,
    overdamped_zeta: float = 0.999,
    type_threshold: float = 0.1,
    sparse_k: int | None = None,
    operating_point=None,
) -> ModalResult:
    """Damped eigenvalues and modes of a train at a reference-shaft speed.

    Parameters
    ----------
    model : a :class:`Train` or its :class:`Assembly`
    speed : rad/s, speed of the reference shaft (default: the model's nominal speed)
    max_frequency : rad/s, keep modes with damped frequency up to this value
    n_modes : keep at most this many (lowest) modes
    method : ``"auto"``, ``"dense"`` or ``"sparse"``
    rigid_tol : rad/s, strain-energy frequency below which a mode is a rigid-body mode
        (default 1e-2 rad/s, 0.1 rpm: far below any bearing or elastic mode, far above the
        round-off of a free mode, ~1e-5 rad/s)
    overdamped_zeta : damping ratio from which a complex pair is flagged over-damped
    type_threshold : kinetic-energy fraction from which a DOF group names the mode type
    sparse_k : initial number of eigenvalues the sparse solver asks for (it doubles the number
        until every mode below ``max_frequency`` is enclosed)
    operating_point : name or :class:`~gearrotor.model.OperatingPoint`: fluid-film bearings at
        the coefficients of the point's static loads (at ``speed``, default the point's speed)
        and the meshes on the loaded flank (:func:`~gearrotor.analyses.static.at_operating_point`)
    """
    if operating_point is not None:
        from .static.operating import model_at_operating_point

        at = None if speed is None else [float(speed)]
        model, w_op = model_at_operating_point(model, operating_point, at)
        speed = w_op if speed is None else float(speed)
    asm = model if isinstance(model, Assembly) else assemble(model)
    w = asm.train.speed if speed is None else float(speed)
    M, C, G, K = asm.matrices(w)
    Cg = C + G
    if method == "auto":
        method = "dense" if asm.n_dof <= DENSE_LIMIT else "sparse"
    if method == "dense":
        lam, V = _solve_dense(M.toarray(), Cg.toarray(), K.toarray(), asm)
    elif method == "sparse":
        lam, V = _solve_sparse(
            M.tocsc(), Cg.tocsc(), K.tocsc(), asm, max_frequency, n_modes, sparse_k
        )
    else:
        raise ValueError(f"unknown method {method!r}; expected 'auto', 'dense' or 'sparse'")
    if not np.all(np.isfinite(lam)):
        raise SolverError("the eigensolver returned non-finite eigenvalues")
    if rigid_tol is None:
        rigid_tol = 1e-2
    res = _classify(
        lam,
        V,
        asm,
        asm.shaft_speeds(w),
        K,
        rigid_tol=rigid_tol,
        overdamped_zeta=overdamped_zeta,
        type_threshold=type_threshold,
        max_frequency=max_frequency,
    )
    if n_modes is not None:
        for key in ("eigenvalues", "mode_shapes", "energy_fractions", "overdamped"):
            res[key] = res[key][:n_modes]
        for key in ("whirl_per_shaft", "whirl", "mode_type"):
            res[key] = res[key][:n_modes]
    return ModalResult(
        speed=w,
        shaft_speeds=asm.shaft_speeds(w),
        method=method,
        n_eigenvalues=int(np.sum(np.abs(lam) <= max_frequency)) if max_frequency else len(lam),
        shaft_names=tuple(s.name for s in asm.train.shafts),
        assembly=asm,
        **res,
    )
