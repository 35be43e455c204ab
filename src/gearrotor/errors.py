"""The package's own exceptions.

Every input error names where it comes from (file and field), the offending value and what was
expected, so that a user can fix the input without reading a traceback.
"""

from __future__ import annotations

__all__ = ["GearrotorError", "ModelError", "SolverError"]


class GearrotorError(Exception):
    """Base class of all gearrotor errors."""


class ModelError(GearrotorError, ValueError):
    """An invalid model or input.

    Parameters
    ----------
    message
        What is wrong.
    field
        Dotted path of the offending input field, e.g. ``meshes[0].gear.node``.
    value
        The offending value as given.
    expected
        What would have been accepted.
    file
        The input file, when the model came from one.
    """

    def __init__(
        self,
        message: str,
        *,
        field: str | None = None,
        value: object = None,
        expected: str | None = None,
        file: str | None = None,
    ) -> None:
        self.message = message
        self.field = field
        self.value = value
        self.expected = expected
        self.file = file
        super().__init__(self._format())

    def with_file(self, file: str) -> ModelError:
        """Return a copy of this error that names the input file."""
        return ModelError(
            self.message, field=self.field, value=self.value, expected=self.expected, file=file
        )

    def _format(self) -> str:
        where = ": ".join(p for p in (self.file, self.field) if p)
        text = f"{where}: {self.message}" if where else self.message
        if self.value is not None:
            text += f" (got {self.value!r})"
        if self.expected:
            text += f"; expected {self.expected}"
        return text


class SolverError(GearrotorError, RuntimeError):
    """A numerical solver failed (no convergence, divergence, singular system)."""
