"""Rotors saved by ROSS (``Rotor.save``, ROSS 3.x TOML) as gearrotor models.

What a ROSS file holds and what it becomes (all values SI in both):

* ``ShaftElement_*``: ``L``, ``idl``/``odl``/``idr``/``odr``, the element number ``n`` (its left
  node) and a ``material`` (``rho``, ``E``, ``G_s``) → a section of one element per ROSS element
  (runs of identical elements merged into one section of several elements). Elements sharing an
  ``n`` are layers of one element: a layer whose modulus is below 1e-3 of the element's stiffest
  layer is mass only (ROSS's usual way to add a sleeve's mass) and becomes the section's
  mass-only diameters, chosen so that ρA and ρI (mass and rotary inertia) of the layers are kept
  exactly; two structural layers are refused. A tapered element (``odl != odr`` or
  ``idl != idr``) becomes :data:`TAPER_PIECES` uniform elements at the diameters of each piece's
  middle. A gap in the element numbers (ROSS's ``MultiRotor`` numbers its second rotor after the
  first) starts a new shaft.
* ``DiskElement_*`` / ``GearElement_*``: ``m``, ``Ip``, ``Id`` → a disk (mass, polar, transverse)
  at the node. Two gears on different shafts become a gear mesh (teeth, base diameter,
  pressure and helix angle from the file); the file holds no mesh stiffness or orientation (a
  ``MultiRotor`` keeps them in memory only), so they are inputs of the import.
* ``BearingElement_*`` and its subclasses (``SealElement_*``, ball, roller, fluid-film tables):
  ``kxx``..``cyy`` (one value: constant; a list against ``speed`` in rad/s: a table; a 2-D
  table against ``speed`` and the whirl ``frequency``: a speed × whirl table; a list against
  ``frequency`` only: a speed × whirl table whose rows are that list at every speed, one row
  at each tabulated frequency) → a bearing, or a seal for seals; ``kzz``/``czz`` → a thrust
  bearing. Speed × whirl tables (docs/model_format.md) carry the frequency dependence into the
  eigenproblem exactly for their rational fit, where ROSS's ``run_modal`` reads them at
  synchronous whirl or, with ``matched_whirl=True``, at each mode's damped frequency. A
  bearing to a link node carrying a ``PointMass`` that a second, diagonal bearing holds to
  ground becomes a bearing on a pedestal (``support``).
* ``PointMass_*`` on a shaft node → a disk with that mass.

Refused, each with a one-line error naming the element and what to do: mass coefficients
(``mxx``...), shaft elements without shear, rotary inertia or gyroscopic terms, axial force or
torque preload, global or modal damping, magnetic bearings, couplings and motors. Between
table points ROSS interpolates by PCHIP and gearrotor linearly: results agree at the table's
speeds.
"""

from __future__ import annotations

from collections import defaultdict
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..errors import ModelError
from ..inputs import read_toml

__all__ = ["TAPER_PIECES", "ImportedModel", "import_ross", "model_toml"]

#: uniform pieces a tapered ROSS shaft element is split into
TAPER_PIECES = 8
#: a layer stiffer than this fraction of its element's stiffest layer is structural
_MASS_ONLY = 1e-3
_COEFS = ("kxx", "kxy", "kyx", "kyy", "cxx", "cxy", "cyx", "cyy")
_MASS_COEFS = ("mxx", "mxy", "myx", "myy", "mzz")
_REFUSED = {
    "MagneticBearingElement": "an active magnetic bearing (controller dynamics); give its "
    "equivalent stiffness and damping as a BearingElement in ROSS and save again",
    "CouplingElement": "a flexible coupling inside one rotor; split the rotor in two in the "
    "gearrotor model and join them with a [[couplings]] entry",
    "Motor": "a motor element; model its rotor as a disk and its torque as a [torsional] drive",
}


@dataclass
class ImportedModel:
    """A gearrotor model (the dict of a model file) and the notes of the import."""

    data: dict
    notes: list[str] = field(default_factory=list)
    comments: dict[str, str] = field(default_factory=dict)  # table path -> comment line


def _err(file: str, element: str, message: str, value=None, expected: str | None = None):
    return ModelError(message, field=element, value=value, expected=expected, file=file)


def import_ross(
    path: str | Path,
    *,
    speed: float = 0.0,
    mesh_stiffness: float | None = None,
    orientation: float = 0.0,
    name: str | None = None,
) -> ImportedModel:
    """Read the ROSS rotor file ``path``; ``speed`` (rad/s) is the reference shaft's speed of the
    model, ``mesh_stiffness`` (N/m) and ``orientation`` (rad, ROSS's ``orientation_angle``;
    gearrotor's line-of-centres angle is its negative) those of a gear mesh (ROSS's file does
    not hold them; the stiffness is required when the file has a gear pair). Raises
    :class:`ModelError` on what gearrotor cannot represent (module docstring)."""
    path = Path(path)
    file = str(path)
    raw = read_toml(path, "ROSS rotor")
    if not isinstance(raw.get("parameters"), dict) or "ross_version" not in raw:
        raise _err(
            file,
            "(top level)",
            "not a rotor saved by ROSS",
            expected="a file written by ROSS's Rotor.save (with ross_version and [parameters])",
        )
    params = raw["parameters"]
    for key in ("alpha", "beta", "default_damping_ratio", "modal_damping_ratio"):
        if float(params.get(key) or 0.0) != 0.0:
            raise _err(
                file,
                f"parameters.{key}",
                "global damping of the ROSS rotor is not imported",
                value=params[key],
                expected="0 (give the shafts' damping per element, alpha/beta, or bearings' "
                "damping in ROSS and save again)",
            )
    groups: dict[str, list[tuple[str, dict]]] = defaultdict(list)
    for key, value in raw.items():
        if key in ("parameters", "ross_version") or key.startswith("_"):
            continue
        if not isinstance(value, dict):
            raise _err(file, key, "unexpected entry", expected="an element table")
        cls = key.split("_")[0]
        if cls in _REFUSED:
            raise _err(file, key, f"{cls} is not imported: {_REFUSED[cls]}")
        groups[cls].append((key, value))
    shafts = groups.pop("ShaftElement", [])
    if not shafts:
        raise _err(
            file, "(top level)", "the rotor has no shaft elements", expected="ShaftElement_* tables"
        )
    out = ImportedModel(data={})
    chains, node_map, materials, sections, shear = _shafts(file, shafts, out)
    disks: dict[int, list[dict]] = defaultdict(list)
    gears = []
    for cls in ("DiskElement", "GearElement"):
        for key, d in groups.pop(cls, []):
            si, node = _node(file, key, d.get("n"), node_map)
            disk = {
                "node": node,
                "name": str(d.get("tag", key.split("_", 1)[1])),
                "mass": float(d["m"]),
                "polar": float(d["Ip"]),
                "transverse": float(d["Id"]),
            }
            disks[si].append(disk)
            if cls == "GearElement":
                gears.append((key, si, node, d))
    point = {}
    for key, d in groups.pop("PointMass", []):
        n = int(d["n"])
        mx, my = float(d.get("mx", d.get("m", 0.0))), float(d.get("my", d.get("m", 0.0)))
        if mx != my:
            raise _err(
                file,
                key,
                "a point mass with mx != my is not imported",
                value=(mx, my),
                expected="equal masses in x and y",
            )
        if n in node_map:
            si, node = node_map[n]
            disks[si].append(
                {
                    "node": node,
                    "name": str(d.get("tag", key)),
                    "mass": mx,
                    "polar": 0.0,
                    "transverse": 0.0,
                }
            )
        else:
            point[n] = (key, mx)
    bearings, seals, thrusts = _bearings(file, groups, node_map, point, chains, out)
    for cls, items in groups.items():
        key = items[0][0]
        raise _err(
            file,
            key,
            f"ROSS element type {cls} is not imported",
            expected="shaft, disk, gear, point-mass, bearing or seal elements",
        )
    shaft_names = [f"shaft{k + 1}" for k in range(len(chains))] if len(chains) > 1 else ["rotor"]
    data: dict = {
        "name": name or f"{path.stem} (imported from ROSS {raw['ross_version']})",
        "speed": speed,
        "shear_method": shear,
        "materials": materials,
        "shafts": [],
    }
    for k, secs in enumerate(sections):
        shaft = {"name": shaft_names[k], "material": secs[0]["material"], "sections": secs}
        if disks.get(k):
            shaft["disks"] = disks[k]
        data["shafts"].append(shaft)
    for group, items in (("bearings", bearings), ("seals", seals), ("thrust_bearings", thrusts)):
        for b in items:
            b["shaft"] = shaft_names[b.pop("_shaft")]
        if items:
            data[group] = items
    if gears:
        mesh = _mesh(file, gears, shaft_names, mesh_stiffness, orientation, out)
        data["meshes"] = [mesh]
        # ROSS's MultiRotor places the driven rotor so that the gears face each other; here the
        # second shaft starts where its gear node meets the first shaft's gear plane
        z = [_node_z(sh["sections"]) for sh in data["shafts"]]
        s1, s2 = (shaft_names.index(mesh[k]["shaft"]) for k in ("gear", "mate"))
        start = z[s1][mesh["gear"]["node"]] - z[s2][mesh["mate"]["node"]]
        if start != 0.0:
            data["shafts"][s2]["start"] = float(start)
        if len(chains) > 2:
            raise _err(
                file,
                gears[0][0],
                "more than two shafts are not imported",
                expected="a Rotor or a two-rotor MultiRotor",
            )
    elif len(chains) > 1:
        raise _err(
            file,
            shafts[0][0],
            f"the shaft elements form {len(chains)} separate chains but there is no gear pair "
            "joining them",
            expected="consecutive element numbers (one rotor) or a GearElement on each rotor",
        )
    out.data = data
    return out


def _node_z(sections: list[dict]) -> list[float]:
    z = [0.0]
    for sec in sections:
        for _ in range(sec["elements"]):
            z.append(z[-1] + sec["length"] / sec["elements"])
    return z


def _node(file: str, key: str, n, node_map) -> tuple[int, int]:
    try:
        return node_map[int(n)]
    except (KeyError, TypeError, ValueError):
        raise _err(
            file,
            f"{key}.n",
            "node is not on a shaft",
            value=n,
            expected=f"one of the shaft nodes {sorted(node_map)}",
        ) from None


def _material(file, key, m, materials, by_value) -> str:
    rho, E, G = (float(m[k]) for k in ("rho", "E", "G_s"))
    if (rho, E, G) in by_value:
        return by_value[(rho, E, G)]
    base = str(m.get("name") or "material")
    name, k = base, 2
    while name in materials:
        name, k = f"{base}_{k}", k + 1
    if not (rho > 0 and E > 0 and G > 0):
        raise _err(
            file, f"{key}.material", "material needs positive rho, E and G_s", value=(rho, E, G)
        )
    materials[name] = {"E": E, "shear_modulus": G, "density": rho}
    by_value[(rho, E, G)] = name
    return name


def _shafts(file, shafts, out):
    """Chains of elements, the node map ROSS node -> (shaft, node), materials, sections."""
    by_n: dict[int, list[tuple[str, dict]]] = defaultdict(list)
    shear = set()
    for key, d in shafts:
        for flag in ("shear_effects", "rotary_inertia", "gyroscopic"):
            if d.get(flag, True) is False:
                raise _err(
                    file,
                    f"{key}.{flag}",
                    f"shaft elements without {flag} are not imported",
                    value=False,
                    expected="true",
                )
        for pre in ("axial_force", "torque"):
            if float(d.get(pre) or 0.0) != 0.0:
                raise _err(
                    file,
                    f"{key}.{pre}",
                    f"a shaft element preloaded by {pre} is not imported",
                    value=d[pre],
                    expected="0",
                )
        shear.add(str(d.get("shear_method_calc", "cowper")))
        by_n[int(d["n"])].append((key, d))
    if len(shear) > 1:
        raise _err(
            file,
            "ShaftElement.shear_method_calc",
            "mixed shear coefficient methods",
            value=sorted(shear),
            expected="one method for every element",
        )
    method = shear.pop()
    if method not in ("cowper", "hutchinson"):
        raise _err(
            file,
            "ShaftElement.shear_method_calc",
            "unknown shear method",
            value=method,
            expected="'cowper' or 'hutchinson'",
        )
    ns = sorted(by_n)
    chains: list[list[int]] = [[ns[0]]]
    for n in ns[1:]:
        if n == chains[-1][-1] + 1:
            chains[-1].append(n)
        else:
            chains.append([n])
    materials: dict[str, dict] = {}
    by_value: dict = {}
    node_map: dict[int, tuple[int, int]] = {}
    sections: list[list[dict]] = []
    layered: list[tuple[int, float]] = []
    for si, chain in enumerate(chains):
        local = 0
        node_map[chain[0]] = (si, 0)
        secs: list[dict] = []
        for n in chain:
            layers = by_n[n]
            key = layers[0][0]
            lengths = {float(d["L"]) for _, d in layers}
            if len(lengths) > 1:
                raise _err(
                    file,
                    key,
                    "layers of one element with different lengths",
                    value=sorted(lengths),
                    expected="equal L for elements sharing n",
                )
            mods = [float(d["material"]["E"]) for _, d in layers]
            structural = [
                ly for ly, E in zip(layers, mods, strict=True) if E >= _MASS_ONLY * max(mods)
            ]
            if len(structural) > 1:
                raise _err(
                    file,
                    key,
                    f"{len(structural)} structural layers share element n = {n}",
                    expected="one structural layer (others mass only, with "
                    "a modulus below 1e-3 of it); merge them into one material in ROSS",
                )
            skey, sd = structural[0]
            mat = _material(file, skey, sd["material"], materials, by_value)
            L = float(sd["L"])
            tapered = float(sd["odl"]) != float(sd["odr"]) or float(sd["idl"]) != float(sd["idr"])
            pieces = TAPER_PIECES if tapered else 1
            if tapered:
                out.notes.append(f"{skey}: tapered element split into {pieces} uniform elements")
            for p in range(pieces):
                t = (p + 0.5) / pieces

                def dia(d, side, t=t):
                    return (1 - t) * float(d[f"{side}l"]) + t * float(d[f"{side}r"])

                od, idd = dia(sd, "od"), dia(sd, "id")
                sec = {
                    "length": L / pieces,
                    "outer_diameter": od,
                    "inner_diameter": idd,
                    "elements": 1,
                    "material": mat,
                }
                rho = float(sd["material"]["rho"])
                extra = [d for k, d in layers if k != skey]
                if extra:
                    a = rho * (od**2 - idd**2)  # ∝ ρA
                    b = rho * (od**4 - idd**4)  # ∝ ρI
                    for d in extra:
                        r = float(d["material"]["rho"])
                        o, i = dia(d, "od"), dia(d, "id")
                        a += r * (o**2 - i**2)
                        b += r * (o**4 - i**4)
                    a, b = a / rho, b / rho
                    mo2, mi2 = (a + b / a) / 2, max((b / a - a) / 2, 0.0)
                    sec["mass_outer_diameter"] = float(np.sqrt(mo2))
                    sec["mass_inner_diameter"] = float(np.sqrt(mi2))
                    layered.append((n, min(mods)))
                alpha = float(sd.get("alpha") or 0.0)
                beta = float(sd.get("beta") or 0.0)
                if alpha or beta:
                    dm = materials[mat].setdefault("damping", {"alpha": alpha, "beta": beta})
                    if (dm["alpha"], dm["beta"]) != (alpha, beta):
                        raise _err(
                            file,
                            skey,
                            "elements of one material with different alpha/beta",
                            expected="one alpha/beta per material",
                        )
                prev = secs[-1] if secs else None
                if (
                    prev is not None
                    and all(
                        prev.get(k) == sec.get(k)
                        for k in (
                            "outer_diameter",
                            "inner_diameter",
                            "material",
                            "mass_outer_diameter",
                            "mass_inner_diameter",
                        )
                    )
                    and np.isclose(prev["length"] / prev["elements"], sec["length"], rtol=1e-12)
                ):
                    prev["length"] += sec["length"]
                    prev["elements"] += 1
                else:
                    secs.append(sec)
                local += 1
            node_map[n + 1] = (si, local)
        sections.append(secs)
    if layered:
        ns_ = sorted({n for n, _ in layered})
        out.notes.append(
            f"{len(ns_)} elements (n = {ns_[0]}..{ns_[-1]}) carry a mass-only layer (modulus "
            f"{max(m for _, m in layered):.3g} Pa at most): kept as the sections' mass-only "
            "diameters (mass and rotary inertia of the layers)"
        )
    return chains, node_map, materials, sections, method


def _coefficients(file, key, d) -> tuple[np.ndarray | None, np.ndarray, np.ndarray | None]:
    """(speeds or None, coefficients, whirl frequencies or None): constants (1, 8); a speed
    table (n, 8); a speed × whirl table (n_speed, n_whirl, 8) with its whirl frequencies (ROSS
    3.x's 2-D ``(speed, frequency)`` tables, and its tables over ``frequency`` only, whose rows
    are the same at every speed: one row per tabulated frequency, at that speed)."""
    for c in _MASS_COEFS:
        if c in d and np.any(np.asarray(d[c], float) != 0.0):
            raise _err(
                file,
                f"{key}.{c}",
                "bearing mass coefficients are not imported",
                value=d[c],
                expected="0 (gearrotor bearings have stiffness and damping)",
            )
    cols = [np.asarray(d.get(c, 0.0), dtype=float) for c in _COEFS]
    if any(v.ndim > 1 for v in cols):
        return _whirl_coefficients(file, key, d, cols)
    cols = [np.atleast_1d(v) for v in cols]
    n = max(len(c) for c in cols)
    for c, name in zip(cols, _COEFS, strict=True):
        if len(c) not in (1, n):
            raise _err(
                file,
                f"{key}.{name}",
                "coefficient lists of different lengths",
                value=len(c),
                expected=f"{n} values or 1",
            )
    vals = np.column_stack([np.broadcast_to(c, (n,)) for c in cols])
    if n == 1:
        return None, vals, None
    frequency_only = d.get("speed") is None and d.get("frequency") is not None
    speed = d.get("speed", d.get("frequency"))
    if speed is None or len(np.atleast_1d(speed)) != n:
        raise _err(
            file,
            f"{key}.speed",
            "a coefficient table needs one speed per row",
            value=speed,
            expected=f"{n} speeds (rad/s)",
        )
    speed = np.asarray(speed, float)
    order = np.argsort(speed)
    if frequency_only:  # the same row at every speed: a row per frequency, at that speed
        f = np.abs(speed[order])
        return f, np.broadcast_to(vals[order], (len(f), len(f), 8)).copy(), f
    return speed[order], vals[order], None


def _fit_tolerance(whirl: np.ndarray, vals: np.ndarray) -> float | None:
    """None when every row of a speed × whirl table is fitted within the default tolerance,
    else a tolerance just above the largest misfit its whirl frequencies allow (a coarse ROSS
    table: three frequencies allow one pole), so that the imported model loads; the model file
    shows it."""
    from ..elements import FIT_TOLERANCE, fit_row

    worst = 0.0
    for v in vals:
        if np.all(v == v[0]):
            continue
        _, misfit = fit_row(np.abs(whirl), v, FIT_TOLERANCE)
        worst = max(worst, misfit)
    if worst <= FIT_TOLERANCE:
        return None
    return float(f"{1.2 * worst:.2g}")


def _whirl_coefficients(file, key, d, cols):
    """A ROSS 2-D table: coefficients (len(speed), len(frequency))."""
    speed, freq = d.get("speed"), d.get("frequency")
    if speed is None or freq is None:
        raise _err(
            file,
            f"{key}.speed",
            "a 2-D coefficient table needs its 'speed' and 'frequency' axes",
            expected="speed and frequency lists (rad/s)",
        )
    speed, freq = np.asarray(speed, float), np.asarray(freq, float)
    shape = (len(speed), len(freq))
    for c, name in zip(cols, _COEFS, strict=True):
        if c.ndim != 0 and c.shape != shape:
            raise _err(
                file,
                f"{key}.{name}",
                "a 2-D coefficient table of the wrong shape",
                value=list(c.shape),
                expected=f"{list(shape)} (len(speed), len(frequency))",
            )
    vals = np.stack([np.broadcast_to(c, shape) for c in cols], axis=-1)
    order = np.argsort(speed)
    return speed[order], vals[order], freq


def _bearings(file, groups, node_map, point, chains, out):
    bearings, seals, thrusts = [], [], []
    classes = [c for c in groups if "Bearing" in c or "Seal" in c]
    items = [(c, k, d) for c in classes for k, d in groups.pop(c)]
    # pedestals: bearings whose node is a link node (not on a shaft), i.e. ground supports
    ground_of_link: dict[int, tuple[str, dict]] = {}
    for _, key, d in items:
        n = int(d["n"])
        if n not in node_map:
            if n not in point:
                raise _err(
                    file,
                    f"{key}.n",
                    "node is neither a shaft node nor a point mass",
                    value=n,
                    expected=f"one of the shaft nodes {sorted(node_map)}",
                )
            ground_of_link[n] = (key, d)
    for c, key, d in items:
        n = int(d["n"])
        if n not in node_map:
            continue
        si, node = node_map[n]
        speed, vals, whirl = _coefficients(file, key, d)
        entry: dict = {"name": str(d.get("tag", key.split("_", 1)[1])), "_shaft": si, "node": node}
        if speed is None:
            entry.update({c_: float(v) for c_, v in zip(_COEFS, vals[0], strict=True)})
        elif whirl is not None:  # a speed × whirl table (docs/model_format.md)
            entry["table"] = {
                "speed": speed.tolist(),
                "whirl": whirl.tolist(),
                **{c_: vals[:, :, j].tolist() for j, c_ in enumerate(_COEFS)},
            }
            tol = _fit_tolerance(whirl, vals)
            if tol is not None:
                entry["fit_tolerance"] = tol
        else:
            entry["table"] = {
                "speed": speed.tolist(),
                **{c_: vals[:, j].tolist() for j, c_ in enumerate(_COEFS)},
            }
        link = d.get("n_link")
        if link is not None:
            link = int(link)
            if link not in point or link not in ground_of_link:
                raise _err(
                    file,
                    f"{key}.n_link",
                    "a bearing linked to a node that is not a "
                    "point mass held to ground by a bearing",
                    value=link,
                    expected="a PointMass node with a BearingElement to ground",
                )
            gkey, gd = ground_of_link[link]
            gs, gv, _ = _coefficients(file, gkey, gd)
            if gs is not None or any(gv[0][j] for j in (1, 2, 5, 6)):
                raise _err(
                    file,
                    gkey,
                    "a pedestal support with cross-coupled or tabulated "
                    "coefficients is not imported",
                    expected="constant kxx, kyy, cxx, cyy",
                )
            entry["support"] = {
                "mass": point[link][1],
                "kxx": float(gv[0][0]),
                "kyy": float(gv[0][3]),
                "cxx": float(gv[0][4]),
                "cyy": float(gv[0][7]),
            }
        is_seal = "Seal" in c
        if is_seal and "support" in entry:
            raise _err(
                file, key, "a seal on a pedestal is not imported", expected="a seal to ground"
            )
        (seals if is_seal else bearings).append(entry)
        kzz = np.atleast_1d(np.asarray(d.get("kzz", 0.0), float))
        czz = np.atleast_1d(np.asarray(d.get("czz", 0.0), float))
        if np.any(kzz) or np.any(czz):
            if len(np.unique(kzz)) > 1 or len(np.unique(czz)) > 1:
                raise _err(
                    file,
                    f"{key}.kzz",
                    "speed-dependent axial coefficients are not imported",
                    expected="constant kzz and czz",
                )
            thrusts.append(
                {
                    "name": f"{entry['name']} (axial)",
                    "_shaft": si,
                    "node": node,
                    "kzz": float(kzz[0]),
                    "czz": float(czz[0]),
                }
            )
    used = {int(d["n_link"]) for _, _, d in items if d.get("n_link") is not None}
    for n, (key, _) in point.items():
        if n not in used:
            raise _err(
                file,
                key,
                "a point mass off the shafts that no bearing links to",
                value=n,
                expected="a PointMass on a shaft node or a pedestal node",
            )
    return bearings, seals, thrusts


def _mesh(file, gears, names, stiffness, orientation, out) -> dict:
    if len(gears) != 2 or gears[0][1] == gears[1][1]:
        raise _err(
            file,
            gears[0][0],
            "gear elements other than one pair on two shafts",
            value=len(gears),
            expected="one GearElement on each of two shafts",
        )
    if stiffness is None:
        raise ModelError(
            "the ROSS file does not hold the gear mesh stiffness (a MultiRotor keeps it in "
            "memory only)",
            field="--mesh-stiffness",
            expected="the mesh stiffness of the gear pair, e.g. --mesh-stiffness 1e8",
        )
    sides = []
    for key, si, node, d in gears:
        pr, helix = float(d.get("pr_angle", 0.0)), float(d.get("helix_angle", 0.0))
        base = d.get("base_diameter")
        sides.append((key, si, node, int(d["n_teeth"]), float(base) / 2, pr, helix))
    (k1, s1, n1, z1, rb1, pr1, h1), (k2, s2, n2, z2, rb2, pr2, h2) = sides
    if not np.isclose(pr1, pr2) or not np.isclose(h1, h2):
        raise _err(
            file,
            k2,
            "the two gears have different pressure or helix angles",
            value=(pr2, h2),
            expected=f"those of {k1}: ({pr1}, {h1})",
        )
    out.notes.append(
        f"gear mesh {k1} - {k2}: stiffness {stiffness:.6g} N/m and orientation "
        f"{np.degrees(orientation):.6g} deg given on the import (not in ROSS's file)"
    )
    return {
        "name": "mesh",
        "gear": {"shaft": names[s1], "node": n1, "teeth": z1, "radius": rb1},
        "mate": {"shaft": names[s2], "node": n2, "teeth": z2, "radius": rb2},
        "radius_type": "base",
        "pressure_angle": pr1,
        "helix_angle": h1,
        "orientation": -orientation,  # ROSS's orientation_angle is −ϕ
        "stiffness": stiffness,
    }


# ----------------------------------------------------------------------------------------------
_UNITS = {
    "length": "m",
    "outer_diameter": "m",
    "inner_diameter": "m",
    "mass_outer_diameter": "m",
    "mass_inner_diameter": "m",
    "radius": "m",
    "E": "Pa",
    "shear_modulus": "Pa",
    "density": "kg/m^3",
    "mass": "kg",
    "polar": "kg*m^2",
    "transverse": "kg*m^2",
    "kxx": "N/m",
    "kxy": "N/m",
    "kyx": "N/m",
    "kyy": "N/m",
    "kzz": "N/m",
    "stiffness": "N/m",
    "cxx": "N*s/m",
    "cxy": "N*s/m",
    "cyx": "N*s/m",
    "cyy": "N*s/m",
    "czz": "N*s/m",
    "pressure_angle": "rad",
    "helix_angle": "rad",
    "orientation": "rad",
    "alpha": "1/s",
    "beta": "s",
}


def _value(key: str, v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, str):
        return '"' + v.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        unit = _UNITS.get(key)
        text = repr(float(v))
        return f'"{text} {unit}"' if unit else text
    if isinstance(v, list | tuple):
        return "[" + ", ".join(_value("", x) for x in v) + "]"
    if isinstance(v, dict):
        return "{ " + ", ".join(f"{k} = {_value(k, x)}" for k, x in v.items()) + " }"
    raise TypeError(type(v))


def model_toml(imported: ImportedModel, source: str) -> str:
    """The model file's text: units on every dimensional value, a header saying where it came
    from and the import's notes as comments."""
    d = imported.data
    lines = [
        f"# Imported from the ROSS rotor file {source} by gearrotor import-ross.",
        "# Shaft elements, disks, bearings and seals as ROSS saved them; see the notes below.",
    ]
    lines += [f"# note: {n}" for n in imported.notes]
    lines += [
        f"name = {_value('', d['name'])}",
        f'speed = "{d["speed"] * 30 / np.pi!r} rpm"  # reference shaft speed (--speed)',
        f"shear_method = {_value('', d['shear_method'])}  # ROSS shear_method_calc",
        "",
    ]
    for name, m in d["materials"].items():
        lines.append(f"[materials.{_value('', name) if not name.isidentifier() else name}]")
        for k, v in m.items():
            if k == "damping":
                lines.append(f"damping = {_value(k, v)}")
            else:
                lines.append(f"{k} = {_value(k, v)}")
        lines.append("")
    for s in d["shafts"]:
        lines.append("[[shafts]]")
        lines.append(f"name = {_value('', s['name'])}")
        lines.append(f"material = {_value('', s['material'])}")
        if "start" in s:
            lines.append(f"start = {_value('length', s['start'])}  # the gears face each other")
        lines.append("sections = [")
        for sec in s["sections"]:
            lines.append(f"  {_value('', sec)},")
        lines.append("]")
        if s.get("disks"):
            lines.append("disks = [")
            for dk in s["disks"]:
                lines.append(f"  {_value('', dk)},")
            lines.append("]")
        lines.append("")
    for group in ("bearings", "seals", "thrust_bearings", "meshes"):
        for item in d.get(group, []):
            lines.append(f"[[{group}]]")
            for k, v in item.items():
                if k == "table":
                    continue
                note = ""
                if k == "fit_tolerance":  # set by the import: the table cannot do better
                    note = "  # the misfit this table's whirl frequencies allow (import)"
                lines.append(f"{k} = {_value(k, v)}{note}")
            if "table" in item:
                t = item["table"]
                lines.append(f"[{group}.table]  # speeds in rad/s (ROSS); N/m and N*s/m")
                lines.append(f"speed = {_value('', [f'{x!r} rad/s' for x in t['speed']])}")
                if "whirl" in t:  # a speed × whirl table: a row per speed
                    lines.append(f"whirl = {_value('', [f'{x!r} rad/s' for x in t['whirl']])}")
                for c in _COEFS:
                    lines.append(f"{c} = {_value('', t[c])}")
            lines.append("")
    return "\n".join(lines).rstrip() + "\n"


# ----------------------------------------------------------------------------------------------
def _mass_layers(sec, field: str) -> list[tuple[float, float]]:
    """The annuli (inner, outer diameter) that a section's mass-only diameters add to its
    structural section."""
    mo = sec.mass_outer_diameter if sec.mass_outer_diameter is not None else sec.outer_diameter
    mi = sec.mass_inner_diameter if sec.mass_inner_diameter is not None else sec.inner_diameter
    if mo < sec.outer_diameter or mi > sec.inner_diameter:
        raise ModelError(
            "mass-only diameters inside the structural section cannot be exported to ROSS",
            field=field,
            value=(mi, mo),
            expected="mass_outer_diameter >= outer_diameter and mass_inner_diameter <= "
            "inner_diameter",
        )
    layers = []
    if mo > sec.outer_diameter:
        layers.append((sec.outer_diameter, mo))
    if mi < sec.inner_diameter:
        layers.append((mi, sec.inner_diameter))
    return layers


def ross_script(asm) -> str:
    """A Python script that builds the assembled model ``asm`` in ROSS 3.x (``rs.Rotor``, or a
    ``rs.MultiRotor`` for two shafts joined by one gear mesh) and runs its damped modes at the
    model's speed. Raises :class:`ModelError` for what ROSS cannot hold (module docstring of
    :func:`import_ross` lists the correspondence; couplings between shafts, more than two shafts
    or meshes, rotating material damping)."""
    from ..assembly import _disk_element, _shaft_elements

    train = asm.train
    layout = train.layout()
    if len(train.shafts) > 2 or len(train.meshes) > (1 if len(train.shafts) == 2 else 0):
        raise ModelError(
            "ROSS's MultiRotor joins two rotors by one gear pair",
            field="shafts",
            value=f"{len(train.shafts)} shafts, {len(train.meshes)} meshes",
            expected="one shaft, or two shafts joined by one mesh",
        )
    if len(train.shafts) == 2 and not train.meshes:
        raise ModelError(
            "two shafts without a gear mesh", field="meshes", expected="one mesh joining them"
        )
    if train.couplings:
        raise ModelError(
            "couplings are not exported",
            field="couplings",
            expected="a model without [[couplings]]",
        )
    if train.torsional_supports:
        raise ModelError(
            "torsional supports (springs / dampers to ground) are not exported",
            field="torsional_supports",
            expected="a model without [[torsional_supports]]",
        )
    for i, sh in enumerate(train.shafts):
        for k, sec in enumerate(sh.sections):
            for key in ("torsional_stiffness", "polar_inertia", "torsional_damping"):
                if getattr(sec, key) is not None:
                    raise ModelError(
                        "a section's torsional rod given directly is not exported (ROSS builds "
                        "it from the diameters)",
                        field=f"shafts[{i}].sections[{k}].{key}",
                        value=getattr(sec, key),
                        expected="the section from its diameters and material",
                    )
    lines = [
        f'"""{train.name}: exported from gearrotor for ROSS 3.x (gearrotor export --to '
        "ross-python).",
        "",
        "Units SI. Bearing and seal tables are the coefficients gearrotor assembles (fluid-film",
        "bearings solved at the tables' speeds); ROSS interpolates them by PCHIP, gearrotor",
        'linearly: results agree at the table speeds."""',
        "",
        "import numpy as np",
        "import ross as rs",
        "",
    ]
    mats: dict = {}
    for name, m in train.materials.items():
        if m.damping is not None and m.damping.rotating:
            raise ModelError(
                "rotating (internal) material damping is not exported",
                field=f"materials.{name}.damping.rotating",
                value=True,
                expected="false",
            )
        var = f"mat_{len(mats)}"
        mats[name] = var
        lines.append(
            f"{var} = rs.Material(name={name!r}, rho={m.density!r}, E={m.E!r}, G_s={m.G!r})"
        )
    lines.append(
        'mass_only = rs.Material(name="mass_only", rho=1.0, E=1.0, G_s=1.0)  # placeholder'
    )
    lines.append("")
    rotors = []
    for si, s in enumerate(train.shafts):
        sl = layout.shafts[si]
        els = _shaft_elements(train, si)
        lines.append(f"# shaft {s.name!r}: {len(els)} elements, nodes 0..{len(els)}")
        lines.append(f"shaft_{si} = []")
        e = 0
        for sec in s.sections:
            mat = sec.material or s.material
            m = train.materials[mat]
            alpha, beta = m.damping.rayleigh if m.damping is not None else (0.0, 0.0)
            for _ in range(sec.elements):
                el = els[e]
                lines.append(
                    f"shaft_{si}.append(rs.ShaftElement(L={el.length!r}, "
                    f"idl={el.inner_diameter!r}, odl={el.outer_diameter!r}, "
                    f"material={mats[mat]}, n={e}, "
                    f"shear_method_calc={train.shear_method!r}, alpha={alpha!r}, beta={beta!r}))"
                )
                if sec.mass_outer_diameter is not None or sec.mass_inner_diameter is not None:
                    for lo, hi in _mass_layers(sec, f"shafts[{si}].sections"):
                        # ROSS adds the layers of an element: the mass-only annuli as layers of
                        # the same density and negligible stiffness keep ρA and ρI exactly
                        lines.append(
                            f"shaft_{si}.append(rs.ShaftElement(L={el.length!r}, idl={lo!r}, "
                            f"odl={hi!r}, material=rs.Material(name='mass_only', "
                            f"rho={m.density!r}, E={m.E * 1e-9!r}, G_s={m.G * 1e-9!r}), "
                            f"n={e}, shear_method_calc={train.shear_method!r}))"
                        )
                e += 1
        lines.append(f"disks_{si} = []")
        gear_nodes = {}
        for k, mesh in enumerate(train.meshes):
            for side in ("gear", "mate"):
                ref = getattr(mesh, side)
                if ref.shaft == s.name:
                    gear_nodes[train.node_index(ref, f"meshes[{k}].{side}")[1]] = (k, side)
        used_disks = set()
        for node, (k, side) in gear_nodes.items():
            mesh = train.meshes[k]
            ref = getattr(mesh, side)
            ri, rj = train.pitch_radii(k)
            r = ri if side == "gear" else rj
            m = ip = it = 0.0
            for dk, d in enumerate(s.disks):
                if train.node_index(d, f"shafts[{si}].disks[{dk}]", shaft=s.name)[1] == node:
                    de = _disk_element(train, si, dk)
                    m, ip, it = m + de.mass, ip + de.polar, it + de.transverse
                    used_disks.add(dk)
            if ip <= 0.0:
                # ROSS's mesh divides by the gears' polar inertias: a gear without a disk gets
                # a vanishing one (1e-9 of the shaft's mass and inertia scale)
                scale = sum(x.mass for x in els)
                r2 = max(x.outer_diameter for x in els) ** 2 / 8
                m, ip, it = m + 1e-9 * scale, ip + 1e-9 * scale * r2, it + 0.5e-9 * scale * r2
                lines.append(
                    "# the gear has no disk in gearrotor: ROSS needs a (vanishing) inertia"
                )
            lines.append(
                f"gear_{si} = rs.GearElement(n={node}, m={m!r}, Id={it!r}, Ip={ip!r}, "
                f"n_teeth={ref.teeth}, pitch_diameter={2 * r!r}, pr_angle={mesh.pressure_angle!r}, "
                f"helix_angle={mesh.helix_angle!r})"
            )
            lines.append(f"disks_{si}.append(gear_{si})")
        for dk, d in enumerate(s.disks):
            if dk in used_disks:
                continue
            node = train.node_index(d, f"shafts[{si}].disks[{dk}]", shaft=s.name)[1]
            de = _disk_element(train, si, dk)
            lines.append(
                f"disks_{si}.append(rs.DiskElement(n={node}, m={de.mass!r}, Id={de.transverse!r}, "
                f"Ip={de.polar!r}, tag={(d.name or f'disk {dk}')!r}))"
            )
        lines.append(f"bearings_{si} = []")
        lines.append(f"points_{si} = []")
        link = len(els) + 1
        for b in asm.bearings:
            if b.shaft != si:
                continue
            node = int((b.dofs[0] - asm.node_offset[si][0]) // 6)
            cls = "SealElement" if b.kind == "seal" else "BearingElement"
            el = b.element
            if getattr(el, "whirl_dependent", False):
                # a speed × whirl table: ROSS's 2-D (speed, frequency) table on the union of
                # the rows' whirl frequencies (each row linear in whirl between its own)
                freq = np.unique(np.concatenate([r.whirl for r in el.rows]))
                grid = np.array([[r.at_whirl(f) for f in freq] for r in el.rows])
                coef = ", ".join(f"{c}={grid[:, :, j].tolist()!r}" for j, c in enumerate(_COEFS))
                coef += f", speed={[r.speed for r in el.rows]!r}, frequency={freq.tolist()!r}"
            elif el.speed_dependent:
                t = el.table
                coef = ", ".join(f"{c}={t.values[:, j].tolist()!r}" for j, c in enumerate(_COEFS))
                coef += f", speed={t.speed.tolist()!r}"
            else:
                kk, cc = el.K(0.0), el.C(0.0)
                vals = [
                    kk[0, 0],
                    kk[0, 1],
                    kk[1, 0],
                    kk[1, 1],
                    cc[0, 0],
                    cc[0, 1],
                    cc[1, 0],
                    cc[1, 1],
                ]
                coef = ", ".join(f"{c}={float(v)!r}" for c, v in zip(_COEFS, vals, strict=True))
            extra = ""
            spec = next((x for x in train.bearings if (x.name or "") == b.name), None)
            if b.support_dofs is not None and spec is not None and spec.support is not None:
                sup = spec.support
                extra = f", n_link={link}"
                lines.append(f"points_{si}.append(rs.PointMass(n={link}, m={sup.mass!r}))")
                lines.append(
                    f"bearings_{si}.append(rs.BearingElement(n={link}, kxx={sup.kxx!r}, "
                    f"kyy={sup.kyy!r}, cxx={sup.cxx!r}, cyy={sup.cyy!r}, "
                    f"tag={b.name + ' pedestal'!r}))"
                )
                link += 1
            lines.append(f"bearings_{si}.append(rs.{cls}(n={node}, {coef}{extra}, tag={b.name!r}))")
        for k, t in enumerate(train.thrust_bearings):
            if t.shaft == s.name:
                node = train.node_index(t, f"thrust_bearings[{k}]")[1]
                lines.append(
                    f"bearings_{si}.append(rs.BearingElement(n={node}, kxx=0.0, kyy=0.0, "
                    f"kzz={t.kzz!r}, czz={t.czz!r}, tag={(t.name or f'thrust {k}')!r}))"
                )
        for k, q in enumerate(train.cross_couplings):
            if q.shaft == s.name:
                node = train.node_index(q, f"cross_couplings[{k}]")[1]
                lines.append(
                    f"bearings_{si}.append(rs.BearingElement(n={node}, kxx=0.0, kxy={q.q!r}, "
                    f"kyx={-q.q!r}, kyy=0.0, tag={(q.name or f'cross coupling {k}')!r}))"
                )
        lines.append(
            f"rotor_{si} = rs.Rotor(shaft_{si}, disks_{si}, bearings_{si}, "
            f"point_mass_elements=points_{si}, tag={s.name!r})"
        )
        lines.append("")
        rotors.append((si, sl, gear_nodes))
    if len(rotors) == 1:
        lines.append("rotor = rotor_0")
    else:
        mesh = train.meshes[0]
        gi = train.shaft_index(mesh.gear.shaft, "meshes[0].gear.shaft")
        (_, _, g0), (_, _, g1) = rotors
        n0, n1 = next(iter(g0)), next(iter(g1))
        # ROSS measures the line of centres (driving rotor to driven rotor) the other way
        # round: its orientation_angle is −ϕ (checked on the flagship with anisotropic
        # bearings at ϕ = ±0.5 rad, tests/io/test_ross.py)
        phi = mesh.orientation if gi == 0 else mesh.orientation + np.pi
        lines.append(
            "rotor = rs.MultiRotor(rotor_0, rotor_1, "
            f"coupled_nodes=({n0}, {n1}), gear_mesh_stiffness={asm.meshes[0].stiffness!r}, "
            f"orientation_angle={float(-phi)!r}, "
            f"mesh_damping_ratio=0.0)"
        )
    speed = float(train.speed)
    lines += [
        "",
        f"SPEED = {speed!r}  # rad/s, the model's reference shaft ({speed * 30 / np.pi:.6g} rpm)",
        "",
        'if __name__ == "__main__":',
        "    modal = rotor.run_modal(speed=SPEED)",
        '    print("damped frequency (Hz), log dec")',
        "    for wd, ld in zip(modal.wd, modal.log_dec):",
        '        print(f"{wd / 2 / np.pi:12.4f} {ld:10.4f}")',
    ]
    return "\n".join(lines) + "\n"
