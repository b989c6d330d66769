"""Progress bars of long commands: a recording's messages (report, replay), a roadmap's growth."""

from __future__ import annotations

from rich.console import Console
from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn


def message_bar(console: Console, verb: str) -> Progress:
    """A transient bar ``VERB NAME [bar] done/total elapsed``, drawn on a terminal only.

    Tasks carry a ``name`` field (the file, the world).

    Piped output gets the commands' own summary lines, not a bar redrawn in place.
    """
    return Progress(
        TextColumn(f"{verb} {{task.fields[name]}}"),
        BarColumn(),
        MofNCompleteColumn(),
        TimeElapsedColumn(),
        console=console,
        transient=True,
        disable=not console.is_terminal,
    )
