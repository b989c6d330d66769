"""TaskTree.expand: which nodes get children at run time, and what they then act as."""

from __future__ import annotations

import pytest

from hdrc3_tst.errors import TstError
from hdrc3_tst.model import EXPANDS_AS, Node, NodeKind, NodeRef, TaskTree

CHILDREN = [NodeRef("uav0", "c1"), NodeRef("uav1", "c2")]


def tree(kind: NodeKind) -> TaskTree:
    t = TaskTree("n")
    t.add(Node("n", kind, {}))
    return t


@pytest.mark.parametrize(
    ("kind", "mode"), [(k, m) for k, modes in EXPANDS_AS.items() for m in modes]
)
def test_goal_and_foreach_expand_and_then_act_as_their_mode(kind: NodeKind, mode: NodeKind) -> None:
    t = tree(kind)
    t.expand("n", mode, CHILDREN)
    assert t.node("n").acts_as is mode and t.node("n").children == CHILDREN
    with pytest.raises(TstError, match="already expanded"):
        t.expand("n", mode, [])


@pytest.mark.parametrize(
    ("kind", "mode", "words"),
    [
        (NodeKind.SEQUENCE, NodeKind.SEQUENCE, "only goal and foreach expand"),
        (NodeKind.ACTION, NodeKind.CONCURRENT, "only goal and foreach expand"),
        (NodeKind.GOAL, NodeKind.IF, "a goal expands as sequence or concurrent, not if"),
        (NodeKind.FOREACH, NodeKind.SEQUENCE, "a foreach expands as concurrent, not sequence"),
    ],
)
def test_misuse_raises(kind: NodeKind, mode: NodeKind, words: str) -> None:
    t = tree(kind)
    with pytest.raises(TstError, match=words):
        t.expand("n", mode, CHILDREN)
    assert t.node("n").expanded_as is None
