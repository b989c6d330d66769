from __future__ import annotations

import json
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from hdrc3.live.channels import CHANNEL_NAMES, CHANNELS, STATIC_CHANNEL_NAMES, registered
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
    entries = {name: registered(name) for name in used}
    assert None not in entries.values(), entries
    assert {c.topic for c in entries.values() if c is not None} == set(CHANNEL_NAMES)


def test_the_layout_shows_each_camera_channel_in_an_image_panel():
    layout = json.loads(LAYOUT.read_text(encoding="utf-8"))
    images = {
        config["imageMode"]["imageTopic"]
        for panel, config in layout["configById"].items()
        if panel.startswith("Image!")
    }
    assert images == {"/live/camera/color/uav0", "/live/camera/thermal/uav0"}
    scene = layout["configById"]["3D!hdrc3scene"]["topics"]
    assert "/live/saliency" in scene


@pytest.mark.parametrize(
    ("name", "entry"),
    [
        ("/live/tf", "/live/tf"),
        ("/live/camera/color/uav1", "/live/camera/color"),
        ("/live/camera/color", None),  # per agent: only its instances are channels
        ("/live/camera/color/UAV1", None),  # not an agent name
        ("/live/tf/uav0", None),  # not per agent
        ("/uav0/ground_truth/state", None),
    ],
)
def test_registered_resolves_advertised_names(name, entry):
    found = registered(name)
    assert (found.topic if found else None) == entry


def test_per_agent_channels_are_not_static_and_not_latched():
    per_agent = [c for c in CHANNELS if c.per_agent]
    assert {c.topic for c in per_agent} == {"/live/camera/color", "/live/camera/thermal"}
    assert not any(c.topic in STATIC_CHANNEL_NAMES for c in per_agent)
    assert all(c.on_demand and not c.latched for c in per_agent)
    assert per_agent[0].instance("uav0") == "/live/camera/color/uav0"


def test_layout_panels_exist_in_the_mosaic():
    layout = json.loads(LAYOUT.read_text(encoding="utf-8"))
    placed = {s for s in strings(layout["layout"]) if "!" in s}
    assert placed == set(layout["configById"])
