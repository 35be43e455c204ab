"""Gear-pair files (TOML): the keys of :class:`gearrotor.model.gear_pair.GearPair`.

Values may carry units (``"3 mm"``, ``"20 deg"``, ``"206 GPa"``, ``"500 N*m"``); plain numbers
are SI (m, rad, Pa, N·m). Unknown keys are rejected; every error is one line naming the file,
the field, the value and what was expected. The format is in ``docs/gears.md``; examples are in
``examples/gears/``::

    module = "3 mm"                 # normal module
    teeth = [50, 50]                # [pinion, gear]
    pressure_angle = "20 deg"       # normal
    helix_angle = "0 deg"
    face_width = "20 mm"
    addendum_coefficient = 1.0
    dedendum_coefficient = 1.25
    profile_shift = [0.0, 0.0]
    bore_diameter = ["60 mm", "60 mm"]   # optional (solid bodies without it)
    E = "206 GPa"
    poisson = 0.3
    torque = "200 N*m"              # pinion torque (or gearrotor mesh --torque)

    [modifications.pinion]
    tip_relief = { amount = "8 um", length = "2 mm", shape = "linear" }
"""

from __future__ import annotations

import difflib
from pathlib import Path

from pydantic import ValidationError

from ..errors import ModelError
from ..inputs import read_toml
from ..model.gear_pair import FlankModifications, GearModifications, GearPair, ToothRelief

__all__ = ["load_gear_pair", "parse_gear_pair", "merge_gear_pair"]


def _known_keys() -> set[str]:
    keys: set[str] = set()
    for cls in (GearPair, GearModifications, FlankModifications, ToothRelief):
        keys |= set(cls.model_fields)
    return keys - {"file"}


def _where(loc: tuple) -> str:
    out = ""
    for part in loc:
        if isinstance(part, int):
            out += f"[{part}]"
        elif str(part).startswith(("function-", "tuple[", "float", "str")):
            continue
        else:
            out += ("." if out else "") + str(part)
    return out or "(top level)"


def _lookup(doc, loc: tuple):
    cur = doc
    for part in loc:
        if isinstance(cur, dict) and part in cur:
            cur = cur[part]
        elif isinstance(cur, list) and isinstance(part, int) and part < len(cur):
            cur = cur[part]
        else:
            return cur if not isinstance(cur, dict | list) else None
    return cur


def parse_gear_pair(doc: dict, source: str = "", *, complete: bool = True) -> GearPair:
    """Validate the top-level keys of a gear-pair file (or an inline geometry); with
    ``complete`` the required keys must all be there. Errors name ``source``."""
    if "file" in doc and source:
        raise ModelError(
            "a gear-pair file cannot point to another one",
            field="file",
            value=doc["file"],
            file=source,
        )
    try:
        spec = GearPair.model_validate(doc)
    except ValidationError as exc:
        errors = sorted(exc.errors(include_url=False), key=lambda e: e["type"] != "extra_forbidden")
        first = errors[0]
        more = f" (and {len(errors) - 1} more error(s))" if len(errors) > 1 else ""
        msg = first["msg"].removeprefix("Value error, ")
        kind = first["type"]
        where = _where(first["loc"])
        value = _lookup(doc, first["loc"])
        if kind == "extra_forbidden":
            key = first["loc"][-1]
            close = difflib.get_close_matches(str(key), sorted(_known_keys()), n=1, cutoff=0.7)
            message = f"unknown key {key!r}" + (f" (did you mean {close[0]!r}?)" if close else "")
            expected, value = "a key listed in docs/gears.md", None
        elif kind == "value_error":
            message, expected = msg, None
        else:
            message, expected = "invalid value", msg[:1].lower() + msg[1:]
        if isinstance(value, dict):
            value = None
        raise ModelError(
            message + more, field=where, value=value, expected=expected, file=source or None
        ) from None
    if complete and spec.missing():
        raise ModelError(
            "missing required keys",
            field=", ".join(spec.missing()),
            expected="module, teeth, pressure_angle and face_width (docs/gears.md)",
            file=source or None,
        )
    return spec


def load_gear_pair(path: str | Path) -> GearPair:
    """Read and validate a gear-pair file."""
    path = Path(path)
    doc = read_toml(path, "gear-pair")
    if not doc:
        raise ModelError(
            "the gear-pair file is empty", file=str(path), expected="module, teeth, ..."
        )
    if "shafts" in doc:
        raise ModelError(
            "this is a rotor model file, not a gear-pair file",
            file=str(path),
            expected="a gear-pair file (docs/gears.md); `gearrotor mesh-response` takes models",
        )
    return parse_gear_pair(doc, str(path))


def merge_gear_pair(ref: GearPair, field: str = "geometry") -> GearPair:
    """The complete gear pair of a model's ``geometry``: its ``file`` (if any) read, with the
    keys given inline taking precedence. Errors in the file name the file; errors of the
    merged pair name ``field``."""
    if ref.file is None:
        if ref.missing():
            raise ModelError(
                "the inline gear geometry misses required keys",
                field=f"{field}.{', '.join(ref.missing())}",
                expected="module, teeth, pressure_angle and face_width, or 'file' (a "
                "gear-pair file)",
            )
        return ref
    base = load_gear_pair(ref.file)
    inline = ref.model_dump(exclude_unset=True, exclude={"file"})
    merged = base.model_dump(exclude_unset=True) | inline
    try:
        return GearPair.model_validate(merged | {"file": ref.file})
    except ValidationError as exc:  # pragma: no cover - both halves validated already
        raise ModelError(str(exc).splitlines()[0], field=field) from None
