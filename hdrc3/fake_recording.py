"""A small synthetic recording of a few flights, for tests of everything that reads recordings.

Each agent flies 100 m east at 10 m/s and 30 m up, with one Data Interface sample and one PFC
state per second; uav0's fly-to asks for a segment and finishes, uav1's fails with a reason that
holds HTML special characters. With ``upper_layers`` the TST managers, the execution monitor and
the saliency node speak too (:func:`_upper_layers`). Real messages, real MCAP: only the flight
itself is made up.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import pymap3d
from rclpy.serialization import serialize_message
from std_msgs.msg import String

from hdrc3.mcap_recording import RecordingWriter, TopicInfo
from hdrc3_interfaces.msg import (
    HelicopterState,
    MonitorViolation,
    PfcState,
    PlatformEvent,
    RecoveryEvent,
    TstNodeStatus,
)

ORIGIN = (55.70, 13.47, 50.0)
"""(latitude, longitude, altitude) the flights' ENU coordinates are relative to."""
AGENTS = {"uav0": 0.0, "uav1": 40.0}
"""Agent -> north offset of its leg."""
FAILURE = "PFC fault: <b>GPS</b> & IMU"
"""uav1's failure reason."""


def write_fake_flights(
    path: Path,
    agents: dict[str, float] = AGENTS,
    *,
    samples: int = 11,
    rate: float = 1.0,
    upper_layers: bool = False,
) -> Path:
    """Write the recording to ``path`` (an empty ``agents`` writes only a ``/clock`` channel).

    ``samples`` Data Interface samples and PFC states per agent at ``rate`` Hz cover the 100 m.
    """
    writer = RecordingWriter(path)
    writer.add_topic(TopicInfo("/clock", "rosgraph_msgs/msg/Clock"))
    for agent in agents:
        for topic, kind in (
            ("helicopter_state", "HelicopterState"),
            ("platform_events", "PlatformEvent"),
            ("pfc/state", "PfcState"),
        ):
            writer.add_topic(TopicInfo(f"/{agent}/{topic}", f"hdrc3_interfaces/msg/{kind}"))
    speed = 100.0 / ((samples - 1) / rate)
    for i in range(samples):
        stamp_ns = 100 * 10**9 + round(i / rate * 1e9)
        for agent, north in agents.items():
            lat, lon, alt = pymap3d.enu2geodetic(speed * i / rate, north, 30.0, *ORIGIN)
            msg = HelicopterState(latitude=lat, longitude=lon, altitude=alt, velocity_east=speed)
            msg.header.stamp.sec, msg.header.stamp.nanosec = divmod(stamp_ns, 10**9)
            writer.write(f"/{agent}/helicopter_state", serialize_message(msg), stamp_ns)
            pfc = PfcState(mode=PfcState.MODE_HOVER if i < 3 else PfcState.MODE_FLYTO)
            pfc.header.stamp = msg.header.stamp
            writer.write(f"/{agent}/pfc/state", serialize_message(pfc), stamp_ns)
    for agent, kind, reason in (
        ("uav0", PlatformEvent.KIND_SEGMENT_REQUEST, ""),
        ("uav0", PlatformEvent.KIND_FINISHED, ""),
        ("uav1", PlatformEvent.KIND_FAILED, FAILURE),
    ):
        if agent in agents:
            event = PlatformEvent(command="fcl_traj3d_flyto", kind=kind, reason=reason)
            event.header.stamp.sec = 110
            writer.write(f"/{agent}/platform_events", serialize_message(event), 110 * 10**9)
    if upper_layers:
        _upper_layers(writer, list(agents))
    writer.close()
    return path


def _upper_layers(writer: RecordingWriter, agents: list[str]) -> None:
    """TST nodes, monitor verdicts, a recovery and a saliency map of uav0 and uav1.

    uav0 flies node ``fly`` (fly-to) from 101 to 109 s of sim time under a sequence, then
    ``look`` (look-at) runs until the recording ends, and its saliency map holds DETECTIONS;
    uav1's ``scan`` (scan-area) fails at 108 s with FAILURE after the speed limit was violated at
    105 s (a hover recovery, no new plan) and a stale stream.
    """
    if agents[:2] != ["uav0", "uav1"]:
        return
    status = "hdrc3_interfaces/msg/TstNodeStatus"
    for agent, topic, kind in (
        ("uav0", "tst_status", status),
        ("uav0", "saliency/map", "std_msgs/msg/String"),
        ("uav1", "tst_status", status),
        ("uav1", "monitor_violations", "hdrc3_interfaces/msg/MonitorViolation"),
        ("uav1", "recovery_events", "hdrc3_interfaces/msg/RecoveryEvent"),
    ):
        writer.add_topic(TopicInfo(f"/{agent}/{topic}", kind))
    nan = math.nan
    rows: list[tuple[float, str, object]] = [
        (100.0, "uav0", TstNodeStatus(mission="m", agent="uav0", node_id="root", kind="sequence",
                                      state="running", start=100.0, end=nan)),
        (100.0, "uav0", TstNodeStatus(mission="m", agent="uav0", node_id="fly", kind="fly-to",
                                      state="created", start=nan, end=nan)),
        (101.0, "uav0", TstNodeStatus(mission="m", agent="uav0", node_id="fly", kind="fly-to",
                                      state="running", start=101.0, end=nan)),
        (109.0, "uav0", TstNodeStatus(mission="m", agent="uav0", node_id="fly", kind="fly-to",
                                      state="succeeded", start=101.0, end=109.0)),
        (109.0, "uav0", TstNodeStatus(mission="m", agent="uav0", node_id="root", kind="sequence",
                                      state="succeeded", start=100.0, end=109.0)),
        (109.5, "uav0", TstNodeStatus(mission="m", agent="uav0", node_id="look", kind="look-at",
                                      state="running", start=109.5, end=nan)),
        (102.0, "uav1", TstNodeStatus(mission="m", agent="uav1", node_id="scan",
                                      kind="scan-area", state="running", start=102.0, end=nan)),
        (105.0, "uav1", MonitorViolation(agent="uav1", monitor_id="speed_limit",
                                         kind=MonitorViolation.KIND_VIOLATION, recovery="hover",
                                         formula="always speed(uav1) <= 12")),
        (105.5, "uav1", RecoveryEvent(mission="m", agent="uav1", node_id="scan",
                                      monitor_id="speed_limit", step=RecoveryEvent.STEP_HOVERING,
                                      attempt=1, reason="holding")),
        (106.0, "uav1", MonitorViolation(agent="uav1", monitor_id="held",
                                         kind=MonitorViolation.KIND_STALE_DATA,
                                         reason="no hook sample for 1.2 s")),
        (108.0, "uav1", TstNodeStatus(mission="m", agent="uav1", node_id="scan",
                                      kind="scan-area", state="failed", start=102.0, end=108.0,
                                      reason=FAILURE)),
        (110.0, "uav0", String(data=json.dumps(_saliency_map()))),
    ]  # fmt: skip
    for t, agent, msg in rows:
        header = getattr(msg, "header", None)
        if header is not None:
            header.stamp.sec, header.stamp.nanosec = int(t), round(t % 1 * 1e9)
        topic = {
            TstNodeStatus: "tst_status",
            MonitorViolation: "monitor_violations",
            RecoveryEvent: "recovery_events",
            String: "saliency/map",
        }[type(msg)]
        writer.write(f"/{agent}/{topic}", serialize_message(msg), round(t * 1e9))


DETECTIONS = ((50.0, 5.0, True), (20.0, -10.0, False))
"""(east, north, confirmed) of uav0's saliency map points, in ORIGIN's frame on the ground."""


def _saliency_map() -> dict[str, object]:
    """uav0's map in the layout of ``hdrc3_perception.saliency_map.to_geojson``."""
    features = []
    for ident, (east, north, confirmed) in enumerate(DETECTIONS):
        lat, lon, alt = pymap3d.enu2geodetic(east, north, 0.0, *ORIGIN)
        t_frame, t_body = (6, 5) if confirmed else (4, 1)
        props = {"id": ident, "lat": lat, "lon": lon, "alt": alt, "east": east, "north": north,
                 "up": 0.0, "p_body": t_body / t_frame, "t_frame": t_frame, "t_body": t_body,
                 "first_seen": 104.0 + ident, "confirmed": confirmed}  # fmt: skip
        point = {"type": "Point", "coordinates": [lon, lat]}
        features.append({"type": "Feature", "geometry": point, "properties": props})
    return {"type": "FeatureCollection", "features": features}
