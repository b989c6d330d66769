"""A small synthetic recording of a few flights, for tests of everything that reads recordings.

Each agent flies 100 m east at 10 m/s and 30 m up, with one Data Interface sample and one PFC
state per second; uav0's fly-to asks for a segment and finishes, uav1's fails with a reason that
holds HTML special characters. Real messages, real MCAP: only the flight itself is made up.
"""

from __future__ import annotations

from pathlib import Path

import pymap3d
from rclpy.serialization import serialize_message

from hdrc3.mcap_recording import RecordingWriter, TopicInfo
from hdrc3_interfaces.msg import HelicopterState, PfcState, PlatformEvent

ORIGIN = (55.70, 13.47, 50.0)
"""(latitude, longitude, altitude) the flights' ENU coordinates are relative to."""
AGENTS = {"uav0": 0.0, "uav1": 40.0}
"""Agent -> north offset of its leg."""
FAILURE = "PFC fault: <b>GPS</b> & IMU"
"""uav1's failure reason."""


def write_fake_flights(
    path: Path, agents: dict[str, float] = AGENTS, *, samples: int = 11, rate: float = 1.0
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
    writer.close()
    return path
