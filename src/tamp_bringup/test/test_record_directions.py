"""scripts/record_directions' library: arguments, the launch and client commands."""
import sys

import pytest

from tamp_bringup.tools import record_directions


def test_defaults_follow_the_drive_test_direction_into_a_run_folder(tmp_path, monkeypatch):
    monkeypatch.setenv("TAMP_WS", str(tmp_path))
    args = record_directions.parse_args([])
    assert args.text == "go straight to the end, then turn left"
    assert args.out_dir.parent == tmp_path / "build" / "directions"
    command = record_directions.launch_command(args, 11411)
    assert command[:5] == ["roslaunch", "-p", "11411", "tamp_bringup", "semantic_nav.launch"]
    assert "floor:=office_ring" in command and "rviz:=false" in command


def test_the_client_gets_the_text_and_the_timeout(tmp_path):
    args = record_directions.parse_args(["turn left", "--timeout", "90",
                                         "--out-dir", str(tmp_path)])
    command = record_directions.client_command(args)
    assert command[:4] == [sys.executable, "-m", "tamp_bringup.ros_directions_client",
                           "turn left"]
    assert command[command.index("--timeout") + 1] == "90"


@pytest.mark.parametrize("option", ["--speed", "--timeout"])
def test_speed_and_timeout_must_be_positive(option, capsys):
    with pytest.raises(SystemExit):
        record_directions.parse_args([option, "0"])
    assert f"{option} must be positive" in capsys.readouterr().err
