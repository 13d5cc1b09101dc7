"""scripts/run_scenario's and scripts/scenario_report's libraries: arguments, the launch command,
the summary lines, stopping a child."""
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest
from tamp_resources import resource

from tamp_bringup.tools import run_scenario, scenario_report
from tamp_bringup.scenario import load_scenario

SCRIPTS = Path(os.environ["TAMP_WS"]) / "scripts"
RESULT = {"requests": 3, "served": 2, "failed": 1, "instructions": 4,
          "states": {"done": 3, "failed": 1}, "reward": 1.23456,
          "model": {"FCFS (model)": 0.5, "Ours(seed/node) (model)": 1.0},
          "order_problems": ["x before y"], "belief": {"Alice": 0.5, "Bob": 1.0},
          "searches": 2, "sources": {"perception": 10, "register": 1}}


def test_summary_lines_of_a_report():
    assert scenario_report.summary_lines(RESULT, Path("out")) == [
        "requests 3: served 2, failed 1; instructions 4 {'done': 3, 'failed': 1}",
        "reward of the run 1.235; model on the same arrivals: FCFS (model) 0.500, "
        "Ours(seed/node) (model) 1.000",
        "order: x before y",
        "belief accuracy: mean 0.75 (Alice 0.50, Bob 1.00); searches 2",
        "human_db history rows by source: perception 10, register 1",
        "report: out/REPORT.md"]


def test_summary_lines_end_with_the_replay_command():
    lines = scenario_report.summary_lines(dict(RESULT, replay="roslaunch x"), "out")
    assert lines[-2:] == ["report: out/REPORT.md", "replay in rviz: roslaunch x"]


def test_summary_lines_leave_out_empty_belief_and_sources():
    result = dict(RESULT, order_problems=[], belief={}, sources={})
    lines = scenario_report.summary_lines(result, "out")
    assert len(lines) == 3 and lines[-1] == "report: out/REPORT.md"


def test_report_arguments_name_missing_files(tmp_path, capsys):
    record = tmp_path / "record.json"
    record.write_text("{}")
    with pytest.raises(SystemExit):
        scenario_report.parse_args([str(record), str(tmp_path / "tasks.sqlite")])
    assert f"journal: no such file: {tmp_path / 'tasks.sqlite'}" in capsys.readouterr().err


def test_report_arguments_of_a_run_directory_parse(tmp_path):
    for name in ("record.json", "social_household_tasks.sqlite",
                 "social_household_humans.sqlite"):
        (tmp_path / name).write_text("")
    args = scenario_report.parse_args(
        run_scenario.report_arguments(tmp_path, tmp_path / "report"))
    assert args.record == tmp_path / "record.json"
    assert args.humans == tmp_path / "social_household_humans.sqlite"
    assert args.out_dir == tmp_path / "report" and args.exact_limit_s == 60.0


def test_report_arguments_name_the_bag(tmp_path):
    arguments = run_scenario.report_arguments(tmp_path, tmp_path / "r", tmp_path / "run.bag")
    assert arguments[-2:] == ["--bag", str(tmp_path / "run.bag")]


def test_a_run_goes_to_a_run_folder_under_build(tmp_path, monkeypatch):
    monkeypatch.setenv("TAMP_WS", str(tmp_path))
    args = run_scenario.parse_args([])
    assert args.out_dir.parent == tmp_path / "build" / "scenario"
    assert args.run_dir == args.out_dir / "run"
    args = run_scenario.parse_args(["--out-dir", str(tmp_path / "o"),
                                    "--run-dir", str(tmp_path / "r")])
    assert (args.out_dir, args.run_dir) == (tmp_path / "o", tmp_path / "r")


def test_launch_command_carries_the_scenario_and_the_switches(tmp_path):
    path = resource("config", "scenarios", "household_short.yaml")
    scenario = load_scenario(path)
    args = run_scenario.parse_args([str(path), "--speed", "2.5", "--no-patrol"])
    command = run_scenario.launch_command(args, scenario, path, tmp_path, 11311)
    assert command[:5] == ["roslaunch", "-p", "11311", "tamp_bringup", "social_household.launch"]
    assert "speed:=2.5" in command and "patrol:=false" in command
    assert "self_instructions:=true" in command and "rviz:=false" in command
    assert f"record:={tmp_path / 'record.json'}" in command
    assert f"planner:={scenario.planner}" in command
    assert f"command:=scripts/run_scenario {path} --speed 2.5" in command
    assert "shirts:=none" in command      # nobody met: the robot asks each resident (§3.2.3)


def test_a_fleet_run_launches_two_robots_and_reports_both_journals(tmp_path):
    path = resource("config", "scenarios", "household_day.yaml")
    args = run_scenario.parse_args([str(path), "--fleet"])
    command = run_scenario.launch_command(args, load_scenario(path), path, tmp_path, 11311)
    assert command[4] == "household_fleet.launch"
    assert f"world:={resource('config', 'worlds', 'household_fleet.yaml')}" in command
    assert f"command:=scripts/run_scenario {path} --speed 5 --fleet" in command
    for name in ("record.json", "robot1_task_buffer.sqlite", "robot2_task_buffer.sqlite",
                 "household_fleet_humans.sqlite"):
        (tmp_path / name).write_text("")
    report = scenario_report.parse_args(
        run_scenario.report_arguments(tmp_path, tmp_path / "r", fleet=True))
    assert report.journal == [tmp_path / "robot1_task_buffer.sqlite",
                              tmp_path / "robot2_task_buffer.sqlite"]
    assert report.humans == tmp_path / "household_fleet_humans.sqlite"


def test_speed_must_be_positive(capsys):
    with pytest.raises(SystemExit):
        run_scenario.parse_args(["--speed", "0"])
    assert "--speed must be positive" in capsys.readouterr().err


def test_stop_interrupts_a_running_child():
    child = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(60)"])
    run_scenario.stop(child, timeout_s=10.0)
    assert child.returncode is not None and child.returncode != 0
    run_scenario.stop(None)               # nothing started: nothing to do


def test_a_run_folder_is_emptied_of_an_earlier_run_and_a_foreign_one_refused(tmp_path):
    run = tmp_path / "run"
    (run / "log" / "latest").mkdir(parents=True)
    for name in ("robot1_task_buffer.sqlite", "robot1_task_buffer.sqlite-wal",
                 "fleet_pool.sqlite", "record.json", "launch.log", "run.bag", "run.urdf"):
        (run / name).write_text("an earlier day")
    run_scenario.fresh_run_dir(run)
    assert list(run.iterdir()) == []
    (run / "notes.txt").write_text("mine")
    (run / "record.json").write_text("an earlier day")
    with pytest.raises(ValueError, match=r"--run-dir .*run holds files no run writes "
                                         r"\(notes.txt\): give an empty or new folder"):
        run_scenario.fresh_run_dir(run)
    assert sorted(p.name for p in run.iterdir()) == ["notes.txt", "record.json"]  # untouched
    run_scenario.fresh_run_dir(tmp_path / "new")
    assert (tmp_path / "new").is_dir()


@pytest.mark.parametrize("text, message", [
    (None, r"^run_scenario: error: \S*nowhere.yaml: no such scenario file$"),
    ("requests: [\n", r"^run_scenario: error: \S*bad.yaml: not valid YAML \(line 2, column 1: "),
    ("BROKEN_PERSON", r"^run_scenario: error: \S*bad.yaml: request 1: unknown person 'Zed' "),
])
def test_a_user_mistake_is_one_line_and_exit_status_2(tmp_path, text, message):
    if text is None:
        path = tmp_path / "nowhere.yaml"
    else:
        path = tmp_path / "bad.yaml"
        path.write_text(text if text != "BROKEN_PERSON" else resource(
            "config", "scenarios", "household_short.yaml").read_text().replace(
            "person: Alice", "person: Zed", 1))
    done = subprocess.run([sys.executable, str(SCRIPTS / "run_scenario"), str(path)],
                          capture_output=True, text=True, timeout=120)
    assert done.returncode == 2, done.stderr
    assert done.stderr.count("\n") == 1 and done.stdout == "", done.stderr
    assert re.match(message, done.stderr), done.stderr
    debug = subprocess.run([sys.executable, str(SCRIPTS / "run_scenario"), str(path), "--debug"],
                           capture_output=True, text=True, timeout=120)
    assert debug.returncode == 1 and "Traceback (most recent call last)" in debug.stderr


def test_a_fleet_run_passes_its_postgresql_pool_and_records_it_without_the_password(tmp_path):
    args = run_scenario.parse_args(["--fleet", "--pool", "postgresql://u:pw@127.0.0.1/f",
                                    "--out-dir", str(tmp_path)])
    scenario = load_scenario(resource("config", "scenarios", "household_short.yaml"))
    command = run_scenario.launch_command(args, scenario, "s.yaml", tmp_path, 11311)
    assert "pool:=postgresql://u:pw@127.0.0.1/f" in command
    assert any(part.startswith("command:=") and part.endswith("--fleet --pool "
                                                              "postgresql://u:***@127.0.0.1/f")
               for part in command)
    for argv in (["--pool", "postgresql://h/f"], ["--fleet", "--pool", "/tmp/pool.sqlite"]):
        with pytest.raises(SystemExit):
            run_scenario.parse_args(argv)
