from __future__ import annotations

from pathlib import Path

import pytest

from hdrc3_tst.check import CheckStatus, load_file, load_text, tree_lines
from hdrc3_tst.errors import TstError
from hdrc3_tst.model import NodeKind, NodeRef
from hdrc3_tst.network import FixStatus
from hdrc3_tst.worlds import WorldCache

EXAMPLES = Path(__file__).resolve().parents[3] / "examples" / "tst"
HEAD = "world revinge\nagents uav0, uav1\npoint Dest = town_square at 30\n"


def ok(text: str):  # type: ignore[no-untyped-def]
    result = load_text(HEAD + text, "t.tst")
    assert result.status is CheckStatus.OK, [str(d) for d in result.diagnostics]
    assert result.tst is not None
    return result.tst


def test_example_6_1_resolves_with_agents_areas_and_windows() -> None:
    result = load_file(EXAMPLES / "example_6_1.tst")
    assert result.status is CheckStatus.OK and result.tst is not None
    tst = result.tst
    assert [n.node_id for _, n in tst.tree.walk()] == ["tau0", "tau1", "tau2", "tau3", "tau4"]
    assert [tst.agent_of(n) for n in ("tau0", "tau1", "tau2", "tau3", "tau4")] == [
        "uav0", "uav0", "uav0", "uav1", "uav0",
    ]  # fmt: skip
    assert tst.ref("tau3") == NodeRef("uav1", "tau3")
    assert tst.tree.node("tau1").kind is NodeKind.CONCURRENT
    assert tst.tree.node("tau2").parent == NodeRef("", "tau1")
    area = tst.network.values[tst.variable("tau2", "area")]
    assert area == "AreaA" and tst.places["AreaA"].coords[0] == (-280.0, -40.0)
    assert tst.places["Dest4"].coords == ((105.0, 45.0, 40.0),)  # town_square of revinge
    assert str(tst.network.window(tst.variable("tau4", "TE"))) == "(0, 1200]"


def test_structure_adds_talf_semantics_and_durations() -> None:
    tst = ok(
        "m(P, TS, TE) = with A, B, C, D sequence\n"
        "  a(A, B) = hover(A, B, 10);\n"
        "  b(C, D) = wait(C, D, 5)\n"
        "where P = uav0 and TS = 0 and TE <= 30 and C - B >= 3\n"
    )
    window = {v: str(tst.network.window(tst.variable(n, p))) for v, n, p in
              (("A", "a", "TS"), ("C", "b", "TS"), ("D", "b", "TE"))}  # fmt: skip
    assert window == {"A": "[0, 12]", "C": "[13, 25]", "D": "[18, 30]"}


@pytest.mark.parametrize(
    ("text", "code", "where", "message"),
    [
        ("m(TS, TE) = jump(TS, TE)", "E110", "4:13", "unknown action type 'jump'"),
        ("m(TS, TE) = fly-to(TS, TE, 3, Nowhere)", "E102", "4:31", "unknown point 'Nowhere'"),
        ("m(TS, TE) = fly-to(TS, TE, 3)", "E111", "4:13", "fly-to takes (TS, TE, speed, destination)"),  # noqa: E501
        ("m(TS, TE) = fly-to(TS, TE, Dest, Dest)", "E106", "4:28", "is a speed; Dest is a point"),
        ("m(TS, TE) = fly-to(TS, TE, 3, 4)", "E106", "4:31", "is a point, not a number"),
        ("m(TS, TE) = wait(TS, TE, 3) where X < 3", "E101", "4:35", "unknown name 'X'"),
        ("m(P, TS, TE) = wait(TS, TE, 3) where P = uav7", "E101", "4:42", "unknown name 'uav7'"),
        ("m(TS, TE) = wait(TS, TE, 3) where cons_x", "E120", "4:35", "unknown constraint set 'cons_x'"),  # noqa: E501
        ("m(TS) = wait(TS, TS, 3)", "E107", "4:1", "(TS, TE) or (P, TS, TE)"),
        ("m(TS, TE) = concurrent a(TS, TE) = land(TS, TE); a(TS, TE) = land(TS, TE)", "E105", "4:50", "used twice"),  # noqa: E501
        ("m(TS, TE) = call nothing(TS, TE)", "E112", "4:18", "unknown TST 'nothing'"),
        ("lib(TS, TE) = call lib(TS, TE)\nm(TS, TE) = call lib(TS, TE)", "E113", "4:20", "recursive call"),  # noqa: E501
        ("m(TS, TE) = wait(TS, TE, 3) where TS * 2 <= 3", "E001", "4:38", "unexpected '*'"),
        ("m(TS, TE) = with S wait(TS, TE, S) where 2 * TS - TE <= 3", "E122", "4:54", "difference"),
        ("m(P, TS, TE) = wait(TS, TE, 3) where P <= uav0", "E121", "4:40", "only take = and !="),
        ("m(TS, TE) = wait(TS, TE, 3)\nn(TS, TE) = land(TS, TE)", "E131", "5:1", "neither the mission"),  # noqa: E501
        ("area A = polygon((0, 0), (1, 1), (0, 1), (1, 0))\nm(TS, TE) = land(TS, TE)", "E103", "4:6", "not a simple polygon"),  # noqa: E501
        ("area A = polygon((0, 0), (900, 0), (0, 900))\nm(TS, TE) = land(TS, TE)", "E103", "4:6", "leaves the world"),  # noqa: E501
        ("point Q = nowhere at 3\nm(TS, TE) = land(TS, TE)", "E102", "4:7", "unknown place 'nowhere'"),  # noqa: E501
        ("m(TS, TE) = with S sequence a(TS, TE) = fly-to(TS, TE, S, Dest); b(TS, TE) = wait(TS, TE, S)", "E106", "4:91", "S is a speed, used here as a duration"),  # noqa: E501
        ("m(TS, TE) = foreach X where agent(X) do conc s(U, V) = wait(U, V, 1) where X < 3", "E106", "4:78", "X has no type"),  # noqa: E501
        ("m(TS, TE) = foreach X where agent(X) do conc s(U, V) = jump(U, V)", "E110", "4:56", "unknown action type"),  # noqa: E501
    ],
)  # fmt: skip
def test_bad_input_is_named_with_its_position(
    text: str, code: str, where: str, message: str
) -> None:
    result = load_text(HEAD + text, "t.tst")
    assert result.status in (CheckStatus.INVALID, CheckStatus.SYNTAX_ERROR)
    diag = result.diagnostics[0]
    assert (diag.code, f"{diag.pos.line}:{diag.pos.column}") == (code, where), str(diag)
    assert message in diag.message
    assert str(diag).startswith(f"t.tst:{where}: error {code}: ")


def test_an_unknown_world_is_reported() -> None:
    result = load_text("world atlantis\nm(TS, TE) = land(TS, TE)", "w.tst")
    assert result.status is CheckStatus.INVALID
    assert result.diagnostics[0].code == "E100" and "atlantis" in result.diagnostics[0].message


def test_inconsistent_constraints_are_rejected_with_the_conflicting_set() -> None:
    result = load_text(
        HEAD
        + "m(TS, TE) = with A, B sequence\n  a(A, B) = hover(A, B, 100)\nwhere TE - TS <= 60\n",
        "c.tst",
    )
    assert result.status is CheckStatus.INCONSISTENT
    message = result.diagnostics[0].message
    assert "c.tst:6:15: TE - TS <= 60" in message
    assert "a: TE - TS = duration 100 s" in message


def test_setting_parameters_updates_the_windows_or_is_refused() -> None:
    tst = ok(
        "m(P, TS, TE) = with A, B, C, D sequence\n"
        "  a(A, B) = fly-to(A, B, S1, Dest);\n"
        "  b(C, D) = hover(C, D, 10)\n"
        "where P = uav0 and TS = 0 and TE <= 100\n"
    )
    assert tst.set("a", "TE", 40.0).status is FixStatus.OK
    assert str(tst.network.window(tst.variable("b", "TS"))) == "[40, 90]"
    refused = tst.set("b", "TE", 45.0)
    assert refused.status is FixStatus.INCONSISTENT
    assert any("TE - TS = duration 10 s" in c for c in refused.conflict)
    assert str(tst.network.window(tst.variable("b", "TS"))) == "[40, 90]"
    assert tst.set("a", "speed", 20.0).status is FixStatus.INCONSISTENT  # RMAX envelope
    assert tst.set("a", "speed", 5.0).status is FixStatus.OK
    assert tst.network.values[tst.variable("a", "speed")] == 5.0
    assert tst.set("a", "P", "uav1").status is FixStatus.INCONSISTENT
    assert tst.set("a", "P", "uav9").status is FixStatus.BAD_VALUE
    assert tst.set("a", "TS", "uav0").status is FixStatus.BAD_VALUE
    assert tst.set("a", "colour", 1.0).status is FixStatus.UNKNOWN_VARIABLE
    assert tst.set("zz", "TS", 1.0).status is FixStatus.UNKNOWN_VARIABLE
    with pytest.raises(TstError):
        tst.variable("a", "colour")


def test_calls_are_instantiated_under_the_call_node() -> None:
    tst = ok(
        "hop(TS, TE) = with S fly-to(TS, TE, S, Dest) where S <= 4\n"
        "m(TS, TE) = with A, B sequence go(A, B) = call hop(A, B); again(A, B) = call hop(A, B)\n"
    )
    assert [n.node_id for _, n in tst.tree.walk()] == ["m", "go", "go/hop", "again", "again/hop"]
    assert tst.variable("go/hop", "speed") != tst.variable("again/hop", "speed")
    assert tst.set("go/hop", "speed", 5.0).status is FixStatus.INCONSISTENT


def test_a_goal_node_expands_into_a_sequence() -> None:
    tst = ok("m(TS, TE) = with A, B concurrent g(A, B) = goal delivered(box1, Dest)\n")
    goal = tst.tree.node("g")
    assert (goal.kind, goal.action, goal.goal_args) == (
        NodeKind.GOAL,
        "delivered",
        ("box1", "Dest"),
    )
    from hdrc3_tst.model import Node

    tst.tree.add(Node("g/1", NodeKind.ACTION, {}, NodeRef("uav0", "g"), action="fly-to"))
    tst.tree.expand("g", NodeKind.SEQUENCE, [NodeRef("uav0", "g/1"), NodeRef("uav1", "x")])
    assert goal.acts_as is NodeKind.SEQUENCE
    assert [n.node_id for _, n in tst.tree.walk("g")] == ["g", "g/1"]  # uav1's node lives elsewhere
    with pytest.raises(TstError, match="already expanded"):
        tst.tree.expand("g", NodeKind.SEQUENCE, [])
    with pytest.raises(TstError, match="only goal and foreach expand"):
        tst.tree.expand("m", NodeKind.SEQUENCE, [])


@pytest.mark.parametrize("path", sorted(EXAMPLES.glob("*.tst")), ids=lambda p: p.name)
def test_every_shipped_example_checks(path: Path) -> None:
    assert load_file(path).status is CheckStatus.OK


def test_a_world_cache_changes_nothing_but_the_loads() -> None:
    worlds = WorldCache()
    for path in sorted(EXAMPLES.glob("*.tst")):
        fresh, cached = load_file(path), load_file(path, worlds=worlds)
        assert cached.status is fresh.status is CheckStatus.OK
        assert fresh.tst is not None and cached.tst is not None
        assert list(tree_lines(cached.tst)) == list(tree_lines(fresh.tst))
    assert 1 <= worlds.loads < len(list(EXAMPLES.glob("*.tst")))


FLY_TO_EACH = (
    "point Dest2 = supply_depot at 25\n"
    "m(P, TS, TE) = with Q foreach X where [TS] point(X) do conc\n"
    "  f(Q, U1, U2) = fly-to(U1, U2, 5, X)\n"
    "where P = uav0 and Q = uav1\n"
)


def test_a_foreach_body_is_a_template_until_instances_are_resolved() -> None:
    tst = ok(FLY_TO_EACH)
    foreach = tst.tree.node("m")
    assert (foreach.children, foreach.template) == ([], "m[*]/f")
    assert [n.node_id for _, n in tst.tree.walk()] == ["m"]  # nobody binds or runs the template
    instance = tst.expand_foreach("m", (("Dest",), ("Dest2",)))
    assert instance.status.value == "ok"
    assert instance.nodes == ("m[Dest]/f", "m[Dest2]/f")
    assert [c.node_id for c in foreach.children] == ["m[Dest]/f", "m[Dest2]/f"]
    assert foreach.acts_as is NodeKind.CONCURRENT
    assert tst.network.values[tst.variable("m[Dest2]/f", "destination")] == "Dest2"
    assert tst.agent_of("m[Dest]/f") == "uav1"  # the head's Q is the foreach's, shared
    window = tst.network.window(tst.variable("m[Dest]/f", "TS"))
    assert window.earliest >= 0.0  # inside the foreach's interval, propagated at once


def test_a_replica_resolves_the_same_instance_from_its_id() -> None:
    owner, replica = ok(FLY_TO_EACH), ok(FLY_TO_EACH)
    owner.expand_foreach("m", (("Dest",), ("Dest2",)))
    made = replica.materialize("m[Dest2]/f")
    assert (made.status.value, made.nodes) == ("ok", ("m[Dest2]/f",))
    assert replica.tree.node("m[Dest2]/f").params == owner.tree.node("m[Dest2]/f").params
    assert replica.tree.node("m").children == []  # the replica does not run the foreach


@pytest.mark.parametrize(
    ("node_id", "reason"),
    [
        ("m[uav0]/f", "'uav0' is not a point"),
        ("m[Dest,Dest2]/f", "m binds 1 variables, got 2 values"),
        ("m[Dest]/g", "no node 'm[Dest]/g'"),
        ("n[Dest]/f", "no node 'n[Dest]/f'"),
    ],
)
def test_a_node_id_naming_no_valid_instance_is_refused(node_id: str, reason: str) -> None:
    made = ok(FLY_TO_EACH).materialize(node_id)
    assert made.status.value == "invalid"
    assert made.reason == reason
