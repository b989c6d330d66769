"""`hdrc3 fcl/ppcl/state`: bad input is refused before any ROS traffic (exit 2)."""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import TYPE_CHECKING, cast

import pytest

from hdrc3.cli.fcl import build_request as fcl_request
from hdrc3.cli.fcl import parse_numbers, wait_accepted
from hdrc3_platform_server.codes import EventKind
from hdrc3_platform_server.completion import TERMINAL, CompletionEvent

if TYPE_CHECKING:
    from hdrc3_platform_server.client import PlatformClient
from hdrc3.cli.main import build_parser, main


@pytest.mark.parametrize(
    "argv",
    [
        ["fcl", "uav0", "land"],
        ["fcl", "uav0", "traj3d_flyto", "13.47", "55.7", "125"],
        ["fcl", "uav0", "yaw", "north"],
        ["fcl", "Bad Agent", "takeoff"],
        ["fcl", "uav0", "takeoff", "--timeout", "0"],
        ["ppcl", "uav0", "request", "wheel"],
        ["ppcl", "uav0", "turn_to", "a", "b"],
        ["ppcl", "uav0", "exposure", "sometimes"],
        ["ppcl", "uav0", "look_at", "13.47"],
        ["state", "Bad Agent"],
        ["state", "uav0", "--timeout", "-1"],
    ],
)
def test_bad_input_exits_2(argv: list[str], capsys: pytest.CaptureFixture[str]) -> None:
    assert main(argv) == 2
    assert "error" in capsys.readouterr().err


def test_unknown_command_is_an_argparse_error() -> None:
    with pytest.raises(SystemExit):
        build_parser().parse_args(["fcl", "uav0", "barrel_roll"])


def test_fcl_requests_use_radians_and_keep_wgs84() -> None:
    _, land = fcl_request("land", parse_numbers("land", ["90"]))
    assert land.heading == pytest.approx(math.pi / 2)  # type: ignore[attr-defined]
    _, fly = fcl_request(
        "traj3d_flyto", parse_numbers("traj3d_flyto", ["13.47", "55.7", "125", "8"])
    )
    assert (fly.longitude, fly.latitude, fly.altitude, fly.velocity) == (13.47, 55.7, 125.0, 8.0)  # type: ignore[attr-defined]
    _, seg = fcl_request("traj3d", tuple(float(i) for i in range(14)))
    assert seg.segment.end_point.x == 3.0 and seg.end_velocity == 13.0  # type: ignore[attr-defined]


def test_ppcl_requests() -> None:
    from hdrc3.cli.ppcl import build_request as ppcl_request

    args = build_parser().parse_args(["ppcl", "uav0", "turn_to", "0", "90"])
    _, name, req = ppcl_request(args)
    assert name == "ppcl/turn_to" and req.tilt == pytest.approx(math.pi / 2)
    args = build_parser().parse_args(["ppcl", "uav0", "zoom", "0.5", "--camera", "thermal"])
    _, name, req = ppcl_request(args)
    assert (name, req.camera_id, req.value) == ("ppcl/zoom", 1, 0.5)
    args = build_parser().parse_args(["ppcl", "uav0", "release", "laser", "--owner", "x"])
    _, name, req = ppcl_request(args)
    assert (name, req.resource, req.request, req.owner) == ("ppcl/control", 3, False, "x")


class _Events:
    """A PlatformClient stand-in: ``wait_final`` replays events of one command."""

    def __init__(self, events: list[CompletionEvent]) -> None:
        self.events = events

    def wait_final(
        self, command_id: int, timeout: float, on_event: Callable[[CompletionEvent], None]
    ) -> CompletionEvent | None:
        for event in self.events:
            if event.kind in TERMINAL:
                return event
            on_event(event)
        return None


def _event(kind: EventKind, reason: str) -> CompletionEvent:
    return CompletionEvent(7, "fcl_track", kind, reason, 0.0)


@pytest.mark.parametrize(
    ("events", "code"),
    [
        ([_event(EventKind.INFO, "accepted by the PFC")], 0),
        (
            [_event(EventKind.INFO, "PFC fault: x"), _event(EventKind.INFO, "accepted by the PFC")],
            0,
        ),
        ([_event(EventKind.FAILED, "rejected by the PFC: track: no colour track")], 1),
        ([], 1),
    ],
)
def test_track_no_wait_returns_on_the_pfcs_acceptance(
    events: list[CompletionEvent], code: int, capsys: pytest.CaptureFixture[str]
) -> None:
    client = cast("PlatformClient", _Events(events))
    assert wait_accepted(client, "fcl_track", 7, 1.0) == code
    if events:
        assert events[-1].reason in capsys.readouterr().out
