import pytest

from hdrc3_dyknow.policy import LateHandling, MissingHandling, Policy
from hdrc3_dyknow.sample import FeatureTerm
from hdrc3_dyknow.semantic_spec import (
    FunctionSource,
    ObjectDecl,
    SpecError,
    SpecSyntaxError,
    StreamDecl,
    TopicSource,
    parse_spec,
)

SPEC = """# two helicopters
object uav0, uav1 : RMAX;   // comment style two
stream uav0/position contains Position(uav0)
    from topic "/uav0/helicopter_state" field position with period 40 ms;
stream uav1/xydist/uav0 contains XYDist[uav1, uav0]
    = xy_dist(uav1/position, uav0/position)
    with period 100 ms, max_delay 200 ms, missing extrapolate, late keep,
         change_only 0.5, unordered;
stream "quoted label" contains on_ground;
"""


def test_parse_full_spec() -> None:
    spec = parse_spec(SPEC)
    assert spec.objects == (ObjectDecl(("uav0", "uav1"), "RMAX"),)
    assert spec.streams == (
        StreamDecl(
            "uav0/position",
            FeatureTerm("Position", ("uav0",)),
            TopicSource("/uav0/helicopter_state", "position"),
            Policy(sample_period_ms=40),
        ),
        StreamDecl(
            "uav1/xydist/uav0",
            FeatureTerm("XYDist", ("uav1", "uav0")),
            FunctionSource("xy_dist", ("uav1/position", "uav0/position")),
            Policy(
                ordered=False,
                change_only=True,
                change_threshold=0.5,
                sample_period_ms=100,
                max_delay_ms=200,
                late=LateHandling.KEEP,
                missing=MissingHandling.EXTRAPOLATE,
            ),
        ),
        StreamDecl("quoted label", FeatureTerm("on_ground"), None, Policy()),
    )
    assert spec.streams[1].annotation == "XYDist[uav1, uav0]"
    assert (spec.streams[1].line, spec.streams[1].column) == (5, 1)


@pytest.mark.parametrize(
    ("text", "location", "message"),
    [
        ("object a : ;", "f.spec:1:12", "expected one of: NAME"),
        (
            "stream a contains X(y)",
            "f.spec:1:23",
            "end of input; expected one of: ';', '=', 'from', 'with'",
        ),
        (
            "stream a contains X(y) with max_delay 5 s;",
            "f.spec:1:41",
            "unexpected 's'; expected one of: 'ms'",
        ),
        ("stream a contains B with missing foo;", "f.spec:1:34", "unknown missing handling 'foo'"),
        ("stream a contains B with late never;", "f.spec:1:31", "unknown late handling 'never'"),
        (
            "\n  stream a contains X(y) with period -3 ms;",
            "f.spec:2:38",
            "unexpected character '-'",
        ),
        ('stream a contains X(y) from topic "/t" field;', "f.spec:1:45", "expected one of: NAME"),
    ],
)
def test_errors_carry_location_and_expectation(text: str, location: str, message: str) -> None:
    with pytest.raises(SpecError) as info:
        parse_spec(text, "f.spec")
    assert str(info.value).startswith(location + ":")
    assert message in str(info.value)


@pytest.mark.parametrize(
    ("text", "syntax"), [("object a : ;", True), ("stream a contains B with late x;", False)]
)
def test_syntax_errors_are_distinguished(text: str, syntax: bool) -> None:
    with pytest.raises(SpecError) as info:
        parse_spec(text)
    assert isinstance(info.value, SpecSyntaxError) is syntax


def test_empty_spec() -> None:
    assert parse_spec("# nothing\n").streams == ()
