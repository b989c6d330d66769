"""Reference HCSM models shipped as package data (chapter Figures 13 and 22)."""

from __future__ import annotations

from importlib import resources
from pathlib import Path


def model_path(file_name: str) -> Path:
    """Filesystem path of a shipped ``.hcsm`` model, e.g. ``model_path("pfc_modes.hcsm")``."""
    return Path(str(resources.files(__name__).joinpath(file_name)))
