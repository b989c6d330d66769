from __future__ import annotations

from hdrc3_deliberative.result import Occurrence
from hdrc3_deliberative.tst_export import TstNodeKind, plan_to_tst


def test_concurrent_node_over_agent_sequences() -> None:
    plan = (
        Occurrence(0, 10, "fly-to", ("h1", "a", "b"), "h1"),
        Occurrence(0, 5, "fly-to", ("h2", "a", "c"), "h2"),
        Occurrence(10, 20, "drop-box", ("h1", "x", "b"), "h1"),
    )
    tree = plan_to_tst(plan)
    assert tree.kind is TstNodeKind.CONCURRENT
    assert [c.agent for c in tree.children] == ["h1", "h2"]
    assert all(c.kind is TstNodeKind.SEQUENCE for c in tree.children)
    assert [o.name for o in tree.children[0].elementary()] == ["fly-to", "drop-box"]
    assert sorted(tree.elementary(), key=lambda o: (o.start, o.agent or "")) == sorted(
        plan, key=lambda o: (o.start, o.agent or "")
    )
    as_dict = tree.to_dict()
    assert as_dict["type"] == "concurrent"
    assert as_dict["children"][0]["children"][1] == {
        "type": "elementary",
        "agent": "h1",
        "action": "drop-box",
        "args": ["h1", "x", "b"],
        "start": 10,
        "end": 20,
    }


def test_single_agent_is_a_sequence() -> None:
    tree = plan_to_tst((Occurrence(0, 1, "a", ()), Occurrence(1, 2, "b", ())))
    assert tree.kind is TstNodeKind.SEQUENCE and tree.agent == "unassigned"
