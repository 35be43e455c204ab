"""Input and output: TOML model files, overrides by dotted path."""

from .model_file import (
    apply_overrides,
    format_validation_error,
    load_model,
    model_from_dict,
    model_from_file_data,
    parse_overrides,
)

__all__ = [
    "apply_overrides",
    "format_validation_error",
    "load_model",
    "model_from_dict",
    "model_from_file_data",
    "parse_overrides",
]
