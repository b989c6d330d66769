import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

from hdrc3_base.ros_env import (
    DISCOVERY_RANGE_VAR,
    PROFILES_VARS,
    apply_dds_defaults,
    discovery_profile,
)

FASTRTPS, FASTDDS = PROFILES_VARS
NS = {"p": "http://www.eprosima.com/XMLSchemas/fastRTPS_Profiles"}

CASES = {
    "nothing set": ({}, {DISCOVERY_RANGE_VAR: "LOCALHOST", FASTRTPS: discovery_profile()}),
    "the user's range": (
        {DISCOVERY_RANGE_VAR: "SUBNET"},
        {DISCOVERY_RANGE_VAR: "SUBNET", FASTRTPS: discovery_profile()},
    ),
    "the user's Fast DDS 2 profile": (
        {FASTRTPS: "/etc/mine.xml"},
        {DISCOVERY_RANGE_VAR: "LOCALHOST", FASTRTPS: "/etc/mine.xml"},
    ),
    "the user's Fast DDS 3 profile": (
        {FASTDDS: "/etc/mine.xml"},
        {DISCOVERY_RANGE_VAR: "LOCALHOST", FASTDDS: "/etc/mine.xml"},
    ),
    "an empty profile variable counts as unset": (
        {FASTRTPS: ""},
        {DISCOVERY_RANGE_VAR: "LOCALHOST", FASTRTPS: discovery_profile()},
    ),
}


@pytest.mark.parametrize(("given", "expected"), CASES.values(), ids=CASES)
def test_defaults_fill_only_what_the_user_left_unset(
    given: dict[str, str], expected: dict[str, str]
) -> None:
    env = dict(given)
    assert apply_dds_defaults(env) == expected[DISCOVERY_RANGE_VAR]
    assert env == expected


def test_the_packaged_profile_is_the_default_participant_with_quick_announcements() -> None:
    root = ET.parse(Path(discovery_profile())).getroot()
    participant = root.find("p:participant", NS)
    assert participant is not None and participant.get("is_default_profile") == "true"
    config = participant.find("p:rtps/p:builtin/p:discovery_config", NS)
    assert config is not None

    def seconds(path: str) -> float:
        node = config.find(path, NS)
        assert node is not None
        sec, nanosec = (float(node.findtext(f"p:{unit}", "0", NS)) for unit in ("sec", "nanosec"))
        return sec + nanosec * 1e-9

    assert seconds("p:leaseAnnouncement") == pytest.approx(0.5)
    assert seconds("p:leaseDuration") == pytest.approx(20.0)
    assert seconds("p:initialAnnouncements/p:period") == pytest.approx(0.05)
