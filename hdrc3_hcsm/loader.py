"""Loading: parse + validate a ``.hcsm`` file into a model the interpreter can run."""

from __future__ import annotations

import enum
import os
from dataclasses import dataclass, replace
from pathlib import Path

from hdrc3_hcsm.diagnostics import Diagnostic, Severity, has_errors
from hdrc3_hcsm.errors import ModelError
from hdrc3_hcsm.model import Model
from hdrc3_hcsm.parser import ParseStatus, parse_file, parse_text
from hdrc3_hcsm.validation import validate

# Declarations an included file contributes, in this order before the includer's own.
_MERGED = ("computers", "events", "conditions", "flags", "slots", "containers", "automata")


class LoadStatus(enum.Enum):
    """Outcome of loading a model."""

    OK = "ok"
    INVALID = "invalid"


@dataclass(frozen=True)
class LoadResult:
    """The parsed model (None on syntax errors) and every diagnostic, sorted by position."""

    status: LoadStatus
    model: Model | None
    diagnostics: tuple[Diagnostic, ...]


def _expand(model: Model, stack: tuple[Path, ...], done: set[Path], out: list[Diagnostic]) -> Model:
    """Merge the declarations of included files (each file at most once) into ``model``."""
    if not model.includes:
        return model
    merged: dict[str, list[object]] = {name: [] for name in _MERGED}
    base = Path(model.file).parent
    for inc in model.includes:
        shown = Path(os.path.normpath(base / inc.path))
        try:
            path = shown.resolve()
        except (OSError, ValueError, RuntimeError) as exc:
            msg = f"cannot include {inc.path!r}: {exc}"
            out.append(Diagnostic(Severity.ERROR, "E005", msg, inc.pos))
            continue
        if path in stack:
            chain = " -> ".join(p.name for p in (*stack, path))
            out.append(Diagnostic(Severity.ERROR, "E003", f"include cycle: {chain}", inc.pos))
            continue
        if path in done:
            continue
        done.add(path)
        parsed = parse_file(shown)
        if parsed.status is ParseStatus.UNREADABLE:
            reason = parsed.diagnostics[0].message
            out.append(
                Diagnostic(
                    Severity.ERROR, "E005", f"cannot include {inc.path!r}: {reason}", inc.pos
                )
            )
            continue
        out.extend(parsed.diagnostics)
        if parsed.model is None:
            continue
        sub = _expand(parsed.model, (*stack, path), done, out)
        for kind, pos in (("model", sub.header_pos), ("root", sub.root_pos)):
            if pos is not None:
                msg = f"an included file must not declare '{kind}'"
                out.append(Diagnostic(Severity.ERROR, "E004", msg, pos))
        for name in _MERGED:
            merged[name].extend(getattr(sub, name))
    fields = {name: (*merged[name], *getattr(model, name)) for name in _MERGED}
    return replace(model, **fields)  # type: ignore[arg-type]


def _finish(model: Model | None, parse_diags: tuple[Diagnostic, ...]) -> LoadResult:
    if model is None:
        return LoadResult(LoadStatus.INVALID, None, parse_diags)
    top = Path(model.file).resolve()
    include_diags: list[Diagnostic] = []
    model = _expand(model, (top,), {top}, include_diags)
    if has_errors(include_diags):
        return LoadResult(LoadStatus.INVALID, model, tuple(include_diags))
    diags = (*include_diags, *validate(model))
    status = LoadStatus.INVALID if has_errors(diags) else LoadStatus.OK
    return LoadResult(status, model, diags)


def check_text(text: str, file: str = "<string>") -> LoadResult:
    """Parse and validate model text; never raises on bad input."""
    parsed = parse_text(text, file)
    return _finish(parsed.model, parsed.diagnostics)


def check_file(path: str | Path) -> LoadResult:
    """Parse and validate a model file; never raises on bad input."""
    parsed = parse_file(path)
    return _finish(parsed.model, parsed.diagnostics)


def _require(result: LoadResult) -> Model:
    if result.status is not LoadStatus.OK or result.model is None:
        errors = [str(d) for d in result.diagnostics if d.severity.value == "error"]
        raise ModelError("invalid HCSM model:\n" + "\n".join(errors))
    if not result.model.root:
        raise ModelError(f"{result.model.file}: model has no 'root' to run")
    return result.model


def load_text(text: str, file: str = "<string>") -> Model:
    """Parse and validate runnable model text, raising ModelError listing every error."""
    return _require(check_text(text, file))


def load_file(path: str | Path) -> Model:
    """Parse and validate a runnable model file, raising ModelError listing every error."""
    return _require(check_file(path))
