"""Damped eigenvalues of the linear train at a speed (SPEC 3.1).

State-space form with z = [q, q̇]:

    A z = λ B z,   A = [[0, I], [−K, −(C + G)]],   B = [[I, 0], [0, M]].

Eigensolver (``method="auto"``, measured by ``benchmarks/scaling.py``):

* **every eigenvalue wanted** (no ``max_frequency``): the dense QR algorithm (LAPACK ``geev``)
  on ``B⁻¹A`` (M factored once by Cholesky) up to ``DENSE_LIMIT`` = 2000 DOFs; above, where a
  dense solve takes minutes, the sparse solver's ``n_modes`` (default 20) lowest modes;
* **the modes below max_frequency wanted**: dense below ``SPARSE_FROM`` = 300 DOFs, sparse
  shift-invert Arnoldi (ARPACK) from there on. The measured crossover is ~200 DOFs (sparse is
  1.7× faster at 252, 5–7× at 336 (ROSS's compressor example, issue 28), 2.5–7× at 500, 4–30×
  at 1000, 34× at 1464: dense grows as DOF³, sparse with the number of wanted modes); below
  300 DOFs (every shipped example: ≤ 252) a dense solve costs under ~0.3 s and it returns
  every eigenvalue, which the sparse solve does not (next point). If the sparse solve
  would have to find more than ``SPARSE_FRACTION`` (1/6) of the 2n eigenvalues to enclose
  max_frequency, it is no cheaper than dense and "auto" solves densely instead
  (``ModalResult.method`` says which solver ran).

A model with speed × whirl tables (bearings or seals whose coefficients depend on the whirl
frequency) is solved with the tables' fitted states added to the first-order form,
:mod:`gearrotor.analyses.lateral.whirl`, by the same dense/sparse rule on the augmented system.

The sparse solver finds the eigenvalues within a circle about a small negative real shift,
raising the number requested (:func:`_next_k`) until every eigenvalue with
``|λ| ≤ max_frequency`` is enclosed, and returns those: every mode with |λ| ≤ max_frequency,
where the dense result also lists heavily damped pairs with Im λ ≤ max_frequency < |λ| and the
real eigenvalues beyond max_frequency (the sparse solver found some of them, depending on how
many eigenvalues it had asked for). Its eigenpairs are refined on the quadratic problem to the
dense solve's accuracy (relative residual ≤ ``REFINE_TOL`` = 1e-10, :func:`_refine`).

Classification, one per eigenvalue, used by the table, the JSON, the footer and the report
alike (:attr:`ModalResult.mode_class`, :attr:`ModalResult.real_class`,
:meth:`ModalResult.class_counts`):

* **rigid-body** (real eigenvalues only): a mode that strains nothing: its strain-energy
  frequency ``√(|φᴴKφ| / φᴴMφ)`` is below ``rigid_tol`` and it does not grow faster than
  ``rigid_tol`` (free torsion of a geared pair, free axial motion). Judging by strain energy
  rather than by |λ| is robust: a zero eigenvalue of a free mode is a defective (Jordan) pair
  that round-off splits by ~√ε‖A‖ into two small, possibly complex, eigenvalues, while its
  eigenvector stays accurate;
* **unstable**: Re λ > ``ROUNDOFF``·|λ| (a growing complex pair, or a positive real eigenvalue
  beyond round-off: never "rigid-body" and never "over-damped");
* **over-damped**: a negative real eigenvalue (listed in ``real_eigenvalues``), or a complex
  pair with ζ ≥ ``overdamped_zeta``: its frequency is ~0 against its decay rate (it decays by
  e^{-2π ζ/√(1-ζ²)} < e^{-140} per period, it never shows an oscillation: typically a real pair of
  a heavily damped bearing split by gyroscopic coupling). Its ζ prints as ">0.9999", not 1;
* **undamped**: |Re λ| ≤ ``ROUNDOFF``·|λ|: the log dec and ζ are round-off and are reported as
  exactly 0 (not ±1e-14);
* **damped**: every other complex pair.

* **whirl** per shaft: the sense of the orbits of the shaft's nodes, weighted by amplitude,
  relative to that shaft's spin (``F`` forward, ``B`` backward, ``-`` no lateral motion);
* **type**: energy shares of the DOF groups lateral ``L`` (x, y, θx, θy, pedestals), torsional
  ``T`` (θz) and axial ``A`` (z). A group's share is the larger of its kinetic-energy fraction
  ``φᴴM_gφ / φᴴMφ`` and its strain-energy fraction ``U_g / U``. U_g is the group's diagonal
  block of the symmetric stiffness without the meshes, plus its part of the gear meshes' spring
  energy ``kg |δ|²``: the mesh deflection ``δ = w·φ = δ_L + δ_T + δ_A`` couples the groups, and
  each group takes the share ``|δ_g|² / Σ|δ_h|²`` of it (a mesh mode on rigid bearings is
  ``T``; a mesh deflected by whirl and twist together is ``L-T``). A mode with at least half
  of its kinetic energy in the pad DOFs of tilting-pad bearings with pad dynamics is a pad mode,
  type ``P`` (``pad_share``; its lateral, axial and torsional fractions are the shafts' shares of
  the whole kinetic energy, pads included, so a pad mode is not a lateral mode). The mode is
  named by every group with a share of at least ``type_threshold`` (default 5 %): ``L``, ``T``,
  ``A``, ``L-T``, ``L-T-A``, ... Both energies count because a stiff mesh couples without straining:
  in the flagship's 5978 rpm mode the gears roll on each other as the shafts whirl (7 % of the
  kinetic energy in torsion, ~0 in the mesh spring), while in its 57,000 rpm mode the mesh
  spring holds 15 % of the strain energy. A strain-free (rigid-body) mode's shares are
  kinetic only. The meshes' fraction of the strain energy is reported too (``share_mesh``).
"""

from __future__ import annotations

import weakref
from dataclasses import dataclass, field

import numpy as np
import scipy.linalg as la
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from numpy.typing import NDArray

from ...assembly import Assembly, assemble
from ...errors import ModelError, SolverError
from ...model import Train
from ...threads import limit, managed
from .whirl import frequency_dependent
from .whirl import solve as solve_whirl

__all__ = [
    "ModalResult",
    "modal",
    "DENSE_LIMIT",
    "SPARSE_FROM",
    "MODE_CLASSES",
    "REAL_CLASSES",
    "auto_method",
    "format_log_dec",
    "format_zeta",
    "shares_to_types",
    "state_matrices",
]

DENSE_LIMIT = 2000  # DOFs up to which "auto" solves densely when every eigenvalue is wanted
SPARSE_FROM = 300  # DOFs from which "auto" solves sparsely when max_frequency is given
SPARSE_FRACTION = 1 / 6  # share of the 2n eigenvalues beyond which sparse costs as dense
KIND_NAMES = ("L", "A", "T")  # index = Assembly.dof_kind() code
# |Re λ| / |λ| at or below which a pair's damping is round-off: conservative modes come out of
# the dense solver at ~1e-15 and out of ARPACK (sparse, a Campbell sweep) at up to ~1e-8
ROUNDOFF = 1e-7
TYPE_THRESHOLD = 0.05  # energy share from which a DOF group (or the mesh) names the mode type
# share of the fitted states of speed × whirl tables from which a mode is bearing-internal (P):
# their largest amplitude at least 3× the rotor's largest displacement (analyses/whirl.py)
STATE_SHARE_P = 0.9
MODE_CLASSES = ("damped", "undamped", "over-damped", "unstable")
REAL_CLASSES = ("rigid-body", "over-damped", "unstable")


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
    overdamped: NDArray  # bool (n,): mode_class == "over-damped"
    real_eigenvalues: NDArray  # real eigenvalues (over-damped / rigid-body / unstable), 1/s
    rigid_body: NDArray  # bool per real eigenvalue: real_class == "rigid-body"
    n_rigid_body: int
    # (n, 4): lateral, axial, torsional shares (max of kinetic and strain fractions) and the
    # mesh springs' strain-energy fraction; they name mode_type (module docstring)
    energy_shares: NDArray
    mode_class: tuple[str, ...]  # per mode, one of MODE_CLASSES
    real_class: tuple[str, ...]  # per real eigenvalue, one of REAL_CLASSES
    method: str
    n_eigenvalues: int  # eigenvalues with |λ| ≤ max_frequency (all returned if none given)
    shaft_names: tuple[str, ...]
    assembly: Assembly = field(repr=False)
    # (n,) kinetic-energy fraction in the pad DOFs (bearings with pad dynamics; 0 without), or
    # the states' share of a speed × whirl table (analyses/whirl.py), whichever is larger
    pad_share: NDArray | None = None
    # speed × whirl tables: how the frequency dependence was solved and its work (eigensolves,
    # states, the tables' whirl ranges and fit misfits; analyses/whirl.py), else None
    frequency_dependence: dict | None = None
    # (n,) bool: a mode of the fitted states of a speed × whirl table (typed P), else None
    state_mode: NDArray | None = None

    @property
    def damped_frequency(self) -> NDArray:
        return self.eigenvalues.imag

    @property
    def natural_frequency(self) -> NDArray:
        return np.abs(self.eigenvalues)

    @property
    def damping_ratio(self) -> NDArray:
        """ζ = −Re λ / |λ|; exactly 0 for an undamped mode (round-off, see ``mode_class``)."""
        return np.where(self._undamped, 0.0, -self.eigenvalues.real / np.abs(self.eigenvalues))

    @property
    def log_dec(self) -> NDArray:
        """δ = −2π Re λ / Im λ; exactly 0 for an undamped mode (round-off)."""
        return np.where(
            self._undamped, 0.0, -2 * np.pi * self.eigenvalues.real / self.eigenvalues.imag
        )

    @property
    def _undamped(self) -> NDArray:
        return np.abs(self.eigenvalues.real) <= ROUNDOFF * np.abs(self.eigenvalues)

    @property
    def frequency_rpm(self) -> NDArray:
        return self.damped_frequency * 30 / np.pi

    @property
    def frequency_hz(self) -> NDArray:
        return self.damped_frequency / (2 * np.pi)

    @property
    def stable(self) -> bool:
        return not bool(np.any(self.unstable)) and "unstable" not in self.real_class

    @property
    def unstable(self) -> NDArray:
        """Growing modes: Re λ > ``ROUNDOFF`` |λ| (round-off of a conservative mode stays
        below; log dec < −6.3e-7)."""
        return self.eigenvalues.real > ROUNDOFF * np.abs(self.eigenvalues)

    def class_counts(self) -> dict[str, dict[str, int]]:
        """How many modes (complex pairs, the table's rows) and real eigenvalues of each class."""
        return {
            "modes": {c: self.mode_class.count(c) for c in MODE_CLASSES},
            "real_eigenvalues": {c: self.real_class.count(c) for c in REAL_CLASSES},
        }

    def counts_line(self) -> str:
        """The footer of the table (and the report's note): the class counts in words."""
        cc = self.class_counts()
        modes = ", ".join(f"{v} {k}" for k, v in cc["modes"].items() if v)
        real = ", ".join(f"{v} {k}" for k, v in cc["real_eigenvalues"].items() if v)
        line = f"modes: {len(self)} ({modes or 'none'})"
        if len(self.real_eigenvalues):
            line += f"; real eigenvalues: {len(self.real_eigenvalues)} ({real})"
        return line

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
                "share_lateral": float(self.energy_shares[i, 0]),
                "share_axial": float(self.energy_shares[i, 1]),
                "share_torsional": float(self.energy_shares[i, 2]),
                "share_mesh": float(self.energy_shares[i, 3]),
                "energy_pads": float(self.pad_share[i]) if self.pad_share is not None else 0.0,
                "class": self.mode_class[i],
                "stable": not bool(self.unstable[i]),
                "overdamped": bool(self.overdamped[i]),
            }
            if shapes:
                d["shape"] = self.shape_dict(i)
            modes.append(d)
        real = [
            {
                "eigenvalue": float(v),
                "class": c,
                "rigid_body": c == "rigid-body",
                "decay_time_s": (float(-1 / v) if c == "over-damped" else None),
            }
            for v, c in zip(self.real_eigenvalues, self.real_class, strict=True)
        ]
        return {
            "speed_rpm": _rpm(self.speed),
            "shaft_speeds_rpm": dict(
                zip(self.shaft_names, (_rpm(s) for s in self.shaft_speeds), strict=True)
            ),
            "n_dof": int(self.assembly.n_dof),
            "method": self.method,
            "stable": self.stable,
            "n_rigid_body_modes": int(self.n_rigid_body),
            "class_counts": self.class_counts(),
            "modes": modes,
            "real_modes": real,
            **(
                {"frequency_dependence": self.frequency_dependence}
                if self.frequency_dependence is not None
                else {}
            ),
        }

    def table(self) -> str:
        """A plain-text table of the modes."""
        head = (
            f"{'#':>3} {'freq rpm':>12} {'freq Hz':>10} {'log dec':>9} {'zeta':>7} "
            f"{'whirl':>6} {'type':>6}  notes"
        )
        rows = [head, "-" * len(head)]
        ld, zeta = self.log_dec, self.damping_ratio
        for i in range(len(self)):
            cls = self.mode_class[i]
            whirl = (
                "/".join(self.whirl_per_shaft[i]) if len(self.shaft_names) > 1 else self.whirl[i]
            )
            rows.append(
                f"{i:>3} {self.frequency_rpm[i]:>12.2f} {self.frequency_hz[i]:>10.3f} "
                f"{format_log_dec(ld[i]):>9} {format_zeta(zeta[i]):>7} {whirl:>6} "
                f"{self.mode_type[i]:>6}  {_NOTE[cls]}"
            )
        rows.append(self.counts_line())
        fd = self.frequency_dependence
        if fd is not None:
            misfit = max((e["max_misfit"] for e in fd["elements"]), default=0.0)
            rows.append(
                f"speed × whirl tables: {fd['states']} fitted states (largest misfit "
                f"{misfit:.2g}), {fd['eigensolves']} eigensolve; type P: modes of the tables' "
                "own dynamics (the rotor barely moves)"
            )
            if fd["modes_beyond_whirl_tables"]:
                rows.append(
                    "modes above the tables' highest whirl frequency: "
                    f"{fd['modes_beyond_whirl_tables']} (they see the fits' continuation)"
                )
        return "\n".join(rows)


_NOTE = {"damped": "", "undamped": "undamped", "over-damped": "over-damped", "unstable": "UNSTABLE"}


def _rpm(w: float) -> float:
    """rad/s → rpm to 12 significant digits: a speed given as 6500 rpm reads 6500.0, not the
    round trip's 6499.999999999999."""
    return float(f"{w * 30 / np.pi:.12g}")


def format_log_dec(v: float) -> str:
    return "0" if v == 0 else f"{v:.4g}"


def format_zeta(z: float) -> str:
    """ζ to 4 decimals, never rounded up to 1 (an oscillating pair has ζ < 1)."""
    if 0.99995 <= z < 1.0:
        return ">0.9999"
    return "0" if z == 0 else f"{z:.4f}"


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
    with limit(2 * n, "eig"):  # more threads only for large state matrices on free cores
        lam, V = la.eig(A, overwrite_a=True, check_finite=False)
    return lam, V[:n]


def auto_method(n_dof: int, max_frequency: float | None) -> str:
    """The solver ``method="auto"`` starts with (module docstring): ``"sparse"`` from
    ``SPARSE_FROM`` DOFs when ``max_frequency`` is given, else ``"dense"`` up to
    ``DENSE_LIMIT`` DOFs."""
    if max_frequency is not None:
        return "sparse" if n_dof >= SPARSE_FROM else "dense"
    return "dense" if n_dof <= DENSE_LIMIT else "sparse"


def _solve_sparse(
    M, Cg, K, asm, max_frequency, n_modes, k0=None, k_max=None
) -> tuple[NDArray, NDArray] | None:
    """Shift-invert Arnoldi on the first-order form, then a Newton refinement of each wanted
    eigenpair on the quadratic problem (:func:`_refine`). None when enclosing
    ``max_frequency`` would take more than ``k_max`` eigenvalues (given by "auto" only).

    The state is z = [q, q̇/s] with s = ``max_frequency`` (rad/s): its two halves then have
    the same size for the wanted modes, where [q, q̇] would differ by |λ| (up to 10⁴), and
    ARPACK's Ritz vectors' largest residual on the quadratic problem falls from 2.2e-6 to
    2.0e-10 on the compressor example (measured before the refinement; on SPEC 6.1 it stays
    ~2e-6, which the refinement brings to 1e-12)."""
    n = M.shape[0]
    scale = max_frequency if max_frequency else 1.0
    sigma = -1e-3 * scale
    op = _shift_invert(M, Cg, K, sigma, scale, asm)
    k = min(k0 or max(n_modes or 20, 10), 2 * n - 2)
    # a fixed start vector: ARPACK's default is random, which made repeated calls (and the
    # Campbell diagram's tracking) differ in the last digits; a seeded generic vector keeps every
    # mode's component non-zero and makes results reproducible
    v0 = np.random.default_rng(20261125).standard_normal(2 * n)
    while True:
        try:
            nu, V = spla.eigs(op, k=k, which="LM", v0=v0)
        except spla.ArpackNoConvergence as exc:
            raise SolverError(f"sparse eigensolver did not converge for {k} modes: {exc}") from None
        lam = sigma + 1.0 / nu
        if max_frequency is None and n_modes and k < 2 * n - 2:
            # the n_modes lowest modes: conjugate pairs, rigid-body and real (over-damped)
            # eigenvalues take some of the k found; ask for more until there are n_modes, then
            # solve for the circle that holds them with the state scaled to it (accuracy)
            osc = np.sort(np.abs(lam[lam.imag > ROUNDOFF * np.abs(lam)]))
            if len(osc) < n_modes:
                k = min(2 * k, 2 * n - 2)
                continue
            return _solve_sparse(M, Cg, K, asm, 1.05 * osc[n_modes - 1], None, k)
        if (
            max_frequency is None
            or k >= 2 * n - 2
            or np.max(np.abs(lam - sigma)) > max_frequency + abs(sigma)
        ):
            X = V[:n]
            lam, X, _ = _refine(M, Cg, K, lam, X, max_frequency)
            if max_frequency is not None:
                # what lies beyond the circle depends on how many were asked for: keep the
                # circle, whose every eigenvalue is found
                inside = np.abs(lam) <= max_frequency
                lam, X = lam[inside], X[:, inside]
            return lam, X
        k = min(_next_k(k, np.abs(lam - sigma), max_frequency + abs(sigma)), 2 * n - 2)
        if k_max is not None and k > k_max:
            return None


def _shift_invert(M, Cg, K, sigma: float, scale: float, asm) -> spla.LinearOperator:
    """The shift-invert operator (A − σB)⁻¹B of the first-order form in the scaled state
    z = [q, q̇/s] (A = [[0, sI], [−K/s, −(C+G)]], B = diag(I, M)) applied through one sparse LU
    of the n×n quadratic pencil P(σ) = σ²M + σ(C+G) + K instead of the 2n×2n first-order
    matrix: (A − σB)z = [v₁, Mv₂] gives z₁ = −P(σ)⁻¹(sMv₂ + (C+G+σM)v₁), z₂ = (v₁ + σz₁)/s.
    Half the order, the band of the finite-element model kept (issue 28: the 336-DOF ROSS
    compressor's solve 2–3× faster than SciPy's generalised shift-invert mode)."""
    n = M.shape[0]
    P = (sigma * sigma) * M + sigma * Cg + K
    try:
        lu = spla.splu(sp.csc_array(P))
    except RuntimeError:  # SuperLU could not factor P(σ): M (or K) is singular
        raise _singular_mass(asm) from None
    CsM = sp.csr_array(Cg + sigma * M)
    Mr = sp.csr_array(M)

    def matvec(v: NDArray) -> NDArray:
        v1, v2 = v[:n], v[n:]
        z1 = -lu.solve(scale * (Mr @ v2) + CsM @ v1)
        return np.concatenate([z1, (v1 + sigma * z1) / scale])

    return spla.LinearOperator((2 * n, 2 * n), matvec=matvec, dtype=float)


def _next_k(k: int, dist: NDArray, wanted: float) -> int:
    """How many eigenvalues to ask for next when the k nearest the shift, at distances
    ``dist``, do not reach ``wanted``: the count N(r) within a radius r extrapolated from its
    local growth among the found ones, N ∝ r^p with p from the outer half (p = 1 for rods'
    torsion and axial modes, ½ for beams' bending modes, less where the bearing modes of many
    shafts crowd the low end), with a 20 % margin, between 1.5k and 4k. Plain doubling took six
    ARPACK runs (k = 20 … 640) for the 165 modes (330 eigenvalues) of a 16-shaft train, and a
    linear extrapolation asked for 1280 (86 s instead of 22 s)."""
    d = np.sort(np.asarray(dist, float))
    if len(d) < 4 or d[len(d) // 2 - 1] <= 0:
        return 2 * k
    p = np.log(len(d) / (len(d) // 2)) / np.log(max(d[-1] / d[len(d) // 2 - 1], 1.0 + 1e-12))
    grow = 1.2 * (wanted / max(d[-1], 1e-300)) ** min(p, 1.0)
    return int(np.ceil(k * min(max(grow, 1.5), 4.0)))


# relative residual (:func:`_residuals`) below which an eigenpair counts as converged: the dense
# QR solve's pairs reach 1e-12 to 1e-10 on the examples (M⁻¹K's rounding); refined sparse
# pairs 1e-13 to 1e-11
REFINE_TOL = 1e-10
_REFINE_STEPS = 3


def _residuals(M, Cg, K, lam: NDArray, X: NDArray) -> NDArray:
    """Relative residual of each eigenpair (λ_j, x_j = X[:, j]) of the quadratic problem:
    ‖P(λ)x‖ / (|λ|²‖Mx‖ + |λ|‖(C+G)x‖ + ‖Kx‖), P(λ) = λ²M + λ(C+G) + K."""
    return _relative_residual(lam, M @ X, Cg @ X, K @ X)


def _relative_residual(lam: NDArray, MX: NDArray, CX: NDArray, KX: NDArray) -> NDArray:
    """:func:`_residuals` from the products MX, (C+G)X, KX (e.g. a projection's, formed once)."""
    R = MX * lam**2 + CX * lam + KX
    a = np.abs(lam)
    den = (
        a**2 * np.linalg.norm(MX, axis=0)
        + a * np.linalg.norm(CX, axis=0)
        + np.linalg.norm(KX, axis=0)
    )
    return np.linalg.norm(R, axis=0) / np.maximum(den, 1e-300)


def _clusters(lam: NDArray, idx: NDArray, rel: float) -> list[NDArray]:
    """The indices ``idx`` grouped into clusters of eigenvalues closer than ``rel``·|λ| to a
    member (chains joined): identical shafts give repeated eigenvalues."""
    order = idx[np.argsort(lam[idx].imag, kind="stable")]
    groups: list[list[int]] = []
    for j in order:
        for g in groups:
            if np.min(np.abs(lam[g] - lam[j])) <= rel * abs(lam[j]):
                g.append(int(j))
                break
        else:
            groups.append([int(j)])
    return [np.array(g) for g in groups]


def _refine(M, Cg, K, lam, X, max_frequency) -> tuple[NDArray, NDArray, dict]:
    """Refine the eigenpairs the result keeps (0 ≤ Im λ ≤ ``max_frequency``; not |λ| below
    1e-6·``max_frequency``, the rigid-body eigenvalues at ~0 where P(λ) ≈ K is singular) whose
    residual (:func:`_residuals`) exceeds ``REFINE_TOL``, by inverse iteration on the quadratic
    problem with a Rayleigh–Ritz projection, per cluster of close eigenvalues (J, at mean σ):

        Y = P(σ)⁻¹ P'(σ) X_J,  Q = orth(Y),  (λ²QᴴMQ + λQᴴ(C+G)Q + QᴴKQ) y = 0,  x = Qy,

    keeping the |J| Ritz values nearest the old ones. For a single eigenvalue this is Newton's
    method (quadratic convergence: ARPACK's ~1e-6 becomes ~1e-12 in one step, one sparse LU of
    P(σ) per step and cluster); a cluster (identical shafts give repeated eigenvalues) keeps its
    |J| independent vectors, where one vector at a time would fall onto the same eigenvector.
    A new pair is kept only if its residual is lower and λ moved by less than 1e-3·|λ|. Up to
    ``_REFINE_STEPS`` steps. Returns the eigenpairs and ``{"before", "after"}`` residuals and
    ``"refined"``, the indices considered."""
    lam = np.array(lam, complex)
    X = np.array(X, complex)
    res0 = _residuals(M, Cg, K, lam, X)
    res = res0.copy()
    small = 1e-6 * (max_frequency or np.max(np.abs(lam), initial=1.0))
    want = (lam.imag >= -ROUNDOFF * np.abs(lam)) & (np.abs(lam) >= small)
    if max_frequency is not None:
        want &= lam.imag <= max_frequency
    idx = np.flatnonzero(want & (res > REFINE_TOL))
    Cg, M, K = sp.csc_array(Cg), sp.csc_array(M), sp.csc_array(K)
    for J in _clusters(lam, idx, 1e-4):
        for _ in range(_REFINE_STEPS):
            sigma = complex(np.mean(lam[J]))
            try:
                lu = spla.splu(sp.csc_array(sigma * sigma * M + sigma * Cg + K))
            except RuntimeError:  # P(σ) exactly singular: σ is an eigenvalue to working precision
                break
            Y = lu.solve((2 * sigma * M + Cg) @ X[:, J])
            if not np.all(np.isfinite(Y)):
                break
            Q = la.qr(Y, mode="economic")[0]
            Mr, Cr, Kr = (Q.conj().T @ (A @ Q) for A in (M, Cg, K))
            c = len(J)
            mu, W = la.eig(
                np.block([[np.zeros((c, c)), np.eye(c)], [-Kr, -Cr]]),
                np.block([[np.eye(c), np.zeros((c, c))], [np.zeros((c, c)), Mr]]),
            )
            ok = np.isfinite(mu)
            mu, W = mu[ok], W[:c, ok]
            if len(mu) < c:
                break
            from scipy.optimize import linear_sum_assignment  # scipy.optimize: on use

            rows, cols = linear_sum_assignment(np.abs(lam[J][:, None] - mu[None, :]))
            new_l = mu[cols[np.argsort(rows)]]
            new_x = Q @ W[:, cols[np.argsort(rows)]]
            new_x /= np.linalg.norm(new_x, axis=0)
            new_r = _residuals(M, Cg, K, new_l, new_x)
            better = (new_r < res[J]) & (np.abs(new_l - lam[J]) < 1e-3 * np.abs(lam[J]))
            if not better.any():
                break
            jj = J[better]
            lam[jj], X[:, jj], res[jj] = new_l[better], new_x[:, better], new_r[better]
            if np.max(res[J]) <= REFINE_TOL:
                break
    return lam, X, {"before": res0, "after": res, "refined": idx}


@dataclass(frozen=True)
class _KindData:
    """What the classification needs of an Assembly that does not change with speed: the DOF
    kinds, the kinetic energy's kind-diagonal blocks, the meshes' DOFs per kind, the shape
    scale. Built once per Assembly (:func:`_kind_data`)."""

    kind: NDArray  # (n,) int: 0 L, 1 A, 2 T, 3 pad (Assembly.dof_kind)
    indicator: NDArray  # (3, n) float: row k is 1 on the DOFs of kind k (pads in none)
    pads: NDArray  # (n,) float: 1 on the pad DOFs
    M_bd: sp.csr_array  # M with the entries between DOFs of different kinds removed
    K0_bd: sp.csr_array  # the same of the speed-independent stiffness K0 (the strain energies)
    meshes: tuple[tuple[float, tuple[tuple[NDArray, NDArray], ...]], ...]  # (k, per kind (dofs, w))
    scale: NDArray  # _scale_vector
    # (shaft DOF x offsets, y offsets) per shaft, for the whirl
    xy: tuple[tuple[NDArray, NDArray], ...]


_KIND_CACHE: dict[int, tuple[weakref.ref, _KindData]] = {}


def _kind_data(asm: Assembly) -> _KindData:
    """The :class:`_KindData` of ``asm``, cached while ``asm`` lives (keyed by identity: an
    Assembly holds arrays, so it has no value hash)."""
    hit = _KIND_CACHE.get(id(asm))
    if hit is not None and hit[0]() is asm:
        return hit[1]
    kind = asm.dof_kind()
    indicator = np.zeros((3, asm.n_dof))
    shaft = kind < 3
    indicator[kind[shaft], np.flatnonzero(shaft)] = 1.0
    meshes = []
    for m in asm.meshes:
        sel = kind[m.dofs]
        meshes.append(
            (float(m.stiffness), tuple((m.dofs[sel == k], m.w[sel == k]) for k in range(3)))
        )
    data = _KindData(
        kind=kind,
        indicator=indicator,
        pads=(kind == 3).astype(float),
        M_bd=_kind_diagonal(asm.M, kind),
        K0_bd=_kind_diagonal(asm.K0, kind),
        meshes=tuple(meshes),
        scale=_scale_vector(asm),
        xy=tuple((offs, offs + 1) for offs in asm.node_offset),
    )
    key = id(asm)
    _KIND_CACHE[key] = (weakref.ref(asm, lambda _, key=key: _KIND_CACHE.pop(key, None)), data)
    return data


def _kind_diagonal(A, kind: NDArray) -> sp.csr_array:
    """A with the entries that couple DOFs of different kinds removed (a block-diagonal matrix
    in the kind ordering)."""
    A = sp.coo_array(A)
    keep = kind[A.row] == kind[A.col]
    return sp.csr_array((A.data[keep], (A.row[keep], A.col[keep])), shape=A.shape)


def _split(X: NDArray) -> tuple[NDArray, NDArray]:
    """Contiguous real and imaginary parts of X: a sparse matrix times a real C-ordered array
    is several times faster than times a strided complex one."""
    return np.ascontiguousarray(X.real), np.ascontiguousarray(X.imag)


def _quadratic(A, a: NDArray, b: NDArray) -> NDArray:
    """xᴴ A x (complex) for each column x = a + ib of X (n, m), A real (sparse), a and b as
    :func:`_split` gives them."""
    Aa, Ab = _times_both(A, a, b)
    return (
        np.einsum("ij,ij->j", a, Aa)
        + np.einsum("ij,ij->j", b, Ab)
        + 1j * (np.einsum("ij,ij->j", a, Ab) - np.einsum("ij,ij->j", b, Aa))
    )


def _times_both(A, a: NDArray, b: NDArray) -> tuple[NDArray, NDArray]:
    """(A a, A b) by one product with [a, b] (a sparse product's fixed cost, ~10 µs, is most of
    it for the few columns of a classification; every column's sums are the same)."""
    AB = A @ np.hstack([a, b])
    k = a.shape[1]
    return AB[:, :k], AB[:, k:]


def _by_kind(data: _KindData, A, X: NDArray) -> NDArray:
    """(m, 3): Re Σ_{i∈k} conj(x_i) (A_kk x_k)_i for each column x of X (n, m) and kind k, with
    A real and kind-diagonal (the kind blocks' quadratic forms Re x_kᴴ A_kk x_k)."""
    a, b = _split(X)
    Aa, Ab = _times_both(A, a, b)
    return (data.indicator @ (a * Aa + b * Ab)).T


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
    for b in asm.bearings:  # a pad tilt times its lever: the pad surface's motion
        if b.pad_dofs is not None:
            s[b.pad_dofs] = b.element.pads.lever[2:]
    return s


def _energy_shares(phi: NDArray, asm: Assembly, K, kin: NDArray | None = None) -> NDArray:
    """(m, 4) shares of lateral, axial and torsional energy, and the meshes' strain-energy
    fraction (see the module docstring). ``kin``: the (m, 3) kinetic energies by kind, when
    the caller has them.

    The strain energy of kind k is U_k = x_kᴴ K_s,kk x_k − Σ_meshes kg |w_k·x_k|² (K_s the
    symmetric part of K, x_k the mode's kind-k part, w_k the mesh vector's): x_kᴴ K_s,kk x_k =
    Re x_kᴴ K_kk x_k for a real K, and the kind-k block of a mesh spring kg w wᵀ gives
    kg |w_k·x_k|²."""
    data = _kind_data(asm)
    X = phi.T
    if kin is None:
        kin = _by_kind(data, data.M_bd, X)
    kin = np.maximum(kin, 0.0)
    n_m = len(phi)
    # (K0's blocks kept: a Campbell classifies every speed with the same K0, issue 28)
    K_bd = data.K0_bd if K is asm.K0 else _kind_diagonal(K, data.kind)
    strain = _by_kind(data, K_bd, X)
    parts = np.zeros((len(data.meshes), n_m, 3), complex)
    for j, (_, groups) in enumerate(data.meshes):
        for k, (dofs, w) in enumerate(groups):
            parts[j, :, k] = phi[:, dofs] @ w
    stiff = np.array([kg for kg, _ in data.meshes])
    p2 = np.abs(parts) ** 2  # (meshes, m, 3)
    strain -= np.einsum("j,jmk->mk", stiff, p2)
    strain = np.maximum(strain, 0.0)
    mesh = np.zeros(n_m)
    for j, kg in enumerate(stiff):
        # the mesh deflection δ = Σ_g δ_g: its energy goes to each group by |δ_g|² / Σ|δ_h|²
        e = kg * np.abs(parts[j].sum(axis=1)) ** 2
        strain += e[:, None] * p2[j] / np.maximum(p2[j].sum(axis=1, keepdims=True), 1e-300)
        mesh += e
    kin_frac = kin / np.maximum(kin.sum(axis=1, keepdims=True), 1e-300)
    total = strain.sum(axis=1)
    has_strain = total > 1e-12 * max(float(total.max(initial=0.0)), 1e-300)
    st = np.maximum(total, 1e-300)[:, None]
    shares = np.zeros((n_m, 4))
    shares[:, :3] = np.where(has_strain[:, None], np.maximum(kin_frac, strain / st), kin_frac)
    shares[:, 3] = np.where(has_strain, mesh / st[:, 0], 0.0)
    return shares


def shares_to_types(shares: NDArray, threshold: float = TYPE_THRESHOLD) -> tuple[str, ...]:
    """Mode types from energy shares (columns L, A, T): the groups at or above the threshold
    (the largest alone when none is)."""
    shares = np.asarray(shares)
    on = shares[:, :3] >= threshold
    none = ~on.any(axis=1)
    on[none, np.argmax(shares[none, :3], axis=1)] = True
    return tuple(_TYPE_NAMES[i] for i in on @ np.array([1, 2, 4]))


# the type of each set of groups at or above the threshold, by bits L = 1, A = 2, T = 4 (named
# in the order L, T, A)
_TYPE_NAMES = tuple(
    "-".join(KIND_NAMES[k] for k in (0, 2, 1) if bits >> k & 1) for bits in range(8)
)


def _classify(
    lam,
    V,
    asm,
    speeds,
    K,
    *,
    rigid_tol,
    overdamped_zeta,
    type_threshold,
    max_frequency,
    state_amplitude=None,
):
    lam = np.asarray(lam)
    mag = np.abs(lam)
    Vr, Vi = _split(V)
    strain = np.abs(_quadratic(K, Vr, Vi))
    MVr, MVi = _times_both(asm.M, Vr, Vi)
    kinetic = np.einsum("ij,ij->j", Vr, MVr) + np.einsum("ij,ij->j", Vi, MVi)
    # strain-free and not growing faster than rigid_tol: a positive real eigenvalue beyond the
    # tolerance is an instability, never a rigid-body mode
    rigid = (np.sqrt(strain / np.maximum(kinetic, 1e-300)) < rigid_tol) & (lam.real < rigid_tol)
    imag_tol = ROUNDOFF * np.maximum(mag, 1.0)
    is_real = (np.abs(lam.imag) <= imag_tol) | rigid
    real_vals = lam[is_real].real
    real_rigid = rigid[is_real]
    order_r = np.argsort(real_vals)[::-1]
    real_vals, real_rigid = real_vals[order_r], real_rigid[order_r]
    real_class = tuple(
        "rigid-body" if r else ("unstable" if v > ROUNDOFF * abs(v) else "over-damped")
        for v, r in zip(real_vals, real_rigid, strict=True)
    )
    n_rigid = real_class.count("rigid-body")
    sel = (~is_real) & (lam.imag > 0)
    if max_frequency is not None:
        sel &= lam.imag <= max_frequency
    idx = np.flatnonzero(sel)
    idx = idx[np.argsort(lam[idx].imag, kind="stable")]
    lam_m, phi = lam[idx], V[:, idx].T  # (m,), (m, n_dof)

    # normalise: largest physical displacement = 1 at zero phase
    data = _kind_data(asm)
    scale = data.scale
    phys = np.abs(phi) * scale
    kmax = np.argmax(phys, axis=1)
    if state_amplitude is not None:  # the states of speed × whirl tables (analyses/whirl.py)
        a2 = np.asarray(state_amplitude)[idx] ** 2
        state_share = a2 / np.maximum(a2 + phys[np.arange(len(idx)), kmax] ** 2, 1e-300)
    ref = phi[np.arange(len(idx)), kmax] * scale[kmax]
    phi = phi / ref[:, None]

    # kinetic-energy fractions by DOF kind (reported), and the energy shares that name the type
    kin = np.maximum(_by_kind(data, data.M_bd, phi.T), 0.0)
    pad_kin = np.zeros(len(idx))
    if data.pads.any():
        a, b = _split(phi.T)
        pad_kin = np.maximum(data.pads @ (a * (data.M_bd @ a) + b * (data.M_bd @ b)), 0.0)
    total_kin = np.maximum(kin.sum(axis=1) + pad_kin, 1e-300)
    frac = kin / total_kin[:, None]
    pad_share = pad_kin / total_kin
    internal = pad_share >= 0.5
    state_mode = None
    if state_amplitude is not None:
        # the states' amplitude only approximates a displacement: a mode is typed P (not
        # judged as a lateral mode) only when the rotor barely moves (analyses/whirl.py); its
        # shafts' fractions are their share of it, the states taking the rest (as the pads'
        # kinetic energy does in a pad mode)
        in_states = state_share >= STATE_SHARE_P
        state_mode = in_states
        internal |= in_states
        frac[in_states] *= (1.0 - state_share[in_states])[:, None]
        pad_share = np.maximum(pad_share, state_share)
    shares = _energy_shares(phi, asm, K, kin)
    types = tuple(
        "P" if p else t
        for t, p in zip(shares_to_types(shares, type_threshold), internal, strict=True)
    )

    # whirl per shaft: the sense of the orbits weighted by amplitude, relative to the spin
    nominal = asm.speed_ratio
    amp = np.zeros((len(idx), len(data.xy)))
    sense = np.zeros((len(idx), len(data.xy)))
    for si, (ix, iy) in enumerate(data.xy):
        X, Y = phi[:, ix], phi[:, iy]
        amp[:, si] = np.sum(np.abs(X) ** 2 + np.abs(Y) ** 2, axis=1)
        ccw = np.sum(np.imag(X * np.conj(Y)), axis=1)
        spin = np.sign(speeds[si]) if speeds[si] != 0 else np.sign(nominal[si]) or 1.0
        sense[:, si] = ccw * spin
    letters = np.where(amp < 1e-12, "-", np.where(sense > 0, "F", "B"))
    whirl_ps = [tuple(row) for row in letters.tolist()]
    whirl = [row[int(j)] for row, j in zip(whirl_ps, np.argmax(amp, axis=1), strict=True)]

    zeta = -lam_m.real / np.abs(lam_m)
    mode_class = []
    for z, lr, lm in zip(zeta, lam_m.real, np.abs(lam_m), strict=True):
        if lr > ROUNDOFF * lm:
            mode_class.append("unstable")
        elif abs(lr) <= ROUNDOFF * lm:
            mode_class.append("undamped")
        elif z >= overdamped_zeta:
            mode_class.append("over-damped")
        else:
            mode_class.append("damped")
    overdamped = np.array([c == "over-damped" for c in mode_class], bool)
    return dict(
        eigenvalues=lam_m,
        mode_shapes=phi,
        whirl_per_shaft=tuple(whirl_ps),
        whirl=tuple(whirl),
        energy_fractions=frac,
        mode_type=types,
        overdamped=overdamped,
        real_eigenvalues=real_vals,
        rigid_body=np.array([c == "rigid-body" for c in real_class], bool),
        n_rigid_body=n_rigid,
        energy_shares=shares,
        mode_class=tuple(mode_class),
        real_class=real_class,
        pad_share=pad_share,
        state_mode=state_mode,
    )


@managed
def modal(
    model: Train | Assembly,
    *,
    speed: float | None = None,
    max_frequency: float | None = None,
    n_modes: int | None = None,
    method: str = "auto",
    rigid_tol: float | None = None,
    overdamped_zeta: float = 0.999,
    type_threshold: float = TYPE_THRESHOLD,
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
    method : ``"auto"`` (the rule in the module docstring, :func:`auto_method`), ``"dense"``
        (every eigenvalue) or ``"sparse"`` (the modes within |λ| ≤ max_frequency, else the
        ``n_modes`` lowest)
    rigid_tol : rad/s, strain-energy frequency below which a mode is a rigid-body mode
        (default 1e-2 rad/s, 0.1 rpm: far below any bearing or elastic mode, far above the
        round-off of a free mode, ~1e-5 rad/s)
    overdamped_zeta : damping ratio from which a complex pair is flagged over-damped
    type_threshold : energy share (kinetic + strain, see the module docstring) from which a DOF
        group, or the mesh springs, name the mode type (default 5 %)
    sparse_k : initial number of eigenvalues the sparse solver asks for (it raises the number
        until every mode below ``max_frequency`` is enclosed)
    operating_point : name or :class:`~gearrotor.model.OperatingPoint`: fluid-film bearings at
        the coefficients of the point's static loads (at ``speed``, default the point's speed)
        and the meshes on the loaded flank (:func:`~gearrotor.analyses.static.at_operating_point`)
    """
    if operating_point is not None:
        from ..static.operating_point import model_at_operating_point

        at = None if speed is None else [float(speed)]
        model, w_op = model_at_operating_point(model, operating_point, at)
        speed = w_op if speed is None else float(speed)
    asm = model if isinstance(model, Assembly) else assemble(model)
    w = asm.train.speed if speed is None else float(speed)
    if method not in ("auto", "dense", "sparse"):
        raise ValueError(f"unknown method {method!r}; expected 'auto', 'dense' or 'sparse'")
    work = state_amplitude = None
    if frequency_dependent(asm):
        # speed × whirl tables: the fits' states added to the eigenproblem (analyses/whirl.py)
        if method == "auto":
            method = auto_method(asm.n_dof, max_frequency)
        if method == "sparse" and max_frequency is None and n_modes is None:
            method = "dense"
        lam, V, K, state_amplitude, work = solve_whirl(
            asm, w, max_frequency=max_frequency, method=method, n_modes=n_modes
        )
    else:
        lam, V, K, method = _solve(asm, w, method, max_frequency, n_modes, sparse_k)
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
        state_amplitude=state_amplitude,
    )
    if n_modes is not None:
        for key in (
            "eigenvalues",
            "mode_shapes",
            "energy_fractions",
            "overdamped",
            "energy_shares",
            "pad_share",
            "state_mode",
        ):
            if res[key] is not None:
                res[key] = res[key][:n_modes]
        for key in ("whirl_per_shaft", "whirl", "mode_type", "mode_class"):
            res[key] = res[key][:n_modes]
    return ModalResult(
        speed=w,
        shaft_speeds=asm.shaft_speeds(w),
        method=method,
        n_eigenvalues=int(np.sum(np.abs(lam) <= max_frequency)) if max_frequency else len(lam),
        shaft_names=tuple(s.name for s in asm.train.shafts),
        assembly=asm,
        frequency_dependence=work,
        **res,
    )


def _solve(asm: Assembly, w: float, method: str, max_frequency, n_modes, sparse_k):
    """(λ, eigenvectors (n, k), K, the method used) of the quadratic problem at speed w."""
    M, C, G, K = asm.matrices(w)
    Cg = C + G
    k_max = None
    if method == "auto":
        method = auto_method(asm.n_dof, max_frequency)
        k_max = SPARSE_FRACTION * 2 * asm.n_dof if asm.n_dof <= DENSE_LIMIT else None
    if method == "sparse":
        out = _solve_sparse(
            M.tocsc(), Cg.tocsc(), K.tocsc(), asm, max_frequency, n_modes, sparse_k, k_max
        )
        if out is None:  # "auto": enclosing max_frequency needs too many eigenvalues
            method = "dense"
        else:
            lam, V = out
    if method == "dense":
        lam, V = _solve_dense(M.toarray(), Cg.toarray(), K.toarray(), asm)
    if not np.all(np.isfinite(lam)):
        raise SolverError("the eigensolver returned non-finite eigenvalues")
    return lam, V, K, method
