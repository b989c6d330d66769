"""Bad input to the `hdrc3` command: one line naming the problem, non-zero exit, no traceback."""

from pathlib import Path

import pytest

from hdrc3.cli.main import main
from hdrc3_base.ros_env import PROFILES_VARS, discovery_profile


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["launch", "--agents", "UAV 0"], "invalid agent name"),
        (["launch", "--nodes", "pilot"], "unknown node 'pilot'"),
        (["launch", "--speed", "0"], "invalid --speed"),
        (["launch", "--domain-id", "500"], "invalid --domain-id 500"),
        (["launch", "--record", "/nonexistent-dir/x.mcap"], "does not exist"),
        (["replay", "{tmp}/missing.mcap"], "no such recording"),
        (["replay", "{tmp}/garbage.mcap"], "not an MCAP file"),
        (["replay", "{tmp}/garbage.mcap", "--speed", "-1"], "invalid --speed"),
        (["record", "{tmp}/out.txt"], "must end in .mcap"),
        (["record", "{tmp}/out.mcap", "--duration", "0"], "--duration must be positive"),
        (["rc", "UAV 0", "--engine", "on"], "invalid agent name"),
        (["launch", "--live-port", "70000"], "invalid --live-port 70000"),
        (["live", "--world", "atlantis"], "unknown world 'atlantis'"),
        (["live", "--domain-id", "500"], "invalid --domain-id 500"),
        (["record", "{tmp}/out.mcap", "--live-channels", "--world", "atlantis"], "unknown world"),
    ],
)
def test_bad_input_is_one_line_and_exit_2(tmp_path: Path, capsys, argv, message) -> None:
    (tmp_path / "garbage.mcap").write_text("not a recording")
    code = main([a.replace("{tmp}", str(tmp_path)) for a in argv])
    err = capsys.readouterr().err
    assert code == 2
    assert message in err
    assert len(err.strip().splitlines()) == 1
    assert "Traceback" not in err


def test_replay_names_a_topic_missing_from_the_recording(tmp_path: Path, capsys) -> None:
    from hdrc3.mcap_recording import RecordingWriter, TopicInfo

    path = tmp_path / "r.mcap"
    writer = RecordingWriter(path)
    writer.add_topic(TopicInfo("/a", "std_msgs/msg/String"))
    writer.write("/a", b"\x00\x01\x00\x00\x01\x00\x00\x00\x00", 1)
    writer.close()
    assert main(["replay", str(path), "--topics", "/b"]) == 2
    assert "topic /b is not in the recording; it has: /a" in capsys.readouterr().err


def test_doctor_reports_a_healthy_installation(capsys, monkeypatch) -> None:
    for var in PROFILES_VARS:
        monkeypatch.delenv(var, raising=False)
    assert main(["doctor", "--no-selftest"]) == 0
    out = capsys.readouterr().out
    assert "rmw implementation  rmw_fastrtps_cpp" in out
    assert "import hdrc3_interfaces.msg" in out and "healthy" in out
    assert f"FASTRTPS_DEFAULT_PROFILES_FILE {discovery_profile()}" in out  # main applied it


@pytest.mark.parametrize(
    ("argv", "expected"),
    [
        (["--nodes", "world_sim"], ("system_monitor", "world_sim")),
        (["--nodes", "world_sim", "--live"], ("system_monitor", "world_sim", "live_view")),
        (["--nodes", "live_view", "--live"], ("system_monitor", "live_view")),
        (["--nodes", "world_sim", "--live-port", "9000", "--cameras"],
         ("system_monitor", "world_sim", "world_render", "saliency", "pad_pose", "live_view")),
    ],
)  # fmt: skip
def test_launch_flags_add_their_nodes_once(argv: list[str], expected: tuple[str, ...]) -> None:
    from hdrc3.cli.launch import options_from
    from hdrc3.cli.main import build_parser

    args = build_parser().parse_args(["launch", *argv])
    assert options_from(args).nodes == expected
