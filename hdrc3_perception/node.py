"""ROS 2 adapter: the ``saliency`` node (one per agent namespace), Algorithm 4 on image pairs.

Subscribes (relative to the agent's namespace): ``camera/color/image_raw`` (``rgb8``) and
``camera/thermal/image_raw`` (``mono16``, centi-kelvin) with their ``camera_info``; the Data
Interface's ``helicopter_state`` (the aircraft's own navigation solution, WGS84 -> local ENU of
the world's origin) and ``camera_state`` (PTU pan and tilt). Each thermal image is paired with
the colour image of the same stamp (within ``pair_tolerance_s``) and handed to the pure core with
the navigation state nearest the image's stamp and the PTU angles interpolated to it
(:mod:`hdrc3_perception.history`): an image arrives after the aircraft has moved on, so the
latest state would misplace what it shows. A pair with no state or PTU angles within
:data:`~hdrc3_perception.history.MAX_GAP_S` of its stamp is not processed (status
``no_state``, with the reason).

The PPC engages the pipeline (``ppcl_ip_saliency``, stopped by ``ppcl_ip_abort``): the node
follows the kernel's latched ``ppc/image_processing`` and subscribes the images only while it is
``SALIENCY``, so the renderer draws nothing for it otherwise. ``gated`` false processes every
pair from the start (a camera feed without a PPC).

Publishes ``~/engaged`` (``std_msgs/Bool``, latched: whether the images are subscribed; once it
reads false no further pair is processed), ``~/pair_result`` (``std_msgs/String``, JSON: status,
reason, per-stage counts) for every thermal image, and when the map changed ``~/map``
(``std_msgs/String``, latched: the map as GeoJSON) and ``~/markers``
(``visualization_msgs/MarkerArray``, one sphere per location, green when confirmed); with
``geojson_path`` set, the file is rewritten on each change.

Parameters: ``world`` (shipped name or .toml path: origin and terrain), ``detector``
(``hog_people``, default, | ``haar_kruppa``), ``geojson_path`` ("" = no file), ``pair_tolerance_s``,
``gated`` (default true).
"""

from __future__ import annotations

import functools
import json
import sys
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray
from rclpy.node import Node
from rclpy.qos import QoSProfile, ReliabilityPolicy, qos_profile_sensor_data
from rclpy.subscription import Subscription
from sensor_msgs.msg import CameraInfo, Image
from std_msgs.msg import String
from visualization_msgs.msg import Marker, MarkerArray

from hdrc3_base.errors import ConfigError, Hdrc3Error
from hdrc3_base.ros_env import apply_dds_defaults
from hdrc3_base.ros_runtime import run_node
from hdrc3_base.stamps import stamp_s
from hdrc3_control.ppc_modes import ImageProcessing
from hdrc3_interfaces.msg import CameraState, HelicopterState
from hdrc3_perception.camera import Intrinsics, NavPose
from hdrc3_perception.classifier import ClassifierParams, Detector
from hdrc3_perception.geolocation import Ground
from hdrc3_perception.history import MAX_GAP_S, NavHistory, PtuHistory
from hdrc3_perception.image_gate import LATCHED, ImageGate
from hdrc3_perception.pipeline import (
    CameraImage,
    FramePair,
    PairResult,
    PairStatus,
    PipelineConfig,
    SaliencyPipeline,
)
from hdrc3_perception.saliency_map import dumps_geojson
from hdrc3_platform_server.geo_frame import WorldFrame
from sim.world_loader import load_world

RESULT_QOS = QoSProfile(depth=50, reliability=ReliabilityPolicy.RELIABLE)
STATE_QOS = QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE)
PTU_QOS = 20
"""Depth of the ``sensors/ptu`` subscriptions of the colour tracker and the pad-pose node."""
_DTYPES: dict[str, tuple[type[np.uint8] | type[np.uint16], int]] = {
    "rgb8": (np.uint8, 3),
    "mono16": (np.uint16, 1),
}


def image_array(msg: Image) -> NDArray[np.generic] | str:
    """The pixels of an ``rgb8`` / ``mono16`` image (rows x cols [x 3]), or why not."""
    if msg.encoding not in _DTYPES:
        return f"encoding {msg.encoding!r} not rgb8/mono16"
    scalar, channels = _DTYPES[msg.encoding]
    dtype = np.dtype(scalar)
    row = msg.width * channels * dtype.itemsize
    if msg.width == 0 or msg.height == 0 or msg.step < row or len(msg.data) < msg.step * msg.height:
        return f"{msg.width}x{msg.height} step {msg.step} with {len(msg.data)} bytes"
    raw = np.frombuffer(bytes(msg.data), dtype=np.uint8)[: msg.step * msg.height]
    rows = raw.reshape(msg.height, msg.step)[:, :row]
    wire = dtype.newbyteorder(">" if msg.is_bigendian else "<")
    pixels = np.ascontiguousarray(rows).view(wire).astype(scalar)  # native byte order
    return pixels.reshape(msg.height, msg.width, channels) if channels > 1 else pixels


class SaliencyNode(Node):
    """Algorithm 4 on the agent's image pairs; the map on topics and in a GeoJSON file."""

    def __init__(self, **kwargs: Any) -> None:
        super().__init__("saliency", **kwargs)
        world_name = str(self.declare_parameter("world", "revinge").value)
        detector = str(self.declare_parameter("detector", Detector.HOG_PEOPLE.value).value)
        path = str(self.declare_parameter("geojson_path", "").value)
        self._tolerance = float(self.declare_parameter("pair_tolerance_s", 0.02).value)
        gated = bool(self.declare_parameter("gated", True).value)
        try:
            kind = Detector(detector)
        except ValueError as exc:
            raise ConfigError(
                f"detector {detector!r}: one of {[d.value for d in Detector]}"
            ) from exc
        self._world = load_world(world_name)
        origin = self._world.origin
        self._frame = WorldFrame(origin.latitude, origin.longitude, origin.altitude)
        ground = Ground(height=self._world.terrain.height, max_slope=1.0)
        self.pipeline = SaliencyPipeline(ground, PipelineConfig(classifier=ClassifierParams(kind)))
        self._geojson = Path(path) if path else None
        self._info: dict[str, Intrinsics | None] = {"color": None, "thermal": None}
        self._color: tuple[float, Image] | None = None
        self._thermal: tuple[float, Image] | None = None
        self._last_published = -1e9
        self._nav = NavHistory()
        self._ptu = PtuHistory()
        self.results: dict[PairStatus | str, int] = {}
        self._result_pub = self.create_publisher(String, "~/pair_result", RESULT_QOS)
        self._map_pub = self.create_publisher(String, "~/map", LATCHED)
        self._marker_pub = self.create_publisher(MarkerArray, "~/markers", LATCHED)
        self.create_subscription(HelicopterState, "helicopter_state", self._on_state, STATE_QOS)
        self.create_subscription(CameraState, "camera_state", self._on_ptu, STATE_QOS)
        self.gate = ImageGate(self, ImageProcessing.SALIENCY, self._subscribe, self._stopped, gated)

    @property
    def engaged(self) -> bool:
        """Whether the node subscribes the images (the PPC engaged the pipeline, or not gated)."""
        return self.gate.engaged

    def _subscribe(self) -> list[Subscription]:
        subs = [
            self.create_subscription(
                CameraInfo,
                f"camera/{cam}/camera_info",
                functools.partial(self._on_info, cam),
                qos_profile_sensor_data,
            )
            for cam in ("color", "thermal")
        ]
        for cam, callback in (("color", self._on_color), ("thermal", self._on_thermal)):
            subs.append(
                self.create_subscription(
                    Image, f"camera/{cam}/image_raw", callback, qos_profile_sensor_data
                )
            )
        return subs

    def _stopped(self) -> None:
        self._color = self._thermal = None
        self._publish_map()

    def _on_info(self, cam: str, msg: CameraInfo) -> None:
        self._info[cam] = Intrinsics.from_k(int(msg.width), int(msg.height), list(msg.k))

    def _on_state(self, msg: HelicopterState) -> None:
        self._nav.add(stamp_s(msg.header.stamp), NavPose.of_state(self._frame, msg))

    def _on_ptu(self, msg: CameraState) -> None:
        self._ptu.add(stamp_s(msg.header.stamp), float(msg.pan), float(msg.tilt))

    def _on_color(self, msg: Image) -> None:
        if self.engaged:  # an image the executor took before the stop is dropped
            self._color = (stamp_s(msg.header.stamp), msg)
            self._try_pair()

    def _on_thermal(self, msg: Image) -> None:
        if self.engaged:
            self._thermal = (stamp_s(msg.header.stamp), msg)
            self._try_pair()

    def _try_pair(self) -> None:
        """Process the latest thermal image once a colour image of its stamp is there.

        The two topics are not ordered against each other, so either may complete a pair.
        """
        if self._thermal is None or self._color is None:
            return
        if abs(self._color[0] - self._thermal[0]) > self._tolerance:
            return
        time, msg = self._thermal
        self._thermal = None
        result = self._process(time, msg)
        key: PairStatus | str = result.status if isinstance(result, PairResult) else result[0]
        self.results[key] = self.results.get(key, 0) + 1
        if isinstance(result, PairResult):
            report = {
                "time": time,
                "status": result.status.value,
                "reason": result.reason,
                "warm_regions": result.warm_regions,
                "candidates": result.candidates,
                "corresponded": result.corresponded,
                "positives": result.positives,
                "added": result.added,
                "merged": result.merged,
            }
            if result.positives or time - self._last_published >= 1.0:
                self._last_published = time
                self._publish_map()
        else:
            report = {"time": time, "status": result[0], "reason": result[1]}
        self._result_pub.publish(String(data=json.dumps(report)))

    def _process(self, time: float, thermal: Image) -> PairResult | tuple[str, str]:
        """The core's result, or (status, reason) for what the node could not hand over."""
        assert self._color is not None  # _try_pair
        nav, ptu = self._nav.at(time), self._ptu.at(time)
        if nav is None or ptu is None:
            missing = "helicopter_state" if nav is None else "camera_state"
            return (
                "no_state",
                f"no {missing} within {MAX_GAP_S} s of the image's time {time:.3f} s",
            )
        for msg in (self._color[1], thermal):
            if msg.encoding not in _DTYPES:
                return (PairStatus.BAD_ENCODING.value, f"encoding {msg.encoding!r}: rgb8/mono16")
        color_px, thermal_px = image_array(self._color[1]), image_array(thermal)
        if isinstance(color_px, str) or isinstance(thermal_px, str):
            reason = color_px if isinstance(color_px, str) else str(thermal_px)
            return (PairStatus.BAD_SIZE.value, reason)
        pair = FramePair(
            time,
            CameraImage(color_px, self._color[1].encoding, self._info["color"]),
            CameraImage(thermal_px, thermal.encoding, self._info["thermal"]),
            nav,
            *ptu,
        )
        return self.pipeline.process(pair)

    def destroy_node(self) -> None:
        """Publish and write the final map, then destroy the node."""
        if len(self.pipeline.map):
            self._publish_map()
        super().destroy_node()

    def _publish_map(self) -> None:
        text = dumps_geojson(self.pipeline.map, self._world.origin)
        self._map_pub.publish(String(data=text))
        if self._geojson is not None:
            tmp = self._geojson.with_suffix(".tmp")
            tmp.write_text(text, encoding="utf-8")
            tmp.replace(self._geojson)
        markers = MarkerArray()
        for loc in self.pipeline.map.locations:
            marker = Marker()
            marker.header.frame_id = "map"
            marker.ns, marker.id = "saliency", loc.ident
            marker.type, marker.action = Marker.SPHERE, Marker.ADD
            marker.pose.position.x, marker.pose.position.y = loc.east, loc.north
            marker.pose.position.z = loc.up
            marker.pose.orientation.w = 1.0
            marker.scale.x = marker.scale.y = marker.scale.z = 1.5
            confirmed = loc.confirmed(self.pipeline.map.params)
            marker.color.r, marker.color.g = (0.0, 1.0) if confirmed else (1.0, 0.6)
            marker.color.a = max(0.3, min(1.0, loc.p_body))
            markers.markers.append(marker)
        self._marker_pub.publish(markers)


def main(argv: Sequence[str] | None = None) -> int:
    """Run ``hdrc3-saliency``; accepts ``--ros-args`` (e.g. ``-r __ns:=/uav0``)."""
    apply_dds_defaults()
    try:
        return run_node(
            lambda context: SaliencyNode(context=context), sys.argv if argv is None else argv
        )
    except Hdrc3Error as exc:
        print(f"hdrc3-saliency: error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
