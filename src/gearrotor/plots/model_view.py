"""Drawings of a model before any analysis (``gearrotor show``, the report's first section).

* :func:`plot_model` — a side view of every shaft to scale (sections with outer and inner
  diameters, mass-only diameters dashed, node numbers, disks, gears with pitch diameter and
  teeth, bearings and seals with their type and name, thrust bearings, couplings, cross-coupling
  destabilisers, probes, unbalances, drives and loads, shaft names and speeds) and an end view
  of the train along z (shaft centres, pitch circles, the line of centres with the mesh
  orientation angle, the senses of rotation and the direction of the line of action).
* :func:`model_figure_3d` — the same model in 3-D (plotly) with node and element tooltips.

Frames (docs/conventions.md): z along the shafts; the end view looks from +z towards −z, so x
points right, y up and a positive speed turns counter-clockwise.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..files import save_figure

__all__ = ["model_parts", "plot_model", "model_figure_3d"]

RPM = 30 / np.pi
MM = 1e3
_SHAFT = "#b9c3cc"
_BORE = "white"
_GEAR = "#d8a24a"
_DISK = "#8c5b3c"
_BEARING = "#355d7a"
_SEAL = "#4f9a8c"
_UNB = "#c0392b"
_PROBE = "#6c3483"
_DRIVE = "#1e8449"


def _plt():
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    return plt


# --------------------------------------------------------------------------------------------
# what is drawn, per shaft: one flat list of parts resolved from the model
@dataclass(frozen=True)
class Part:
    kind: str  # section, disk, gear, bearing, seal, thrust, coupling, cross, probe, unbalance,
    #            drive, load
    shaft: int
    node: int
    z: float  # m, node position (sections: start)
    label: str
    length: float = 0.0  # m (sections, disks, gears: axial extent)
    outer: float = 0.0  # m, diameter
    inner: float = 0.0  # m, diameter
    mass_outer: float | None = None  # m, mass-only diameters (sections)
    mass_inner: float | None = None
    angle: float = 0.0  # rad (probes, unbalance phase)
    detail: str = ""  # tooltip text


def _num(x: float) -> str:
    """4 significant digits, thousands separated, no exponent between 1e-3 and 1e9."""
    if x == 0 or not 1e-3 <= abs(x) < 1e9:
        return f"{x:.4g}"
    digits = max(0, 3 - int(np.floor(np.log10(abs(x)))))
    return f"{x:,.{digits}f}"


def _bearing_type(b) -> str:
    if b.fluid_film is not None:
        return f"fluid film ({Path(b.fluid_film.file).name})"
    if b.table is not None:
        if b.table.whirl is not None:
            return f"table ({len(b.table.speed)} speeds × {len(b.table.whirl)} whirl)"
        return f"table ({len(b.table.speed)} speeds)"
    if b.table_file is not None:
        return f"table ({Path(b.table_file).name})"
    return "constant"


def model_parts(train) -> list[Part]:
    """Every drawn item of ``train`` with its shaft, node and axial position."""
    from ..assembly import _disk_element, _shaft_elements

    layout = train.layout()
    parts: list[Part] = []

    def where(ref, field, shaft=None):
        si, n = train.node_index(ref, field, shaft=shaft)
        return si, n, float(layout.shafts[si].z[n])

    for i, s in enumerate(train.shafts):
        z = layout.shafts[i].z
        e = 0
        for j, sec in enumerate(s.sections):
            mat = sec.material or s.material
            parts.append(
                Part(
                    "section",
                    i,
                    e,
                    float(z[e]),
                    f"sections[{j}]",
                    length=sec.length,
                    outer=sec.outer_diameter,
                    inner=sec.inner_diameter,
                    mass_outer=sec.mass_outer_diameter,
                    mass_inner=sec.mass_inner_diameter,
                    detail=(
                        f"{s.name} sections[{j}]: L {sec.length * MM:.4g} mm, "
                        f"OD {sec.outer_diameter * MM:.4g} mm, ID {sec.inner_diameter * MM:.4g} "
                        f"mm, {sec.elements} element(s), nodes {e}–{e + sec.elements}, {mat}"
                    ),
                )
            )
            e += sec.elements
        els = _shaft_elements(train, i)
        for k, d in enumerate(s.disks):
            _, n, zn = where(d, f"shafts[{i}].disks[{k}]", shaft=s.name)
            el = _disk_element(train, i, k)
            if d.outer_diameter is not None:
                D, w = d.outer_diameter, d.width
            else:  # a lumped disk: the solid steel-like disk of the same mass and polar inertia
                D = float(np.sqrt(8 * el.polar / el.mass)) if el.mass > 0 and el.polar > 0 else 0.0
                w = None
            if w is None:
                w = 0.6 * min(els[min(n, len(els) - 1)].length, D or 1.0)
            name = d.name or f"disks[{k}]"
            parts.append(
                Part(
                    "disk",
                    i,
                    n,
                    zn,
                    name,
                    length=w,
                    outer=max(D, 0.0),
                    inner=d.inner_diameter,
                    detail=f"{name}: m {el.mass:.4g} kg, Ip {el.polar:.4g} kg·m², "
                    f"It {el.transverse:.4g} kg·m² at node {n}",
                )
            )
    for k, m in enumerate(train.meshes):
        ri, rj = train.pitch_radii(k)
        name = m.name or f"meshes[{k}]"
        for side, r in ((m.gear, ri), (m.mate, rj)):
            si, n, zn = where(side, f"meshes[{k}].{'gear' if side is m.gear else 'mate'}")
            parts.append(
                Part(
                    "gear",
                    si,
                    n,
                    zn,
                    f"{name}: {side.teeth} t, d {2 * r * MM:.4g} mm",
                    length=m.face_width or 0.0,
                    outer=2 * r,
                    detail=f"{name}: {side.teeth} teeth, pitch diameter {2 * r * MM:.4g} mm, "
                    f"αn {np.degrees(m.pressure_angle):.3g}°, β {np.degrees(m.helix_angle):.3g}°",
                )
            )
    for k, b in enumerate(train.bearings):
        si, n, zn = where(b, f"bearings[{k}]")
        name = b.name or f"bearings[{k}]"
        kind = _bearing_type(b) + (" on pedestal" if b.support is not None else "")
        parts.append(
            Part("bearing", si, n, zn, f"{name}\n{kind}", detail=f"bearing {name}: {kind}")
        )
    for k, sl in enumerate(train.seals):
        si, n, zn = where(sl, f"seals[{k}]")
        name = sl.name or f"seals[{k}]"
        kind = (
            _bearing_type(sl)
            if hasattr(sl, "fluid_film")
            else ("table" if sl.table is not None or sl.table_file is not None else "constant")
        )
        if getattr(sl, "file", None) is not None:  # a seal file: computed from its geometry
            kind = f"geometry, {Path(sl.file).name}"
        parts.append(Part("seal", si, n, zn, f"{name}\n(seal, {kind})", detail=f"seal {name}"))
    for k, t in enumerate(train.thrust_bearings):
        si, n, zn = where(t, f"thrust_bearings[{k}]")
        name = t.name or f"thrust_bearings[{k}]"
        parts.append(
            Part("thrust", si, n, zn, f"{name}\n(thrust)", detail=f"thrust {name}: Kzz {t.kzz:.3g}")
        )
    for k, c in enumerate(train.couplings):
        name = c.name or f"couplings[{k}]"
        si, ni, zi = where(c.node_i, f"couplings[{k}].node_i")
        sj, nj, zj = where(c.node_j, f"couplings[{k}].node_j")
        parts.append(
            Part(
                "coupling",
                si,
                ni,
                zi,
                f"{name}\n→ {c.node_j.shaft}:{nj}",
                detail=f"coupling {name}",
            )
        )
        parts.append(
            Part(
                "coupling",
                sj,
                nj,
                zj,
                f"{name}\n→ {c.node_i.shaft}:{ni}",
                detail=f"coupling {name}",
            )
        )
    for k, q in enumerate(train.cross_couplings):
        si, n, zn = where(q, f"cross_couplings[{k}]")
        name = q.name or f"cross_couplings[{k}]"
        parts.append(
            Part("cross", si, n, zn, f"{name}\nq {q.q:.3g} N/m", detail=f"cross-coupling {name}")
        )
    for k, p in enumerate(train.probes):
        si, n, zn = where(p, f"probes[{k}]")
        parts.append(
            Part(
                "probe",
                si,
                n,
                zn,
                f"{p.name} {np.degrees(p.angle):.0f}°",
                angle=p.angle,
                detail=f"probe {p.name} at {np.degrees(p.angle):.1f}°",
            )
        )
    for k, u in enumerate(train.unbalances):
        si, n, zn = where(u, f"unbalances[{k}]")
        parts.append(
            Part(
                "unbalance",
                si,
                n,
                zn,
                f"U {_num(u.amount * 1e6)} g·mm ∠{np.degrees(u.phase):.0f}°",
                angle=u.phase,
                detail=f"unbalance {_num(u.amount * 1e6)} g·mm at {np.degrees(u.phase):.1f}°",
            )
        )
    if train.torsional is not None:
        for group, kind in (("drives", "drive"), ("loads", "load")):
            for k, d in enumerate(getattr(train.torsional, group)):
                si, n, zn = where(d, f"torsional.{group}[{k}]")
                name = d.name or f"{group}[{k}]"
                parts.append(
                    Part(kind, si, n, zn, f"{name}\n({kind}: {d.type})", detail=f"{kind} {name}")
                )
    for k, t in enumerate(train.torques):
        si, n, zn = where(t, f"torques[{k}]")
        name = t.name or f"torques[{k}]"
        parts.append(Part("drive", si, n, zn, f"{name}\n(torque)", detail=f"torque {name}"))
    roles: dict[tuple[int, int, str], list[str]] = {}
    for p in train.operating_points:
        for role, ref in (("drive", p.drive), ("load", p.load)):
            if ref is not None:
                si, n, _ = where(ref, f"operating_points[{p.name}].{role}")
                roles.setdefault((si, n, role), []).append(p.name)
    for (si, n, role), names in roles.items():
        few = ", ".join(names) if len(names) <= 3 else f"{names[0]} … {names[-1]}"
        parts.append(
            Part(
                role,
                si,
                n,
                float(layout.shafts[si].z[n]),
                f"{role} of {len(names)} operating point(s)\n({few})",
                detail=f"{role} of operating points {', '.join(names)}",
            )
        )
    return parts


# --------------------------------------------------------------------------------------------
def _side_view(ax, train, i: int, parts: list[Part], speed: float) -> None:
    from matplotlib.patches import Polygon, Rectangle

    sl = train.layout().shafts[i]
    mine = [p for p in parts if p.shaft == i]
    secs = [p for p in mine if p.kind == "section"]
    r_shaft = max(p.outer for p in secs) / 2
    r_big = max([r_shaft] + [p.outer / 2 for p in mine if p.kind in ("disk", "gear")])
    length = float(sl.z[-1] - sl.z[0])
    # sections: outer, bore, mass-only outline
    for p in secs:
        z0, L = p.z * MM, p.length * MM
        ro, rb = p.outer / 2 * MM, p.inner / 2 * MM
        ax.add_patch(Rectangle((z0, -ro), L, 2 * ro, fc=_SHAFT, ec="#4d5656", lw=0.8, zorder=2))
        if rb > 0:
            ax.add_patch(
                Rectangle(
                    (z0, -rb), L, 2 * rb, fc=_BORE, ec="#4d5656", lw=0.5, hatch="////", zorder=2.1
                )
            )
        if p.mass_outer is not None:
            rm = p.mass_outer / 2 * MM
            ax.add_patch(
                Rectangle(
                    (z0, -rm), L, 2 * rm, fill=False, ec="#4d5656", lw=0.7, ls="--", zorder=2.2
                )
            )
    # element boundaries and node numbers
    step = 1 if sl.n_nodes <= 31 else (5 if sl.n_nodes <= 151 else 10)
    marked = {p.node for p in mine if p.kind != "section"}
    for n, zn in enumerate(sl.z):
        ax.plot([zn * MM] * 2, [-r_shaft * MM, r_shaft * MM], color="#4d5656", lw=0.3, zorder=2.3)
        if n % step == 0 or n == sl.n_nodes - 1 or n in marked:
            ax.text(
                zn * MM,
                0,
                str(n),
                ha="center",
                va="center",
                fontsize=6,
                color="#17202a",
                zorder=6,
                bbox=dict(boxstyle="round,pad=0.1", fc="white", ec="none", alpha=0.7),
            )
    ax.plot(
        [sl.z[0] * MM - 0.02 * length * MM, sl.z[-1] * MM + 0.02 * length * MM],
        [0, 0],
        color="#17202a",
        lw=0.5,
        ls="-.",
        zorder=1,
    )
    # components
    span = r_big * MM
    below, above = [], []  # labels placed under / over the shaft, staggered
    for p in mine:
        zm = p.z * MM
        if p.kind in ("disk", "gear"):
            w = max(p.length * MM, 0.012 * length * MM)
            ro = p.outer / 2 * MM
            color = _GEAR if p.kind == "gear" else _DISK
            ax.add_patch(
                Rectangle(
                    (zm - w / 2, -ro),
                    w,
                    2 * ro,
                    fc=color,
                    ec="black",
                    lw=0.7,
                    alpha=0.85,
                    hatch="||" if p.kind == "gear" else None,
                    zorder=3,
                )
            )
            above.append((zm, ro, p.label, color))
        elif p.kind in ("bearing", "seal", "thrust"):
            r = _radius_at(secs, p.z) * MM
            h = min(0.5 * r, 0.05 * length * MM) + 0.015 * length * MM
            color = {"bearing": _BEARING, "seal": _SEAL, "thrust": "#7d3c98"}[p.kind]
            if p.kind == "bearing":
                for sgn in (-1, 1):
                    ax.add_patch(
                        Polygon(
                            [
                                (zm, sgn * r),
                                (zm - h * 0.6, sgn * (r + h)),
                                (zm + h * 0.6, sgn * (r + h)),
                            ],
                            closed=True,
                            fc=color,
                            ec="black",
                            lw=0.6,
                            zorder=4,
                        )
                    )
            elif p.kind == "seal":
                for sgn in (-1, 1):
                    ax.add_patch(
                        Rectangle(
                            (zm - h * 0.4, sgn * r if sgn > 0 else -r - h * 0.6),
                            h * 0.8,
                            h * 0.6,
                            fc=color,
                            ec="black",
                            lw=0.6,
                            hatch="xx",
                            zorder=4,
                        )
                    )
            else:
                ax.add_patch(
                    Rectangle(
                        (zm - h * 0.15, -r - h),
                        h * 0.3,
                        2 * (r + h),
                        fill=False,
                        ec=color,
                        lw=1.5,
                        zorder=4,
                    )
                )
            below.append((zm, r + h, p.label, color))
        elif p.kind == "unbalance":
            r = _radius_at(secs, p.z) * MM
            ax.plot(zm, r, "o", ms=6, color=_UNB, zorder=5, mec="black", mew=0.5)
            above.append((zm, r, p.label, _UNB))
        elif p.kind == "probe":
            r = _radius_at(secs, p.z) * MM
            tip = r + 0.06 * length * MM
            ax.annotate(
                "",
                xy=(zm, r),
                xytext=(zm, tip),
                arrowprops=dict(arrowstyle="-|>", color=_PROBE, lw=1.0),
                zorder=5,
            )
            above.append((zm, tip, p.label, _PROBE))
        elif p.kind in ("drive", "load"):
            r = _radius_at(secs, p.z) * MM
            ax.plot(
                zm,
                0,
                marker="$\u21bb$" if p.kind == "drive" else "$\u21ba$",
                ms=14,
                color=_DRIVE if p.kind == "drive" else "#a04000",
                zorder=6,
            )
            below.append((zm, r, p.label, _DRIVE if p.kind == "drive" else "#a04000"))
        elif p.kind in ("coupling", "cross"):
            r = _radius_at(secs, p.z) * MM
            color = "#2e4053" if p.kind == "coupling" else "#c0392b"
            zz = np.linspace(-r * 1.3, r * 1.3, 9)
            ax.plot(
                zm + 0.01 * length * MM * np.tile([1, -1], 5)[:9], zz, color=color, lw=1.2, zorder=5
            )
            below.append((zm, r * 1.3, p.label, color))
    ymax = _place_labels(ax, above, +1, span, length * MM)
    ymin = _place_labels(ax, below, -1, span, length * MM)
    name = train.shafts[i].name
    ax.set_title(
        f"{name}: {speed * sl.speed_ratio * RPM:,.0f} rpm, {length * MM:.4g} mm, "
        f"{sl.n_nodes - 1} elements",
        fontsize=9,
        loc="left",
    )
    ax.set_xlim(sl.z[0] * MM - 0.04 * length * MM, sl.z[-1] * MM + 0.04 * length * MM)
    ax.set_ylim(ymin, ymax)
    ax.set_aspect("equal", adjustable="box")
    ax.set_xlabel("axial position z (mm)", fontsize=8)
    ax.set_ylabel("radius (mm)", fontsize=8)
    ax.tick_params(labelsize=7)


def _radius_at(secs: list[Part], z: float) -> float:
    r = 0.0
    for p in secs:
        if p.z - 1e-12 <= z <= p.z + p.length + 1e-12:
            r = max(r, p.outer / 2)
    return r


def _place_labels(ax, items, sign: int, span: float, length: float) -> float:
    """Labels above (sign +1) or below (−1) their items, beyond the largest radius ``span``:
    labels at one node form one block; blocks closer than a label's width go to the next row
    out. Returns the extent reached (mm)."""
    merged: dict[float, list] = {}
    for z, r, text, color in items:
        key = round(z, 6)
        if key in merged:
            m = merged[key]
            m[1] = max(m[1], r)
            if text not in m[2]:
                m[2].append(text)
        else:
            merged[key] = [z, r, [text], color]
    blocks = sorted(((z, r, "\n".join(t), c) for z, r, t, c in merged.values()), key=lambda b: b[0])
    line = 0.02 * length  # text line height at 6.5 pt on a 12.7-inch-wide panel, mm
    width = 0.11 * length
    rows: list[tuple[float, float]] = []  # per row: last z used, height (mm)
    placed = []
    for z, r, text, color in blocks:
        nlines = text.count("\n") + 1
        row = next((k for k, (last, _) in enumerate(rows) if z - last > width), len(rows))
        if row == len(rows):
            rows.append((z, 0.0))
        rows[row] = (z, max(rows[row][1], nlines * line))
        placed.append((row, z, r, text, color))
    base = [max(span, 0.0) + 0.6 * line]
    for _, h in rows:
        base.append(base[-1] + h + 0.5 * line)
    extent = sign * (span + 2 * line)
    for row, z, r, text, color in placed:
        y = sign * max(base[row], r + 0.6 * line)
        ax.annotate(
            text,
            xy=(z, sign * r),
            xytext=(z, y),
            ha="center",
            va="bottom" if sign > 0 else "top",
            fontsize=6.5,
            color=color,
            arrowprops=dict(arrowstyle="-", color=color, lw=0.4, alpha=0.6),
            zorder=7,
        )
    if rows:
        extent = sign * (base[-1] + line)
    return extent


def _end_view(ax, train, speed: float) -> None:
    from matplotlib.patches import Arc, Circle, FancyArrowPatch

    layout = train.layout()
    centres = [np.asarray(s.position) * MM for s in layout.shafts]
    scale = 1.0
    radii: dict[int, float] = {}
    for k, m in enumerate(train.meshes):
        ri, rj = train.pitch_radii(k)
        si = train.shaft_index(m.gear.shaft, "")
        sj = train.shaft_index(m.mate.shaft, "")
        radii[si] = max(radii.get(si, 0.0), ri * MM)
        radii[sj] = max(radii.get(sj, 0.0), rj * MM)
    for i, s in enumerate(train.shafts):
        radii.setdefault(i, max(sec.outer_diameter for sec in s.sections) / 2 * MM)
    scale = max(radii.values())
    seen: dict[tuple, int] = {}
    for i, (c, sl) in enumerate(zip(centres, layout.shafts, strict=True)):
        r = max(sec.outer_diameter for sec in train.shafts[i].sections) / 2 * MM
        ax.add_patch(Circle(c, r, fc=_SHAFT, ec="#4d5656", lw=0.8, zorder=2))
        key = (round(c[0], 6), round(c[1], 6))
        stack = seen.get(key, 0)
        seen[key] = stack + 1
        w = speed * sl.speed_ratio
        sense = "" if w == 0 else (" ↺ (+z)" if w > 0 else " ↻ (−z)")
        ax.annotate(
            f"{sl.name}\n{w * RPM:,.0f} rpm{sense}",
            xy=c,
            xytext=(c[0], c[1] - radii[i] - 0.12 * scale - stack * 0.28 * scale),
            ha="center",
            va="top",
            fontsize=7.5,
            zorder=6,
        )
        if w != 0:  # sense of rotation: an arc arrow just outside the largest circle
            rr = 1.12 * max(radii[i], r)
            a0, a1 = (60, 120) if w > 0 else (120, 60)
            ax.add_patch(
                FancyArrowPatch(
                    c + rr * np.array([np.cos(np.radians(a0)), np.sin(np.radians(a0))]),
                    c + rr * np.array([np.cos(np.radians(a1)), np.sin(np.radians(a1))]),
                    connectionstyle=f"arc3,rad={0.5 if w > 0 else -0.5}",
                    arrowstyle="-|>",
                    mutation_scale=10,
                    color=_DRIVE,
                    lw=1.0,
                    zorder=5,
                )
            )
        ax.plot(*c, "+", color="black", ms=8, zorder=6)
    drawn: dict[tuple, list[str]] = {}
    for k, m in enumerate(train.meshes):  # meshes between the same shafts look alike end-on
        key = (m.gear.shaft, m.mate.shaft, round(m.orientation, 9))
        drawn.setdefault(key, []).append(m.name or f"meshes[{k}]")
    for k, m in enumerate(train.meshes):
        key = (m.gear.shaft, m.mate.shaft, round(m.orientation, 9))
        names = drawn[key]
        if (m.name or f"meshes[{k}]") != names[0]:
            continue
        ri, rj = (r * MM for r in train.pitch_radii(k))
        si = train.shaft_index(m.gear.shaft, "")
        sj = train.shaft_index(m.mate.shaft, "")
        ci, cj = centres[si], centres[sj]
        ax.add_patch(Circle(ci, ri, fill=False, ec=_GEAR, lw=1.2, ls="--", zorder=3))
        ax.add_patch(Circle(cj, rj, fill=False, ec=_GEAR, lw=1.2, ls="--", zorder=3))
        ax.plot([ci[0], cj[0]], [ci[1], cj[1]], color="#7f8c8d", lw=0.8, ls=":", zorder=2)
        phi = m.orientation
        e = np.array([np.cos(phi), np.sin(phi)])
        pitch = ci + ri * e
        ax.add_patch(
            Arc(
                ci,
                0.5 * ri,
                0.5 * ri,
                theta1=min(0, np.degrees(phi)),
                theta2=max(0, np.degrees(phi)),
                color="#7f8c8d",
                lw=0.8,
            )
        )
        ax.annotate(
            f"ϕ = {np.degrees(phi):.1f}°",
            xy=ci + 0.3 * ri * np.array([np.cos(phi / 2), np.sin(phi / 2)]),
            fontsize=6.5,
            color="#7f8c8d",
        )
        # the line of action: the tooth-normal direction n projected on the end plane (SPEC 2.3)
        cx = np.cos(m.helix_angle) * np.cos(m.pressure_angle)
        cy = np.sin(m.pressure_angle)
        n = np.array([np.sin(phi) * cx + np.cos(phi) * cy, np.sin(phi) * cy - np.cos(phi) * cx])
        n /= np.linalg.norm(n)
        L = 0.6 * min(ri, rj)
        ax.plot(*np.column_stack([pitch - L * n, pitch + L * n]), color=_UNB, lw=0.9, zorder=4)
        ax.add_patch(
            FancyArrowPatch(
                pitch,
                pitch + L * n,
                arrowstyle="-|>",
                mutation_scale=10,
                color=_UNB,
                lw=1.0,
                zorder=5,
            )
        )
        ax.annotate(
            f"{', '.join(names)}: line of action\n"
            f"N {m.gear.teeth}/{m.mate.teeth}, αn {np.degrees(m.pressure_angle):.1f}°",
            xy=pitch - L * n,
            xytext=(-4, 4),
            textcoords="offset points",
            fontsize=6.5,
            color=_UNB,
            ha="right",
            va="bottom",
            zorder=6,
        )
        ax.plot(*pitch, "o", ms=3, color=_UNB, zorder=6)
    allc = np.array(centres)
    lo = allc.min(axis=0) - 1.35 * scale - 0.15 * scale * len(layout.shafts)
    hi = allc.max(axis=0) + 1.25 * scale
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[1], hi[1])
    ax.set_aspect("equal")
    ax.set_title("end view (from +z): x right, y up", fontsize=9, loc="left")
    ax.set_xlabel("x (mm)", fontsize=8)
    ax.set_ylabel("y (mm)", fontsize=8)
    ax.tick_params(labelsize=7)
    ax.grid(True, lw=0.3, alpha=0.5)


def plot_model(train, path: str | Path | None = None, *, speed: float | None = None):
    """Side view of every shaft to scale and the end view of the train; returns the Figure.

    ``speed`` (rad/s): the reference-shaft speed printed with the shafts (default the model's).
    """
    plt = _plt()
    speed = train.speed if speed is None else speed
    parts = model_parts(train)
    layout = train.layout()
    n = len(layout.shafts)
    fig = plt.figure(figsize=(14, 4 * (n + 1)))
    axes = [fig.add_subplot(n + 1, 1, i + 1) for i in range(n + 1)]
    for i in range(n):
        _side_view(axes[i], train, i, parts, speed)
    _end_view(axes[n], train, speed)
    # to scale: every panel exactly as tall as its data for its width (equal aspect, nothing
    # left empty), stacked top to bottom with room for titles and axis labels
    fig_w, left, gap, top = 14.0, 1.0, 1.0, 0.7
    boxes = []
    for k, ax in enumerate(axes):
        (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
        w = fig_w - left - 0.3 if k < n else 0.55 * fig_w
        h = w * (y1 - y0) / (x1 - x0)
        if k == n and h > 7.0:
            w, h = 7.0 * (x1 - x0) / (y1 - y0), 7.0
        boxes.append((w, h))
    fig_h = top + sum(h for _, h in boxes) + gap * (n + 1)
    fig.set_size_inches(fig_w, fig_h)
    y = fig_h - top
    for ax, (w, h) in zip(axes, boxes, strict=True):
        y -= h
        ax.set_position([left / fig_w, y / fig_h, w / fig_w, h / fig_h])
        y -= gap
    fig.suptitle(train.name, fontsize=11, x=0.01, y=1 - 0.25 / fig_h, ha="left", va="top")
    if path is not None:
        path = Path(path)
        save_figure(fig, path, dpi=130, bbox_inches="tight")
    return fig


# --------------------------------------------------------------------------------------------
def _tube(z0: float, z1: float, r: float, cx: float, cy: float, n: int = 24):
    """Vertices and triangles of a closed cylinder (plotly Mesh3d)."""
    t = np.linspace(0, 2 * np.pi, n, endpoint=False)
    x = np.concatenate([cx + r * np.cos(t)] * 2 + [[cx, cx]])
    y = np.concatenate([cy + r * np.sin(t)] * 2 + [[cy, cy]])
    z = np.concatenate([np.full(n, z0), np.full(n, z1), [z0, z1]])
    i, j, k = [], [], []
    for a in range(n):
        b = (a + 1) % n
        i += [a, b, 2 * n, 2 * n + 1]  # two side triangles, then the two end caps
        j += [b, n + b, b, n + a]
        k += [n + a, n + a, a, n + b]
    return x, y, z, i, j, k


def model_figure_3d(train, *, speed: float | None = None):
    """The model in 3-D (plotly): shaft elements as cylinders, disks and gears, bearings and
    the other components as markers; hovering shows each node, element and component."""
    import plotly.graph_objects as go

    from ..assembly import _shaft_elements

    speed = train.speed if speed is None else speed
    layout = train.layout()
    parts = model_parts(train)
    fig = go.Figure()
    for i, sl in enumerate(layout.shafts):
        cx, cy = (v * MM for v in sl.position)
        els = _shaft_elements(train, i)
        xs, ys, zs, ii, jj, kk, text = [], [], [], [], [], [], []
        for e, el in enumerate(els):
            x, y, z, a, b, c = _tube(
                sl.z[e] * MM, sl.z[e + 1] * MM, el.outer_diameter / 2 * MM, cx, cy
            )
            off = len(xs)
            xs += list(x)
            ys += list(y)
            zs += list(z)
            ii += [v + off for v in a]
            jj += [v + off for v in b]
            kk += [v + off for v in c]
            tip = (
                f"{sl.name} element {e} (nodes {e}–{e + 1})<br>L {el.length * MM:.4g} mm, "
                f"OD {el.outer_diameter * MM:.4g} mm, ID {el.inner_diameter * MM:.4g} mm"
            )
            text += [tip] * len(x)
        fig.add_trace(
            go.Mesh3d(
                x=xs,
                y=ys,
                z=zs,
                i=ii,
                j=jj,
                k=kk,
                color=_SHAFT,
                opacity=1.0,
                hovertext=text,
                hoverinfo="text",
                name=sl.name,
                flatshading=True,
            )
        )
        r = np.array([el.outer_diameter / 2 for el in els] + [els[-1].outer_diameter / 2]) * MM
        fig.add_trace(
            go.Scatter3d(
                x=np.full(sl.n_nodes, cx),
                y=np.full(sl.n_nodes, cy) + r,
                z=sl.z * MM,
                mode="markers+text",
                marker=dict(size=2, color="#17202a"),
                text=[str(n) for n in range(sl.n_nodes)],
                textfont=dict(size=9),
                hovertext=[f"{sl.name} node {n}<br>z {z * MM:.5g} mm" for n, z in enumerate(sl.z)],
                hoverinfo="text",
                name=f"{sl.name} nodes",
            )
        )
    colors = {"disk": _DISK, "gear": _GEAR}
    for p in parts:
        sl = layout.shafts[p.shaft]
        cx, cy = (v * MM for v in sl.position)
        if p.kind in ("disk", "gear") and p.outer > 0:
            w = max(p.length, 0.01 * float(sl.z[-1] - sl.z[0])) * MM
            x, y, z, a, b, c = _tube(p.z * MM - w / 2, p.z * MM + w / 2, p.outer / 2 * MM, cx, cy)
            fig.add_trace(
                go.Mesh3d(
                    x=x,
                    y=y,
                    z=z,
                    i=a,
                    j=b,
                    k=c,
                    color=colors[p.kind],
                    opacity=0.55,
                    hovertext=p.detail,
                    hoverinfo="text",
                    name=p.label.split("\n")[0],
                    flatshading=True,
                )
            )
        elif p.kind != "section":
            color = {
                "bearing": _BEARING,
                "seal": _SEAL,
                "unbalance": _UNB,
                "probe": _PROBE,
                "drive": _DRIVE,
            }.get(p.kind, "#2e4053")
            r = _radius_at([q for q in parts if q.kind == "section" and q.shaft == p.shaft], p.z)
            fig.add_trace(
                go.Scatter3d(
                    x=[cx],
                    y=[cy - r * MM * 1.4],
                    z=[p.z * MM],
                    mode="markers",
                    marker=dict(size=6, color=color, symbol="diamond"),
                    hovertext=p.detail or p.label,
                    hoverinfo="text",
                    name=p.label.replace("\n", " "),
                )
            )
    fig.update_layout(
        title=f"{train.name} ({speed * RPM:,.0f} rpm)",
        scene=dict(
            aspectmode="data",
            xaxis_title="x (mm)",
            yaxis_title="y (mm)",
            zaxis_title="z (mm)",
            # y up, the shafts' axis z running across the screen
            camera=dict(up=dict(x=0, y=1, z=0), eye=dict(x=1.7, y=0.7, z=0.5)),
        ),
        margin=dict(l=0, r=0, t=40, b=0),
        showlegend=False,
    )
    return fig
