from __future__ import annotations

import itertools
import json
import math

import numpy as np
import pytest
from foxglove.messages import CompressedImage, FrameTransforms, Log, LogLevel, SceneUpdate
from sensor_msgs.msg import Image
from std_msgs.msg import String

from hdrc3.live.converters import (
    AircraftConverter,
    EventConverter,
    GisConverter,
    HcsmConverter,
    ImageConverter,
    PlannedPathConverter,
    RateLimiter,
    SaliencyConverter,
    SkipReason,
    TrackConverter,
    TransformConverter,
    TstConverter,
    WorldConverter,
)
from hdrc3.live.wire import WireSchema, decode
from hdrc3_hcsm.trace import FiredTransition, TraceRecord
from hdrc3_interfaces.msg import (
    ExecutionFlag,
    GisState,
    GisZone,
    MonitorViolation,
    Path,
    PathSegment,
    PlatformEvent,
    RecoveryEvent,
    TruthState,
    TstNodeStatus,
)
from hdrc3_perception.saliency_map import Location, SaliencyMap, dumps_geojson
from sim.world_loader import load_world

WORLD = load_world("revinge")
MS = 1_000_000
SCENE = WireSchema.well_known(SceneUpdate)


def truth(x: float = 1.0, y: float = 2.0, z: float = 3.0, heading: float = 0.0) -> TruthState:
    msg = TruthState()
    msg.position_enu = [x, y, z]
    msg.heading = heading
    return msg


@pytest.mark.parametrize(
    ("period_ms", "times_ms", "passed"),
    [
        (40, range(0, 1000, 20), 25),  # 50 Hz in, 25 Hz out
        (40, range(0, 1000, 40), 25),
        (40, range(0, 1000, 10), 25),
        (40, [0, 10, 500, 510, 540], 3),  # a pause is not caught up in a burst
        (500, range(0, 1000, 20), 2),
    ],
)
def test_rate_limiter(period_ms, times_ms, passed):
    limit = RateLimiter(period_ms * MS)
    assert sum(limit.due("a", t * MS) for t in times_ms) == passed


def test_rate_limiter_keys_are_independent():
    limit = RateLimiter(40 * MS)
    assert limit.due("uav0", 0) and limit.due("uav1", 0)
    assert not limit.due("uav0", 10 * MS)


def test_transforms_at_25_hz_per_agent_with_the_pose():
    conv = TransformConverter(WORLD)
    out = [o for t in range(0, 1000, 20) for o in conv.convert("s", "uav0", truth(), t * MS)]
    assert len(out) == 25 and {o.key for o in out} == {"uav0"}
    msg = decode(WireSchema.well_known(FrameTransforms), out[0].data)
    (tf,) = msg.transforms
    assert (tf.parent_frame_id, tf.child_frame_id) == ("world", "uav0")
    assert (tf.translation.x, tf.translation.y, tf.translation.z) == (1.0, 2.0, 3.0)
    assert tf.rotation.z == pytest.approx(math.sqrt(0.5))  # heading north: yaw +90 deg in ENU


def test_transform_of_a_non_finite_state_is_dropped():
    assert TransformConverter(WORLD).convert("s", "uav0", truth(x=math.nan), 0) == []


def test_aircraft_model_once_per_agent_in_its_own_frame():
    conv = AircraftConverter(WORLD)
    first = conv.convert("s", "uav0", truth(), 0)
    assert conv.convert("s", "uav0", truth(), 1) == []
    assert len(conv.convert("s", "uav1", truth(), 2)) == 1
    (entity,) = decode(SCENE, first[0].data).entities
    assert (entity.id, entity.frame_id, entity.frame_locked) == ("aircraft/uav0", "uav0", True)


def test_track_keeps_points_apart_and_refreshes_twice_a_second():
    conv = TrackConverter(WORLD)
    out = []
    for i in range(100):  # 2 s at 50 Hz, 0.2 m per sample
        out += conv.convert("s", "uav0", truth(x=0.2 * i), i * 20 * MS)
    assert len(out) == 4
    (entity,) = decode(SCENE, out[-1].data).entities
    xs = [p.x for p in entity.lines[0].points]
    assert entity.id == "track/uav0" and entity.frame_id == "world"
    assert all(b - a >= 0.5 for a, b in itertools.pairwise(xs))


def segment(start, end) -> PathSegment:
    seg = PathSegment()
    seg.start_point.x, seg.start_point.y, seg.start_point.z = start
    seg.end_point.x, seg.end_point.y, seg.end_point.z = end
    d = [e - s for s, e in zip(start, end, strict=True)]
    seg.start_direction.x, seg.start_direction.y, seg.start_direction.z = d
    seg.end_direction.x, seg.end_direction.y, seg.end_direction.z = d
    seg.target_velocity = 5.0
    return seg


def test_planned_path_is_sampled_through_its_segments():
    path = Path(segments=[segment((0, 0, 10), (10, 0, 10)), segment((10, 0, 10), (10, 20, 10))])
    (out,) = PlannedPathConverter(WORLD).convert("planned_path", "uav0", path, 0)
    (entity,) = decode(SCENE, out.data).entities
    pts = [(p.x, p.y, p.z) for p in entity.lines[0].points]
    assert entity.id == "planned_path/uav0"
    assert pts[0] == pytest.approx((0, 0, 10)) and pts[-1] == pytest.approx((10, 20, 10))
    assert (10.0, 0.0, 10.0) in [tuple(round(c, 6) for c in p) for p in pts]
    assert len(pts) == 2 * 12 + 1


@pytest.mark.parametrize(
    ("segments", "result"),
    [
        ([], "deleted"),
        ([segment((0, 0, 10), (0, 0, 10))], "nothing"),  # zero length: not a segment
    ],
)
def test_planned_path_without_a_drawable_curve(segments, result):
    out = PlannedPathConverter(WORLD).convert("planned_path", "uav0", Path(segments=segments), 0)
    if result == "nothing":
        assert out == []
    else:
        assert [d.id for d in decode(SCENE, out[0].data).deletions] == ["planned_path/uav0"]


def zone(name: str, floor: float = 0.0, ceiling: float = 50.0, ring=None) -> GisZone:
    east, north = zip(*(ring or [(0, 0), (10, 0), (10, 10)]), strict=True)
    return GisZone(name=name, polygon_east=east, polygon_north=north, floor=floor, ceiling=ceiling)


def test_gis_zones_of_every_agent_replace_the_previous_ones():
    conv = GisConverter(WORLD)
    conv.convert("g", "uav0", GisState(no_fly_zones=[zone("a")]), 0)
    state = GisState(
        no_fly_zones=[zone("b"), zone("bad", 60.0, 50.0), zone("nan", ring=[(0, 0), (1, 0)])],
        obstacles=[zone("crane", ceiling=math.nan), zone("mast")],
    )
    (out,) = conv.convert("g", "uav1", state, 1)
    scene = decode(SCENE, out.data)
    assert len(scene.deletions) == 1  # everything shown before
    assert sorted(e.id for e in scene.entities) == [
        "gis/uav0/no_fly_zone/a",
        "gis/uav1/no_fly_zone/b",
        "gis/uav1/obstacle/mast",
    ]


def tst_status(node_id: str, state: str) -> TstNodeStatus:
    return TstNodeStatus(mission="m", agent="uav0", node_id=node_id, kind="fly-to", state=state)


def test_tst_table_keeps_the_latest_state_of_every_node():
    conv = TstConverter(WORLD)
    conv.convert("tst_status", "uav0", tst_status("n1", "running"), 0)
    conv.convert("tst_status", "uav0", tst_status("n0", "running"), 0)
    (out,) = conv.convert("tst_status", "uav0", tst_status("n1", "succeeded"), 0)
    table = json.loads(out.data)
    assert table["changed"]["state"] == "succeeded"
    assert [(n["node_id"], n["state"]) for n in table["nodes"]] == [
        ("n0", "running"),
        ("n1", "succeeded"),
    ]


def test_tst_times_not_yet_known_are_null_not_nan():
    msg = tst_status("n1", "running")
    msg.start, msg.end = math.nan, math.nan  # waiting to begin

    def refuse(constant: str) -> None:
        raise AssertionError(f"{constant} is not JSON")

    (out,) = TstConverter(WORLD).convert("tst_status", "uav0", msg, 0)
    row = json.loads(out.data, parse_constant=refuse)["changed"]
    assert (row["start"], row["end"]) == (None, None)


def test_hcsm_active_states_from_a_trace_record():
    record = TraceRecord(
        "PFC", 3, 1, 12.5, "TakeOff-EV", "DRC",
        (FiredTransition("T1", "ModeSwitch", "Hover", "TakeOff", ()),), (),
        ("Root", "ModeSwitch.TakeOff"),
    )  # fmt: skip
    conv = HcsmConverter(WORLD)
    (out,) = conv.convert("hcsm/trace", "uav0", String(data=record.to_json()), 0)
    payload = json.loads(out.data)
    assert payload["active_states"] == ["Root", "ModeSwitch.TakeOff"]
    assert payload["transitions"] == ["Hover -> TakeOff"] and out.key == "uav0/PFC"
    assert conv.convert("hcsm/trace", "uav0", String(data="{not json"), 0) == []
    assert conv.skipped == {SkipReason.MALFORMED_TRACE: 1}


@pytest.mark.parametrize(
    ("kind", "level", "text"),
    [
        (PlatformEvent.KIND_FINISHED, LogLevel.Info, "fcl_takeoff #7 finished"),
        (PlatformEvent.KIND_FAILED, LogLevel.Error, "fcl_takeoff #7 failed: no"),
        (PlatformEvent.KIND_CANCELLED, LogLevel.Warning, "fcl_takeoff #7 cancelled: no"),
        (99, LogLevel.Info, "fcl_takeoff #7 kind 99: no"),
    ],
)
def test_platform_events_as_log_lines(kind, level, text):
    event = PlatformEvent(command_id=7, command="fcl_takeoff", kind=kind)
    event.reason = "" if kind == PlatformEvent.KIND_FINISHED else "no"
    (out,) = EventConverter(WORLD).convert("platform_events", "uav0", event, 0)
    line = decode(WireSchema.well_known(Log), out.data)
    assert line.level == level.value and line.message.endswith(text)
    assert line.name == "uav0/platform_server"


def test_execution_flags_as_log_lines():
    flag = ExecutionFlag(mission="m", agent="uav0", node_id="n3", action="fly-to", executing=True)
    (out,) = EventConverter(WORLD).convert("execution_flags", "uav0", flag, 0)
    assert decode(WireSchema.well_known(Log), out.data).message.endswith(
        "m: uav0/n3 fly-to executing"
    )


def test_world_converter_has_no_sources():
    conv = WorldConverter(WORLD)
    assert conv.convert("x", "uav0", truth(), 0) == []
    assert [o.key for o in conv.start(0)] == ["world"]


def test_rate_limiter_ready_schedules_nothing():
    limit = RateLimiter(40 * MS)
    assert limit.ready("a", 0) and limit.ready("a", 0)
    assert limit.due("a", 0)
    assert not limit.ready("a", 10 * MS) and limit.ready("a", 40 * MS)


def violation(kind: int, **fields) -> MonitorViolation:
    msg = MonitorViolation(agent="uav0", monitor_id="speed_limit", formula="always v < 12")
    msg.kind = kind
    for name, value in fields.items():
        setattr(msg, name, value)
    return msg


@pytest.mark.parametrize(
    ("msg", "level", "text"),
    [
        (violation(MonitorViolation.KIND_VIOLATION), LogLevel.Error,
         "monitor speed_limit violation: always v < 12"),
        (violation(MonitorViolation.KIND_VIOLATION, node_id="n4", action="fly-to",
                   argument_names=["x"], argument_values=["depot"], recovery="avoid",
                   emergency_brake=True),
         LogLevel.Error, "violation: always v < 12 [x=depot] (node n4 fly-to); recovery avoid; "
                         "emergency brake"),
        (violation(MonitorViolation.KIND_STALE_DATA, reason="no speed for 2 s"), LogLevel.Warning,
         "monitor speed_limit stale data: always v < 12: no speed for 2 s"),
        (violation(MonitorViolation.KIND_REFUSED), LogLevel.Warning, "refused: always v < 12"),
        (violation(42), LogLevel.Warning, "monitor speed_limit kind 42"),
    ],
)  # fmt: skip
def test_monitor_violations_as_log_lines(msg, level, text):
    (out,) = EventConverter(WORLD).convert("monitor_violations", "uav0", msg, 0)
    line = decode(WireSchema.well_known(Log), out.data)
    assert line.level == level.value and text in line.message
    assert line.name == "uav0/execution_monitor"


def recovery(step: int, **fields) -> RecoveryEvent:
    msg = RecoveryEvent(mission="m", agent="uav1", node_id="g2", monitor_id="wind", attempt=1)
    msg.step = step
    for name, value in fields.items():
        setattr(msg, name, value)
    return msg


@pytest.mark.parametrize(
    ("msg", "level", "text"),
    [
        (recovery(RecoveryEvent.STEP_SUSPENDED), LogLevel.Info,
         "m: g2 suspended (wind, attempt 1)"),
        (recovery(RecoveryEvent.STEP_OPERATOR_APPLIED, recovery="lower-wind",
                  changes=["(wind-ok) false"]),
         LogLevel.Info, "g2 operator applied (wind, attempt 1); operator lower-wind; "
                        "changed (wind-ok) false"),
        (recovery(RecoveryEvent.STEP_REPLANNED, plan=["fly-to uav1 a", "land uav1"]),
         LogLevel.Info, "replanned (wind, attempt 1); plan fly-to uav1 a / land uav1"),
        (recovery(RecoveryEvent.STEP_GAVE_UP, reason="no plan"), LogLevel.Error,
         "gave up (wind, attempt 1): no plan"),
        (recovery(99), LogLevel.Info, "m: g2 step 99"),
    ],
)  # fmt: skip
def test_recovery_steps_as_log_lines(msg, level, text):
    (out,) = EventConverter(WORLD).convert("recovery_events", "uav1", msg, 0)
    line = decode(WireSchema.well_known(Log), out.data)
    assert line.level == level.value and text in line.message
    assert line.name == "uav1/tst_recovery"


def camera_image(encoding: str = "rgb8", width: int = 8, height: int = 6) -> Image:
    channels = {"rgb8": 3, "mono16": 2}.get(encoding, 1)
    data = bytes(np.arange(width * height * channels, dtype=np.uint32).astype(np.uint8))
    msg = Image(height=height, width=width, encoding=encoding, step=width * channels, data=data)
    msg.header.frame_id = "uav0/color_optical"
    return msg


def test_images_are_jpeg_at_5_hz_per_agent_in_the_camera_frame():
    conv = ImageConverter(WORLD)
    out = []
    for t in range(0, 1000, 40):  # 25 Hz camera
        for agent in ("uav0", "uav1"):
            if conv.wants("camera/color/image_raw", agent, t * MS):
                out += conv.convert("camera/color/image_raw", agent, camera_image(), t * MS)
    assert [o.key for o in out].count("uav0") == 5 and len(out) == 10
    image = decode(WireSchema.well_known(CompressedImage), out[0].data)
    assert (image.format, image.frame_id) == ("jpeg", "uav0/color_optical")
    assert image.data[:2] == b"\xff\xd8"


def test_an_image_without_frame_gets_the_cameras_optical_frame():
    msg = camera_image("mono16")
    msg.header.frame_id = ""
    (out,) = ImageConverter(WORLD).convert("camera/thermal/image_raw", "uav2", msg, 0)
    image = decode(WireSchema.well_known(CompressedImage), out.data)
    assert image.frame_id == "uav2/thermal_optical"


@pytest.mark.parametrize(
    ("msg", "reason"),
    [
        (camera_image("yuv422"), SkipReason.UNKNOWN_ENCODING),
        (camera_image(width=0), SkipReason.BAD_IMAGE_SIZE),
        (Image(encoding="rgb8", width=4, height=4, step=12, data=b"short"),
         SkipReason.BAD_IMAGE_SIZE),
    ],
)  # fmt: skip
def test_images_that_cannot_be_shown_are_skipped_and_counted(msg, reason):
    conv = ImageConverter(WORLD)
    assert conv.convert("camera/color/image_raw", "uav0", msg, 0) == []
    assert conv.skipped == {reason: 1}


def saliency_map(*locations: tuple[float, float, float, int, int]) -> String:
    smap = SaliencyMap()
    smap.absorb([Location(i, *loc, first_seen=1.0) for i, loc in enumerate(locations)])
    return String(data=dumps_geojson(smap, WORLD.origin))


def test_saliency_map_as_spheres_in_the_world_frame_coloured_by_certainty():
    msg = saliency_map((10.0, 20.0, 1.0, 4, 4), (-5.0, 3.0, 0.5, 4, 1))
    (out,) = SaliencyConverter(WORLD).convert("saliency/map", "uav0", msg, 0)
    (entity,) = decode(SCENE, out.data).entities
    assert (entity.id, entity.frame_id) == ("saliency/uav0", "world")
    sure, unsure = entity.spheres
    assert (sure.pose.position.x, sure.pose.position.y) == pytest.approx((10.0, 20.0), abs=1e-6)
    assert sure.pose.position.z == pytest.approx(2.0, abs=1e-6)  # the sphere sits on the ground
    assert sure.color.g > sure.color.r  # confirmed: green
    assert unsure.color.r == 1.0 and unsure.color.a < sure.color.a  # unlikely: red, faint
    assert [t.text for t in entity.texts] == ["1.00 (4/4)", "0.25 (1/4)"]


def test_an_empty_saliency_map_deletes_the_agents_entity():
    (out,) = SaliencyConverter(WORLD).convert("saliency/map", "uav1", saliency_map(), 0)
    assert [d.id for d in decode(SCENE, out.data).deletions] == ["saliency/uav1"]


@pytest.mark.parametrize(
    "text",
    [
        "{not json",
        "[]",
        '{"type": "FeatureCollection"}',
        '{"type": "FeatureCollection", "features": [{"properties": {"east": 1}}]}',
        '{"type": "FeatureCollection", "features": [7]}',
        "[" * 100_000,  # nesting deeper than the JSON decoder's recursion
    ],
)
def test_malformed_saliency_maps_are_skipped_and_counted(text):
    conv = SaliencyConverter(WORLD)
    assert conv.convert("saliency/map", "uav0", String(data=text), 0) == []
    assert conv.skipped == {SkipReason.MALFORMED_MAP: 1}


def test_non_finite_poses_are_counted():
    conv = TrackConverter(WORLD)
    conv.convert("s", "uav0", truth(x=math.nan), 0)
    assert conv.skipped == {SkipReason.NON_FINITE: 1}
