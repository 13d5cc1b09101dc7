"""tamp_bringup.bag_record: what a run's bag holds, the recorder's command and its stop, the
robot model kept next to the bag, the replay command, and replay.launch's arguments."""
import os
import signal
import subprocess
import time
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest
import rospkg
from tamp_resources import resource

from tamp_bringup import bag_record

LAUNCH = Path(rospkg.RosPack().get_path("tamp_bringup"), "launch", "replay.launch")


@pytest.mark.parametrize("topics", [bag_record.SCENARIO_TOPICS, bag_record.DIRECTIONS_TOPICS])
def test_a_run_records_what_rviz_draws_and_never_the_clock(topics):
    for topic in ("/tf", "/tf_static", "/scan", "/odom"):
        assert topic in topics
    assert "/clock" not in topics
    assert len(set(topics)) == len(topics)


def test_the_household_bag_has_map_plans_markers_people_and_planner_state():
    for topic in ("/map", "/move_base/plan", "/sim2d/markers", "/task_planner/markers",
                  "/task_planner/state", "/humans/known", "/amcl_pose"):
        assert topic in bag_record.SCENARIO_TOPICS


def test_record_command_drops_the_clock():
    command = bag_record.record_command(Path("/r/run.bag"), ["/tf", "/clock", "/scan"], "rec")
    assert command == ["rec", "--lz4", "-O", "/r/run.bag", "/tf", "/scan", "__name:=run_recorder"]


ROSNODE_INFO = """--------------------------------------------------------------------------------
Node [/run_recorder]
Publications:
 * /rosout [rosgraph_msgs/Log]

Subscriptions:
 * /scan [sensor_msgs/LaserScan]
 * /tf [tf2_msgs/TFMessage]

Services:
 * /run_recorder/get_loggers

contacting node http://localhost:40002/ ...
Pid: 4242
Connections:
 * topic: /rosout
    * to: /rosout
    * direction: outbound (44571 - 127.0.0.1:50100) [12]
    * transport: TCPROS
{scan}
"""
SCAN_CONNECTION = """ * topic: /scan
    * to: /sim2d (http://localhost:41919/)
    * direction: inbound (50102 - localhost:36139) [14]
    * transport: TCPROS"""


@pytest.mark.parametrize("scan, connected", [(SCAN_CONNECTION, True), ("", False),
                                             (SCAN_CONNECTION.replace("/scan", "/scan2"), False)])
def test_the_recording_starts_when_the_recorder_has_an_inbound_connection(
        monkeypatch, scan, connected):
    asked = []

    def rosnode(command, env):
        asked.append(command)
        return ROSNODE_INFO.format(scan=scan)
    monkeypatch.setattr(bag_record, "ros_tool", rosnode)
    assert bag_record.recorder_connected({}, "/scan") is connected
    assert asked == [["rosnode", "info", "/run_recorder"]]


def test_a_subscribed_but_unconnected_or_unanswering_recorder_is_not_recording(monkeypatch):
    monkeypatch.setattr(bag_record, "ros_tool", lambda command, env: None)
    assert not bag_record.recorder_connected({}, "/scan")
    subscribed = ROSNODE_INFO.format(scan="").split("contacting node")[0]   # no connection yet
    monkeypatch.setattr(bag_record, "ros_tool", lambda command, env: subscribed)
    assert not bag_record.recorder_connected({}, "/scan")


def test_the_recorder_is_rosbags_record_program():
    program = Path(bag_record.record_program())
    assert program.name == "record" and os.access(program, os.X_OK)


def test_a_recorder_started_with_sigint_ignored_stops_cleanly(tmp_path):
    """`rosbag record` (the Python wrapper) dies with "TypeError: 'Handlers' object is not
    callable" on SIGINT when it was started with SIGINT ignored; the record program does not."""
    env = bag_record.run_environment(tmp_path, bag_record.free_port())   # no master there
    previous = signal.signal(signal.SIGINT, signal.SIG_IGN)              # inherited by the child
    try:
        recorder = bag_record.start_recorder(tmp_path / "x.bag", ["/tf"], env,
                                             tmp_path / "rosbag.log")
    finally:
        signal.signal(signal.SIGINT, previous)
    time.sleep(1.0)
    bag_record.stop(recorder, timeout_s=20.0)
    log = (tmp_path / "rosbag.log").read_text()
    assert recorder.returncode == 0, log
    assert "Traceback" not in log and "TypeError" not in log


def test_stop_interrupts_a_running_child():
    child = subprocess.Popen(["sleep", "60"])
    bag_record.stop(child, timeout_s=10.0)
    assert child.returncode is not None and child.returncode != 0
    bag_record.stop(None)


def test_run_environment_has_its_own_master_and_ros_home(tmp_path):
    env = bag_record.run_environment(tmp_path, 12345, base={"PATH": "/bin"})
    assert env == {"PATH": "/bin", "ROS_HOME": str(tmp_path),
                   "ROS_LOG_DIR": str(tmp_path / "log"),
                   "ROS_MASTER_URI": "http://localhost:12345", "ROS_HOSTNAME": "localhost"}


def test_wait_until_names_what_did_not_come():
    with pytest.raises(bag_record.RecordError, match="no ROS master within 0 s"):
        bag_record.wait_until(lambda: False, None, 0.0, "ROS master")
    ended = subprocess.Popen(["true"])
    ended.wait()
    with pytest.raises(bag_record.RecordError, match=r"^true ended \(status 0\) before ROS master"):
        bag_record.wait_until(lambda: False, ended, 10.0, "ROS master")


def test_robot_description_is_kept_next_to_the_bag(tmp_path):
    bag = tmp_path / "run.bag"
    assert bag_record.description_path(bag) == tmp_path / "run.urdf"
    assert bag_record.robot_description(bag) == ""
    (tmp_path / "run.urdf").write_text("<robot name='r'/>")
    assert bag_record.robot_description(bag) == "<robot name='r'/>"


def test_replay_command_names_the_bag_and_the_view(monkeypatch):
    monkeypatch.setenv("TAMP_WS", "/ws")
    assert (bag_record.replay_command(Path("/ws/build/demo/run.bag"))
            == "roslaunch tamp_bringup replay.launch bag:=$TAMP_WS/build/demo/run.bag")
    assert (bag_record.replay_command(Path("/b/run.bag"))
            == "roslaunch tamp_bringup replay.launch bag:=/b/run.bag")
    assert bag_record.replay_command("/b/d.bag", "semantic_nav").endswith(
        "bag:=/b/d.bag view:=semantic_nav")
    assert "bag:='/a b/run.bag'" in bag_record.replay_command("/a b/run.bag")
    with pytest.raises(ValueError):
        bag_record.replay_command("/b/run.bag", "nope")


def test_replay_launch_documents_every_argument_and_offers_every_view():
    root = ET.parse(LAUNCH).getroot()
    args = {arg.get("name"): arg for arg in root.iter("arg")}
    assert {"bag", "view", "config", "rate", "start", "rviz"} <= set(args)
    assert all(arg.get("doc") for arg in args.values())
    assert all(arg.get("default") for name, arg in args.items() if name != "bag")
    for view in bag_record.VIEWS:
        assert view in args["view"].get("doc")
        assert resource("config", "rviz", f"{view}.rviz").is_file()
    play = next(node for node in root.iter("node") if node.get("type") == "play")
    assert "--clock" in play.get("args").split()
    assert any(p.get("name") == "use_sim_time" and p.get("value") == "true"
               for p in root.iter("param"))
