"""The demo mission as an FCL client: take off, fly a survey through traj3d segments, land.

Everything goes through the Platform Server's FCL services and platform events, exactly as a TST
executor would use them (chapter §6.2, §7.2): segments are streamed one after another, the next
one sent when the control kernel requests it.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

from hdrc3_base.errors import Hdrc3Error
from hdrc3_control.path_segment import PathSegment
from hdrc3_interfaces.msg import FclReturn, HelicopterState
from hdrc3_interfaces.srv import FclLand, FclTakeoff, FclTraj3d, FclTraj3dFlyto
from hdrc3_navigation.messages import segment_to_msg
from hdrc3_platform_server.client import PlatformClient
from hdrc3_platform_server.codes import EventKind
from hdrc3_platform_server.completion import TERMINAL, CompletionEvent
from hdrc3_platform_server.geo_frame import WorldFrame
from hdrc3_platform_server.node import STATE_QOS

CALL_TIMEOUT_S = 10.0
READY_TIMEOUT_S = 120.0
COMMAND_TIMEOUT_S = 600.0
ON_GROUND_TIMEOUT_S = 60.0
"""Wall-clock bound on the Data Interface reporting the aircraft on the ground after landing."""


class MissionError(Hdrc3Error):
    """A step of the mission was refused or did not finish."""


@dataclass(frozen=True, slots=True)
class MissionStep:
    """One FCL command of the mission and how it ended."""

    command: str
    command_id: int
    outcome: str
    reason: str


class SurveyMission:
    """Runs take-off, fly-to, streamed survey segments and landing for one agent.

    :meth:`run` flies the whole mission; its steps (:meth:`takeoff`, :meth:`fly_to`,
    :meth:`stream`, :meth:`land`) are public so that a test can fly them between checks of its
    own. Each step raises MissionError unless its command finished.
    """

    def __init__(
        self,
        client: PlatformClient,
        frame: WorldFrame,
        survey: Sequence[PathSegment],
        log: Callable[[str], None] = print,
    ) -> None:
        """Prepare the mission; ``survey`` is flown after flying to its first point."""
        if not survey:
            raise MissionError("the survey has no segments")
        self._client = client
        self._frame = frame
        self._survey = list(survey)
        self._log = log
        self.steps: list[MissionStep] = []
        self.segment_ids: list[int] = []
        """Command ids of the segments of the latest :meth:`stream`, in flight order."""
        self._on_ground = False
        client.node.create_subscription(
            HelicopterState, f"/{client.agent}/helicopter_state", self._on_state, STATE_QOS
        )

    def _on_state(self, msg: Any) -> None:
        self._on_ground = bool(msg.on_ground_flag)

    def _call(self, srv: Any, name: str, request: Any) -> FclReturn:
        response = self._client.call(srv, f"fcl/{name}", request, CALL_TIMEOUT_S)
        if response is None:
            raise MissionError(f"fcl_{name}: no answer within {CALL_TIMEOUT_S} s")
        result: FclReturn = response.result
        return result

    def _accepted(self, srv: Any, name: str, request: Any) -> int:
        """Call until accepted (the kernel may still be initialising); return the command id."""
        deadline = time.monotonic() + READY_TIMEOUT_S
        while True:
            result = self._call(srv, name, request)
            if result.code == FclReturn.FCL_OK:
                self._log(f"fcl_{name}: FCL_OK (command {result.command_id})")
                return int(result.command_id)
            if time.monotonic() > deadline or self._client.process.stop_requested.is_set():
                raise MissionError(f"fcl_{name} refused: code {result.code}: {result.reason}")
            self._client.process.spin_until(lambda: False, 1.0)  # retry pace: 1 s

    def _finish(self, name: str, command_id: int) -> MissionStep:
        final = self._client.wait_final(command_id, COMMAND_TIMEOUT_S, lambda _e: None)
        if final is None:
            raise MissionError(f"fcl_{name} (command {command_id}) did not finish")
        step = MissionStep(f"fcl_{name}", command_id, final.kind.name, final.reason)
        self.steps.append(step)
        self._log(f"fcl_{name}: {final.kind.name} {final.reason}".rstrip())
        if final.kind is not EventKind.FINISHED:
            raise MissionError(f"fcl_{name} ended {final.kind.name}: {final.reason}")
        return step

    def _command(self, srv: Any, name: str, request: Any) -> MissionStep:
        return self._finish(name, self._accepted(srv, name, request))

    def _events_of(self, command_id: int) -> list[CompletionEvent]:
        return [e for e in self._client.events if e.command_id == command_id]

    def takeoff(self) -> MissionStep:
        """Take off from the pad; returns the finished step."""
        return self._command(FclTakeoff, "takeoff", FclTakeoff.Request())

    def fly_to(self, point: tuple[float, float, float], velocity: float) -> MissionStep:
        """Fly straight to ``point`` (local ENU, m) at ``velocity`` m/s and hover there."""
        lon, lat, alt = self._frame.to_wgs84(*point)
        return self._command(
            FclTraj3dFlyto,
            "traj3d_flyto",
            FclTraj3dFlyto.Request(longitude=lon, latitude=lat, altitude=alt, velocity=velocity),
        )

    def stream(self, path: Sequence[PathSegment]) -> MissionStep:
        """Fly ``path``: send its first segment, then each next one when the kernel asks (§7.2).

        Returns:
            The step of the last segment; every segment's command id is in :attr:`segment_ids`.
        """
        if not path:
            raise MissionError("the path has no segments")
        ids: list[int] = []
        self.segment_ids = ids
        for index, segment in enumerate(path):
            request = FclTraj3d.Request(
                segment=segment_to_msg(segment),
                velocity=segment.target_velocity,
                end_velocity=segment.end_velocity,
            )
            if index == 0:
                ids.append(self._accepted(FclTraj3d, "traj3d", request))
                continue
            previous = ids[-1]

            def requested(previous: int = previous) -> bool:
                return any(
                    e.kind is EventKind.SEGMENT_REQUEST or e.kind in TERMINAL
                    for e in self._events_of(previous)
                )

            if not self._client.process.spin_until(requested, COMMAND_TIMEOUT_S):
                raise MissionError(f"no segment request after segment {index - 1}")
            failed = [
                e
                for e in self._events_of(previous)
                if e.kind is not EventKind.FINISHED and e.kind in TERMINAL
            ]
            if failed:
                raise MissionError(
                    f"segment {index - 1} ended {failed[0].kind.name}: {failed[0].reason}"
                )
            result = self._call(FclTraj3d, "traj3d", request)
            if result.code != FclReturn.FCL_OK:
                raise MissionError(f"segment {index} refused: {result.reason}")
            ids.append(int(result.command_id))
        return self._finish("traj3d", ids[-1])

    def land(self, heading: float = 0.0) -> MissionStep:
        """Land with ``heading`` (rad), shut the engine down, and see the Data Interface say so.

        The Data Interface reports the touchdown at its next sample after FCL_FINISHED; a
        system stopped at once would otherwise end its recording one sample before it.
        """
        self._on_ground = False
        step = self._command(FclLand, "land", FclLand.Request(heading=heading))
        if not self._client.process.spin_until(lambda: self._on_ground, ON_GROUND_TIMEOUT_S):
            raise MissionError(
                f"fcl_land finished, but the Data Interface did not report the aircraft on the "
                f"ground within {ON_GROUND_TIMEOUT_S:.0f} s"
            )
        return step

    def run(self) -> list[MissionStep]:
        """Fly the whole mission; raises MissionError at the first step that fails."""
        self.takeoff()
        self.fly_to(self._survey[0].start, self._survey[0].target_velocity)
        self.stream(self._survey)
        self.land()
        return self.steps
