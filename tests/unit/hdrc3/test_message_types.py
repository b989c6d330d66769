import pytest
from mcap_ros2._dynamic import generate_dynamic

from hdrc3.message_types import (
    SEPARATOR,
    DefinitionResolver,
    MessageTypeError,
    MessageTypeName,
    constant_names,
    field_types,
    message_class,
)
from hdrc3_interfaces.msg import MonitorViolation, PfcState


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("std_msgs/msg/String", MessageTypeName("std_msgs", "String")),
        ("std_msgs/String", MessageTypeName("std_msgs", "String")),
        (" hdrc3_interfaces/msg/Event ", MessageTypeName("hdrc3_interfaces", "Event")),
    ],
)
def test_parse_type_names(text: str, expected: MessageTypeName) -> None:
    assert MessageTypeName.parse(text) == expected


@pytest.mark.parametrize("text", ["", "String", "std_msgs/srv/String", "a/b/c/d", "1pkg/X"])
def test_malformed_type_names_are_rejected(text: str) -> None:
    with pytest.raises(MessageTypeError, match="not a message type name"):
        MessageTypeName.parse(text)


@pytest.mark.parametrize(
    ("msg_text", "package", "expected"),
    [
        ("int32 x\nstring<=5 s\nfloat64[3] v", "p", []),
        ("Header header", "p", [MessageTypeName("std_msgs", "Header")]),
        (
            "Point p  # comment\nq/Other[] others",
            "geo",
            [MessageTypeName("geo", "Point"), MessageTypeName("q", "Other")],
        ),
        ('uint8 A=1\nstring NAME="x"\n# Foo f', "p", []),
        (
            "Seg[<=4] segs\nbuiltin_interfaces/Time t",
            "p",
            [MessageTypeName("p", "Seg"), MessageTypeName("builtin_interfaces", "Time")],
        ),
    ],
)
def test_field_types(msg_text: str, package: str, expected: list[MessageTypeName]) -> None:
    assert field_types(msg_text, package) == expected


def test_message_class_resolves_generated_classes() -> None:
    from hdrc3_interfaces.msg import HelicopterState

    assert message_class("hdrc3_interfaces/msg/HelicopterState") is HelicopterState


def test_message_class_reports_missing_types() -> None:
    with pytest.raises(MessageTypeError, match="not installed"):
        message_class("no_such_pkg/msg/Thing")


@pytest.mark.parametrize(
    ("type_name", "nested"),
    [
        (
            "hdrc3_interfaces/msg/Path",
            [
                "std_msgs/Header",
                "hdrc3_interfaces/PathSegment",
                "geometry_msgs/Point",
                "geometry_msgs/Vector3",
                "builtin_interfaces/Time",
            ],
        ),
        ("std_msgs/msg/String", []),
    ],
)
def test_full_definition_lists_every_nested_type_once(type_name: str, nested: list[str]) -> None:
    text = DefinitionResolver().full_definition(type_name)
    found = [line.removeprefix("MSG: ") for line in text.splitlines() if line.startswith("MSG: ")]
    assert sorted(found) == sorted(nested)
    assert text.count(SEPARATOR) == len(nested)
    # An independent ros2msg parser accepts the text and knows the root type.
    assert type_name in generate_dynamic(type_name, text)


def test_missing_definition_names_the_search_path(tmp_path) -> None:
    resolver = DefinitionResolver(search_path=[tmp_path])
    with pytest.raises(MessageTypeError, match=str(tmp_path)):
        resolver.full_definition("std_msgs/msg/String")


@pytest.mark.parametrize(
    ("cls", "prefix", "some"),
    [
        (PfcState, "MODE_", {2: "ground idle", 7: "flyto"}),
        (MonitorViolation, "KIND_", {1: "violation", 2: "stale data", 3: "refused"}),
    ],
)
def test_constant_names_read_the_message_constants(
    cls: type, prefix: str, some: dict[int, str]
) -> None:
    names = constant_names(cls, prefix)
    assert names.items() >= some.items()
    assert all(name == name.lower() for name in names.values())
