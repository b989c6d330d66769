from pathlib import Path

import pytest

from hdrc3_platform_server.journal import CommandJournal


def test_without_a_file_nothing_is_known_of_earlier_runs() -> None:
    journal = CommandJournal(None)
    journal.accepted(7, "fcl_yaw")
    assert journal.earlier is None and journal.open_ids() == {7: "fcl_yaw"}


@pytest.mark.parametrize(
    "text",
    [None, "", "{", "[]", '{"open": 3}', '{"open": {"x": "fcl_yaw"}}', '{"other": {}}'],
    ids=["missing", "empty", "truncated", "list", "not_a_map", "bad_id", "foreign"],
)
def test_an_unreadable_file_is_an_empty_journal(tmp_path: Path, text: str | None) -> None:
    path = tmp_path / "j.checkpoint"
    if text is not None:
        path.write_text(text)
    assert CommandJournal(path).earlier == {}


def test_open_ids_survive_a_restart_until_their_terminal_event(tmp_path: Path) -> None:
    path = tmp_path / "j.checkpoint"
    first = CommandJournal(path)
    first.accepted(11, "fcl_takeoff")
    first.accepted(12, "ppcl_turn_to")
    first.ended(11)
    first.ended(13)  # ended before its answer (fcl_cancel): never open ...
    first.accepted(13, "fcl_cancel")
    assert first.open_ids() == {12: "ppcl_turn_to"}
    second = CommandJournal(path)
    assert second.earlier == {12: "ppcl_turn_to"}
    second.accepted(21, "fcl_yaw")
    assert CommandJournal(path).earlier == {12: "ppcl_turn_to", 21: "fcl_yaw"}
    second.ended(12)
    second.ended(21)
    assert CommandJournal(path).earlier == {}
    assert not path.with_name(path.name + ".tmp").exists()
