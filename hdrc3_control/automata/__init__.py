"""The PFC automata of chapter Figure 12 as ``.hcsm`` files (package data)."""

from __future__ import annotations

from importlib import resources
from pathlib import Path

PFC_MODEL = "pfc.hcsm"
"""The runnable model: Root with every PFC automaton below it."""


def automaton_path(file_name: str = PFC_MODEL) -> Path:
    """Filesystem path of a shipped automaton file, e.g. ``automaton_path("pfc.hcsm")``."""
    return Path(str(resources.files(__name__).joinpath(file_name)))
