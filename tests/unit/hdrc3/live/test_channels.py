from __future__ import annotations

import json
from collections.abc import Iterator
from pathlib import Path
from typing import Any

from hdrc3.live.channels import CHANNEL_NAMES, CHANNELS
from hdrc3.message_types import message_class

LAYOUT = Path(__file__).resolve().parents[4] / "foxglove" / "hdrc3.json"


def strings(value: Any) -> Iterator[str]:
    if isinstance(value, str):
        yield value
    elif isinstance(value, dict):
        for k, v in value.items():
            yield from strings(k)
            yield from strings(v)
    elif isinstance(value, list):
        for v in value:
            yield from strings(v)


def test_channel_names_are_unique_and_namespaced():
    assert len(set(CHANNEL_NAMES)) == len(CHANNEL_NAMES)
    assert all(name.startswith("/live/") for name in CHANNEL_NAMES)


def test_every_source_type_exists_and_agrees_across_channels():
    types: dict[str, str] = {}
    for channel in CHANNELS:
        for source in channel.sources:
            assert message_class(source.type_name) is not None
            assert types.setdefault(source.suffix, source.type_name) == source.type_name


def test_the_saved_layout_shows_exactly_the_registered_channels():
    layout = json.loads(LAYOUT.read_text(encoding="utf-8"))
    used = {s.split(".")[0] for s in strings(layout) if s.startswith("/live/")}
    assert used == set(CHANNEL_NAMES)


def test_layout_panels_exist_in_the_mosaic():
    layout = json.loads(LAYOUT.read_text(encoding="utf-8"))
    placed = {s for s in strings(layout["layout"]) if "!" in s}
    assert placed == set(layout["configById"])
