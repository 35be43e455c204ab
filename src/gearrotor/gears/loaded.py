"""Load sharing over the mesh cycle: loaded static transmission error (STE) and time-varying
mesh stiffness (TVMS) of a spur or helical pair under its operating torque.

Slice model. The face width b is cut into n slices of width Δb (helical gears: the contact line
of each tooth pair crosses the face obliquely, so a slice at axial position z sees the contact
shifted along the transverse line of action by ``z tan β_b``). At each position τ ∈ [0, 1) of
the mesh cycle (one transverse base pitch p_bt of roll), tooth pair k touches slice j at

    s_jk = s_A + (τ + k) p_bt + z_j tan β_b     (pinion driving; from s_E backwards when the
                                                 gear drives),

measured along the transverse line of action from T1; it is in contact where s_A ≤ s_jk ≤ s_E.
Each contact is a piece of contact line of length Δb / cos β_b with the compliance (per unit
length, :mod:`.tooth`) of the two teeth and of the Hertzian contact there; a helical pair's
teeth bend in their normal section, so their compliance is that of the virtual spur pair of
ISO 6336 (z_n = z / (cos² β_b cos β), normal module and pressure angle) at the same fraction
of its path of contact. Slices act independently (the slice model of the Weber–Banaschek
school, without coupling between neighbouring slices). The initial separation g_jk is the sum
of the two flanks' modifications there (profile reliefs in s, crowning and lead slope in z;
given along the transverse line of action, ×cos β_b along the normal). The gear bodies
approach by δ along the normal to the flanks (rigid-body rotation of the pair), and

    Σ_jk  k_jk · max(0, δ − g_jk) = F_n = T_pinion / (r_b1 cos β_b),   k_jk = Δb / (cos β_b c_jk),

is solved exactly for δ (piecewise linear and increasing in δ). The loaded STE is δ (it holds
the unloaded transmission error of the modifications, min g), the TVMS is the tangent
stiffness Σ_engaged k_jk, which is what the equations of motion linearised about the loaded
state need. Both are along the normal to the flanks, the direction of the rotor model's mesh
element (for a spur pair, the transverse line of action).

For the rotor model the pair acts as ``F = k(τ) (δ − e(τ))`` with the loaded TVMS k and
``e = STE − F_n / k``, the first-order expansion of the contact law about the loaded static
state: at the operating torque the static deflection is exactly the loaded STE and small
motions see the tangent stiffness (:meth:`MeshCurves.excitation`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from ..errors import ModelError
from ..model.gear_pair import FlankModifications, GearPair, ToothRelief
from .geometry import PairGeometry, pair_geometry
from .tooth import hertz_compliance, tooth_compliance, tooth_profile

__all__ = ["MeshCurves", "mesh_curves", "resolve_materials"]

_PATH_POINTS = 300  # compliance samples along the path of contact (interpolated between)


@dataclass(frozen=True)
class MeshCurves:
    """Loaded mesh of a gear pair over one mesh cycle (normal direction, SI units).

    position : (n,) fraction τ of the mesh cycle (0: a tooth pair enters contact at the start
    of the path, at mid-face); stiffness : (n,) N/m tangent TVMS; ste : (n,) m loaded static
    transmission error (approach of the flanks); nlte : (n,) m unloaded transmission error of
    the modifications; pair_load : (n, K) N normal load on each tooth pair k (k = 0 enters at
    τ = 0); pair_roll : (n, K) m roll position of pair k at mid-face (NaN out of contact);
    force : N normal mesh force; torque : N·m pinion torque; compliance_path : (m,) roll
    positions s and compliance_pair : (m,) m²/N transverse compliance of one pair per unit
    face width along the path (and its parts ``compliance_parts``, a dict of (m,) arrays).
    """

    geometry: PairGeometry
    torque: float
    driver: str
    slices: int
    position: NDArray
    stiffness: NDArray
    ste: NDArray
    nlte: NDArray
    pair_load: NDArray
    pair_roll: NDArray
    force: float
    harmonics: int
    compliance_path: NDArray
    compliance_pair: NDArray
    compliance_parts: dict

    # -- summary -----------------------------------------------------------------------------
    @property
    def mean_stiffness(self) -> float:
        return float(self.stiffness.mean())

    @property
    def max_stiffness(self) -> float:
        return float(self.stiffness.max())

    @property
    def min_stiffness(self) -> float:
        return float(self.stiffness.min())

    @property
    def contact_ratio(self) -> float:
        return self.geometry.contact_ratio

    @property
    def overlap_ratio(self) -> float:
        return self.geometry.overlap_ratio

    @property
    def ste_peak_to_peak(self) -> float:
        return float(self.ste.max() - self.ste.min())

    def fourier(self, values: NDArray, n: int | None = None) -> NDArray:
        """Complex Fourier coefficients c_h, h = 0..n, of a curve over the mesh cycle:
        ``values(τ) ≈ Re Σ_h c_h e^{2πihτ}`` with c_0 the mean and |c_h| the amplitude of
        harmonic h (from the samples, corrected for their linear interpolation)."""
        n = self.harmonics if n is None else n
        N = len(values)
        c = np.fft.rfft(values) / N
        c[1:] *= 2
        h = np.arange(len(c))
        c = c * np.sinc(h / N) ** -2 if N > 2 else c
        out = np.zeros(n + 1, complex)
        m = min(n + 1, len(c))
        out[:m] = c[:m]
        return out

    def ste_harmonics(self, n: int | None = None) -> NDArray:
        """|c_h| of the loaded STE (m), h = 1..n."""
        return np.abs(self.fourier(self.ste, n)[1:])

    def stiffness_harmonics(self, n: int | None = None) -> NDArray:
        """|c_h| of the TVMS (N/m), h = 1..n."""
        return np.abs(self.fourier(self.stiffness, n)[1:])

    def excitation(self, n: int | None = None) -> tuple[NDArray, NDArray, NDArray]:
        """The law the rotor model uses, as Fourier coefficients over the mesh cycle τ:
        (k_h, e_h, mean force) with ``k(τ) = Re Σ_h k_h e^{2πihτ}`` (N/m) and
        ``e(τ) = Re Σ_h e_h e^{2πihτ}`` (m, ``e = STE − F_n/k``), h = 0..n (``harmonics``)."""
        k = self.fourier(self.stiffness, n)
        e = self.fourier(self.ste - self.force / self.stiffness, n)
        return k, e, self.force

    # -- output ------------------------------------------------------------------------------
    def to_dict(self, points: int | None = None) -> dict:
        """JSON-ready numbers (units in the key names); ``points`` thins the curves."""
        g = self.geometry
        idx = np.arange(len(self.position))
        if points is not None and points < len(idx):
            idx = np.unique(np.linspace(0, len(idx) - 1, points).round().astype(int))
        ste_c = self.fourier(self.ste)
        k_c = self.fourier(self.stiffness)
        out = {
            "mean_stiffness_N_per_m": self.mean_stiffness,
            "max_stiffness_N_per_m": self.max_stiffness,
            "min_stiffness_N_per_m": self.min_stiffness,
            "contact_ratio": self.contact_ratio,
        }
        if g.pinion.helix_angle > 0:
            out["overlap_ratio"] = self.overlap_ratio
        out.update(
            {
                "total_contact_ratio": g.total_contact_ratio,
                "torque_N_m": self.torque,
                "driver": self.driver,
                "normal_force_N": self.force,
                "ste_mean_um": float(self.ste.mean() * 1e6),
                "ste_peak_to_peak_um": self.ste_peak_to_peak * 1e6,
                "direction": "normal to the flanks (the rotor model's mesh direction)",
                "geometry": {
                    "center_distance_m": g.center_distance,
                    "working_transverse_pressure_angle_deg": float(np.rad2deg(g.alpha_wt)),
                    "base_helix_angle_deg": float(np.rad2deg(g.beta_b)),
                    "base_pitch_m": g.base_pitch,
                    "path_of_contact_m": g.s_E - g.s_A,
                    "pitch_diameter_m": [2 * g.pinion.r, 2 * g.gear.r],
                    "base_diameter_m": [2 * g.pinion.r_b, 2 * g.gear.r_b],
                    "tip_diameter_m": [2 * g.pinion.r_a, 2 * g.gear.r_a],
                    "root_diameter_m": [2 * g.pinion.r_f, 2 * g.gear.r_f],
                    "form_diameter_m": [2 * g.pinion.r_form, 2 * g.gear.r_form],
                },
                "slices": self.slices,
                "curves": {
                    "mesh_cycle": [float(x) for x in self.position[idx]],
                    "stiffness_N_per_m": [float(x) for x in self.stiffness[idx]],
                    "ste_um": [float(x * 1e6) for x in self.ste[idx]],
                    "unloaded_te_um": [float(x * 1e6) for x in self.nlte[idx]],
                },
                "ste_harmonics": [
                    {
                        "order": h,
                        "amplitude_um": float(abs(ste_c[h]) * 1e6),
                        "phase_deg": float(np.rad2deg(np.angle(ste_c[h]))),
                        "stiffness_amplitude_N_per_m": float(abs(k_c[h])),
                    }
                    for h in range(1, len(ste_c))
                ],
            }
        )
        return out

    def table(self, harmonics: int = 5) -> str:
        g = self.geometry
        lines = [
            f"gear pair {g.pinion.teeth}/{g.gear.teeth} teeth, module {g.pinion.module * 1e3:g}"
            f" mm, face {g.face_width * 1e3:g} mm, helix {np.rad2deg(g.pinion.helix_angle):g}°",
            f"  contact ratio (transverse)   {self.contact_ratio:.4f}"
            + (f"   overlap ratio {self.overlap_ratio:.4f}" if g.pinion.helix_angle else ""),
            f"  torque (pinion)              {self.torque:.6g} N*m ({self.driver} drives); "
            f"normal force {self.force:.6g} N",
            f"  mesh stiffness (normal)      mean {self.mean_stiffness:.4e}  max "
            f"{self.max_stiffness:.4e}  min {self.min_stiffness:.4e} N/m",
            f"  loaded STE                   mean {self.ste.mean() * 1e6:.4f} um, peak-to-peak "
            f"{self.ste_peak_to_peak * 1e6:.4f} um",
            "  STE harmonics (um):          "
            + "  ".join(
                f"{h}x {a * 1e6:.4f}" for h, a in enumerate(self.ste_harmonics(harmonics), 1)
            ),
        ]
        return "\n".join(lines)


def resolve_materials(
    spec: GearPair, E: tuple[float, float] | None = None, nu: tuple[float, float] | None = None
):
    """(E1, E2), (ν1, ν2) of the pair: the spec's, else the given fallbacks (a model's shaft
    materials), else a ModelError."""
    Es = spec.per_gear("E") or E
    nus = spec.per_gear("poisson") or nu
    for name, v in (("E", Es), ("poisson", nus)):
        if v is None:
            raise ModelError(
                f"the gear pair needs '{name}'",
                field=name,
                expected="a value, or [pinion, gear] values (e.g. E = '206 GPa', poisson = 0.3)",
            )
    return tuple(float(x) for x in Es), tuple(float(x) for x in nus)


def _relief(r: ToothRelief | None, d: NDArray) -> NDArray:
    """Relief amount at distance ``d`` (m, ≥ 0 inside the relief) from where it starts."""
    if r is None or r.amount == 0:
        return np.zeros_like(d)
    x = np.clip(d / r.length, 0.0, None)
    return r.amount * (x if r.shape == "linear" else x**2)


def _profile_gap(mp: FlankModifications, mg: FlankModifications, s, g: PairGeometry) -> NDArray:
    """Initial separation from the profile reliefs at roll position s (transverse, m)."""
    s = np.asarray(s, float)
    gap = np.zeros_like(s)
    # pinion tip at s_E, pinion root at s_A; gear tip at s_A, gear root at s_E
    if mp.tip_relief is not None:
        gap += _relief(mp.tip_relief, s - (g.s_E - mp.tip_relief.length))
    if mp.root_relief is not None:
        gap += _relief(mp.root_relief, (g.s_A + mp.root_relief.length) - s)
    if mg.tip_relief is not None:
        gap += _relief(mg.tip_relief, (g.s_A + mg.tip_relief.length) - s)
    if mg.root_relief is not None:
        gap += _relief(mg.root_relief, s - (g.s_E - mg.root_relief.length))
    return gap


def _lead_gap(mp: FlankModifications, mg: FlankModifications, z: NDArray, b: float) -> NDArray:
    zeta = z / b + 0.5  # 0 at the start of the face, 1 at its end
    crown = (mp.crowning + mg.crowning) * (2 * z / b) ** 2
    return crown + (mp.lead_slope + mg.lead_slope) * zeta


def _check_relief(m: FlankModifications, name: str, g: PairGeometry) -> None:
    path = g.s_E - g.s_A
    for kind in ("tip_relief", "root_relief"):
        r = getattr(m, kind)
        if r is not None and r.length > path * (1 + 1e-9):
            raise ModelError(
                f"the {name}'s {kind.replace('_', ' ')} is longer than the path of contact",
                field=f"modifications.{name}.{kind}.length",
                value=r.length,
                expected=f"at most {path:.6g} m (the path of contact)",
            )


def mesh_curves(
    spec: GearPair,
    torque: float | None = None,
    *,
    E: tuple[float, float] | None = None,
    poisson: tuple[float, float] | None = None,
    positions: int | None = None,
    slices: int | None = None,
) -> MeshCurves:
    """Loaded STE and TVMS of the gear pair ``spec`` at the pinion ``torque`` (N·m; default
    the spec's). ``E``/``poisson`` are fallbacks for a spec without them."""
    missing = spec.missing()
    if missing:
        raise ModelError(
            "the gear pair misses required keys",
            field=", ".join(missing),
            expected="module, teeth, pressure_angle and face_width (see docs/gears.md)",
        )
    T = spec.torque if torque is None else torque
    if T is None:
        raise ModelError(
            "the gear pair needs the operating torque",
            field="torque",
            expected="the pinion torque, e.g. torque = '500 N*m' (or --torque)",
        )
    if not T >= 0 or not np.isfinite(T):
        raise ModelError("the torque must be ≥ 0", field="torque", value=T, expected="≥ 0 N*m")
    Es, nus = resolve_materials(spec, E, poisson)
    g = pair_geometry(
        spec.teeth,
        spec.module,
        spec.pressure_angle,
        spec.face_width,
        helix_angle=spec.helix_angle,
        profile_shift=spec.profile_shift,
        addendum=spec.addendum_coefficient,
        dedendum=spec.dedendum_coefficient,
        tip_radius_coefficient=spec.root_radius_coefficient,
    )
    mods = spec.modifications
    _check_relief(mods.pinion, "pinion", g)
    _check_relief(mods.gear, "gear", g)
    helical = g.pinion.helix_angle > 0
    lead = any(m.crowning or m.lead_slope for m in (mods.pinion, mods.gear))
    n_s = slices or spec.slices or (41 if helical or lead else 1)
    n_pos = positions or spec.positions
    bores = spec.bore_diameter or (None, None)

    # compliance of one pair per unit length of contact line along the path of contact; a
    # helical pair's teeth bend in the normal section: the virtual spur pair of ISO 6336
    # (z_n = z / (cos² β_b cos β), normal module and pressure angle), at the same fraction of
    # its path of contact
    s_grid = np.linspace(g.s_A, g.s_E, _PATH_POINTS)
    cos_bb = np.cos(g.beta_b)
    if helical:
        cb = np.cos(g.pinion.helix_angle)
        vg = pair_geometry(
            tuple(z / (cos_bb**2 * cb) for z in spec.teeth),
            spec.module,
            spec.pressure_angle,
            spec.face_width,
            profile_shift=spec.profile_shift,
            addendum=spec.addendum_coefficient,
            dedendum=spec.dedendum_coefficient,
            tip_radius_coefficient=spec.root_radius_coefficient,
        )
        s_v = vg.s_A + (s_grid - g.s_A) * (vg.s_E - vg.s_A) / (g.s_E - g.s_A)
    else:
        vg, s_v = g, s_grid
    parts = {}
    total = np.zeros_like(s_grid)
    for k, (t, rad) in enumerate(
        ((vg.pinion, vg.radius_on_pinion(s_v)), (vg.gear, vg.radius_on_gear(s_v)))
    ):
        try:
            c = tooth_compliance(t, rad, Es[k], nus[k], bores[k], tooth_profile(t))
        except ModelError as exc:
            f = exc.field
            if f == "bore_diameter":
                f = f"bore_diameter[{k}]"
            raise ModelError(exc.message, field=f, value=exc.value, expected=exc.expected) from None
        name = ("pinion", "gear")[k]
        for part in ("bending", "shear", "axial", "foundation"):
            parts[f"{name}_{part}"] = getattr(c, part)
        total += c.total
    c_hertz = hertz_compliance(Es[0], nus[0], Es[1], nus[1])
    parts["hertz"] = np.full_like(s_grid, c_hertz)
    total += c_hertz

    # contacts: positions × (pairs, slices)
    b = g.face_width
    db = b / n_s
    z = (np.arange(n_s) + 0.5) * db - b / 2
    shift = z * g.lead_shift
    pb = g.base_pitch
    tau = np.arange(n_pos) / n_pos
    ext = abs(shift).max() / pb if n_s > 1 else 0.0
    k_lo = int(np.floor(-ext)) - 1
    k_hi = int(np.ceil(g.contact_ratio + ext)) + 1
    ks = np.arange(k_lo, k_hi + 1)
    roll = (tau[:, None] + ks[None, :]) * pb  # (n_pos, K) roll from the entry at mid-face
    if spec.driver == "pinion":
        s_mid = g.s_A + roll
    else:
        s_mid = g.s_E - roll
    s = s_mid[:, :, None] + shift[None, None, :]  # (n_pos, K, n_s)
    # the share of each slice's piece of contact line inside the path of contact (a helical
    # slice spans Δb tan β_b of roll: contact lines enter and leave the face gradually)
    half = 0.5 * db * g.lead_shift
    if half > 0:
        lo, hi = np.maximum(s - half, g.s_A), np.minimum(s + half, g.s_E)
        share = np.clip((hi - lo) / (2 * half), 0.0, 1.0)
    else:
        share = ((s >= g.s_A - 1e-12 * pb) & (s <= g.s_E + 1e-12 * pb)).astype(float)
    inside = share > 0
    s_c = np.clip(s, g.s_A, g.s_E)
    # normal stiffness of each contact: its contact line Δb / cos β_b over the compliance
    stiff = np.where(inside, share * db / cos_bb / np.interp(s_c, s_grid, total), 0.0)
    gap = _profile_gap(mods.pinion, mods.gear, s_c, g) + _lead_gap(mods.pinion, mods.gear, z, b)
    gap = np.where(inside, gap * cos_bb, np.inf)  # modifications: transverse → normal
    if not inside.reshape(n_pos, -1).any(axis=1).all():
        raise ModelError("no tooth pair in contact at some mesh position", field="teeth")

    F_n = T / g.pinion.r_b / cos_bb
    kk = stiff.reshape(n_pos, -1)
    gg = gap.reshape(n_pos, -1)
    order = np.argsort(gg, axis=1)
    gs = np.take_along_axis(gg, order, axis=1)
    ksrt = np.take_along_axis(kk, order, axis=1)
    Kc = np.cumsum(ksrt, axis=1)
    KG = np.cumsum(ksrt * np.where(np.isfinite(gs), gs, 0.0), axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        delta_m = (F_n + KG) / Kc
    nxt = np.concatenate([gs[:, 1:], np.full((n_pos, 1), np.inf)], axis=1)
    ok = (delta_m <= nxt) & (Kc > 0) & np.isfinite(gs)
    first = np.argmax(ok, axis=1)
    delta = delta_m[np.arange(n_pos), first]
    nlte = gs[:, 0]
    tol = 1e-9 * max(float(np.nanmax(np.where(np.isfinite(gg), gg, 0.0))), 1e-9) + 1e-15
    engaged = gg <= delta[:, None] + tol
    k_t = np.where(engaged, kk, 0.0).sum(axis=1)
    load = np.where(engaged, kk * np.clip(delta[:, None] - gg, 0.0, None), 0.0)
    pair_load = load.reshape(n_pos, len(ks), n_s).sum(axis=2)
    pair_roll = np.where(inside.any(axis=2), s_mid, np.nan)
    keep = np.flatnonzero(np.nansum(pair_load, axis=0) > 0) if T > 0 else np.arange(len(ks))
    return MeshCurves(
        geometry=g,
        torque=float(T),
        driver=spec.driver,
        slices=n_s,
        position=tau,
        stiffness=k_t,
        ste=delta,
        nlte=nlte,
        pair_load=pair_load[:, keep],
        pair_roll=pair_roll[:, keep],
        force=F_n,
        harmonics=spec.harmonics,
        compliance_path=s_grid,
        compliance_pair=total,
        compliance_parts=parts,
    )
