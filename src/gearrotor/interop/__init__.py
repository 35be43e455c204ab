"""Other tools' files: rotors from ROSS (``import_ross``) and scripts for ROSS (``ross_script``).

A room of its own above the assembly: the export writes the coefficients gearrotor assembles
(fluid-film bearing tables included); the import only needs the model."""

from .ross import import_ross, model_toml, ross_script

__all__ = ["import_ross", "model_toml", "ross_script"]
