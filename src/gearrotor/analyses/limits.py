"""Bounds on the size of a time integration, shared by the transients (6-DOF and torsional).

A transient keeps its saved histories in memory and steps a fixed number of times: a run whose
record would not fit, or that would not end, is refused before it starts, with one input error
naming ``t_end`` (or the option given) and the estimate, instead of a memory error traceback
after the allocation or a run killed hours later.
"""

from __future__ import annotations

from ..errors import ModelError

__all__ = ["MAX_RECORD_BYTES", "MAX_STEPS", "check_run_size"]

#: Largest record a transient allocates (bytes): the saved histories live in memory.
MAX_RECORD_BYTES = 2 * 1024**3
#: Most steps a transient takes (about a day at a few microseconds per step).
MAX_STEPS = 2 * 10**10


def check_run_size(
    n_steps: int,
    n_samples: int,
    values_per_sample: int,
    t_end: float,
    *,
    field: str = "t_end",
    value: float | None = None,
) -> None:
    """Refuse a run of ``n_steps`` steps saving ``n_samples`` samples of
    ``values_per_sample`` float64 values each: more than :data:`MAX_STEPS` steps or a record
    above :data:`MAX_RECORD_BYTES` is a :class:`ModelError` naming ``field`` (with ``value``,
    default ``t_end``)."""
    need = n_samples * values_per_sample * 8
    if need > MAX_RECORD_BYTES or n_steps > MAX_STEPS:
        raise ModelError(
            f"the run is too long: {n_steps:.3g} steps, {n_samples:.3g} saved samples of "
            f"{values_per_sample} values would need {need / 1e9:.3g} GB of memory",
            field=field,
            value=t_end if value is None else value,
            expected=f"a record of at most {MAX_RECORD_BYTES / 1e9:.3g} GB and at most "
            f"{MAX_STEPS:.3g} steps (a shorter t_end, a larger step or save interval)",
        )
