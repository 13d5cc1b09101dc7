"""Runs recorded as rosbags that rviz can replay (`launch/replay.launch`), and the launches they
come from, each on its own roscore port.

The bag of a run holds what the run's rviz view draws (tf, tf_static, the map, the laser,
odometry, plans, markers, people) and what the robot was told and decided, in the simulator's
time; never `/clock`, which `rosbag play --clock` publishes from the bag's own times. Topic names
are those of the launch files in the root namespace (`rostopic list` on a running launch).

ROS-free: the recorder is rosbag's `record` program run as a child process, and the master is
asked through the ROS command-line tools. `record` is run directly, not through the `rosbag
record` Python wrapper: that wrapper passes SIGINT on and then calls the SIGINT handler it
replaced, which is `signal.Handlers.SIG_IGN` when it was started with SIGINT ignored (a
background job of a non-interactive shell, `nohup`), and it then dies with
`TypeError: 'Handlers' object is not callable`. `record` handles SIGINT itself (it closes the
bag) whatever it inherited.
"""
import contextlib
import os
import shlex
import signal
import socket
import subprocess
import tempfile
import time
from pathlib import Path

import yaml

# what replay.launch's social_household view (config/rviz/social_household.rviz) draws, and what
# the robot was told, believed, decided and said (launch/social_household.launch); not the camera's
# detections, the speech audio or the logs
SCENARIO_TOPICS = (
    "/tf", "/tf_static", "/map", "/map_metadata", "/scan", "/odom", "/base_pose_ground_truth",
    "/amcl_pose", "/initialpose", "/cmd_vel", "/stall", "/sim2d/markers",
    "/move_base/goal", "/move_base/result", "/move_base/status", "/move_base/feedback",
    "/move_base/cancel", "/move_base/plan", "/move_base_simple/goal",
    "/task_planner/instructions", "/task_planner/state", "/task_planner/markers",
    "/task_planner/activity", "/task_planner/tree", "/humans/known", "/humans/observed",
    "/robot/say", "/voice_message", "/introduction/dialogue_open", "/diagnostics")
# what replay.launch's semantic_nav view (config/rviz/semantic_nav.rviz) draws, the Penguin's
# base (penguin_sim.launch) and the direction and its action (launch/semantic_nav.launch)
DIRECTIONS_TOPICS = (
    "/tf", "/tf_static", "/scan", "/odom", "/base_pose_ground_truth", "/cmd_vel",
    "/wheel_command", "/joint_states", "/stall", "/sim2d/markers",
    "/semantic_nav/path", "/semantic_nav/doorways",
    "/follow_directions/goal", "/follow_directions/feedback", "/follow_directions/result",
    "/follow_directions/status", "/voice_message", "/robot/say", "/diagnostics")
NEVER_RECORDED = ("/clock",)   # `rosbag play --clock` publishes the bag's own clock
RECORDER_NODE = "/run_recorder"   # the recorder's node name (record_command's __name)
VIEWS = ("social_household", "semantic_nav", "sim")   # replay.launch's view:= (rviz configs)
STOP_TIMEOUT_S = 30.0    # [s] SIGINT grace before a child is killed
POLL_S = 0.5             # [s] period of the waits on the master
TOOL_TIMEOUT_S = 10.0    # [s] longest a rostopic / rosparam query may take


class RecordError(RuntimeError):
    """A run could not be started or recorded; the message says why and what to do."""


def free_port():
    """A free TCP port on localhost, for a run's own roscore."""
    with socket.socket() as s:
        s.bind(("localhost", 0))
        return s.getsockname()[1]


def run_environment(run_dir, port, base=None):
    """The environment of a run: its own ROS_HOME (logs) and master port."""
    return dict(os.environ if base is None else base, ROS_HOME=str(run_dir),
                ROS_LOG_DIR=str(run_dir / "log"), ROS_MASTER_URI=f"http://localhost:{port}",
                ROS_HOSTNAME="localhost")


def stop(process, timeout_s=STOP_TIMEOUT_S):
    """SIGINT a running child, then kill it when it has not ended within `timeout_s`."""
    if process is not None and process.poll() is None:
        process.send_signal(signal.SIGINT)
        try:
            process.wait(timeout_s)
        except subprocess.TimeoutExpired:
            process.kill()
            process.wait()


def record_program():
    """rosbag's recorder, the program behind `rosbag record`."""
    from roslib.packages import find_node    # roslib: package paths only, no rospy
    found = find_node("rosbag", "record")
    if not found:
        raise RecordError("rosbag's record program was not found; install ROS 1's rosbag "
                          "(scripts/setup)")
    return found[0]


def record_command(bag, topics, program="record"):
    """The command line that records `topics` (never /clock) into `bag`, LZ4-compressed (the
    markers and odometry shrink to about a third; rosbag play and rosbag's Python API read it)."""
    kept = [topic for topic in topics if topic not in NEVER_RECORDED]
    return [program, "--lz4", "-O", str(bag), *kept, f"__name:={RECORDER_NODE[1:]}"]


def start_recorder(bag, topics, env, log_path):
    """Start recording `topics` into `bag` (written as `bag.active` until stopped); its output
    goes to `log_path`. Stop it with `stop` (SIGINT: it closes the bag)."""
    with open(log_path, "w") as log:
        return subprocess.Popen(record_command(bag, topics, record_program()), env=env,
                                stdout=log, stderr=subprocess.STDOUT)


def ros_tool(command, env, timeout_s=TOOL_TIMEOUT_S):
    """stdout of a ROS command-line tool, or None when it fails or takes too long."""
    try:
        done = subprocess.run(command, env=env, capture_output=True, text=True,
                              timeout=timeout_s)
    except subprocess.TimeoutExpired:
        return None
    return done.stdout if done.returncode == 0 else None


def wait_until(check, process, timeout_s, what):
    """Poll `check()` until it is true; RecordError when the process it depends on (a launch,
    the recorder) ends or time runs out."""
    deadline = time.monotonic() + timeout_s
    while not check():
        if process is not None and process.poll() is not None:
            name = Path(str(process.args[0])).name if getattr(process, "args", None) else "it"
            raise RecordError(f"{name} ended (status {process.returncode}) before {what}")
        if time.monotonic() > deadline:
            raise RecordError(f"no {what} within {timeout_s:.0f} s")
        time.sleep(POLL_S)


def wait_for_master(env, launch, timeout_s=60.0):
    wait_until(lambda: ros_tool(["rostopic", "list"], env) is not None, launch, timeout_s,
               "ROS master")


@contextlib.contextmanager
def own_roscore(timeout_s=60.0):
    """A roscore on a free port with a temporary ROS_HOME, until the block ends -> the
    environment of its clients (run_environment)."""
    with tempfile.TemporaryDirectory() as home:
        env = run_environment(Path(home), free_port())
        core = subprocess.Popen(["roscore", "-p", env["ROS_MASTER_URI"].rsplit(":", 1)[1]],
                                env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        try:
            wait_for_master(env, core, timeout_s)
            yield env
        finally:
            stop(core)


def wait_for_sim_time(env, launch, timeout_s=60.0):
    """Wait until the launch has set /use_sim_time: a recorder started before then would stamp
    the bag with wall-clock time, and the simulator's stamps would not replay."""
    def sim_time_set():
        value = ros_tool(["rosparam", "get", "/use_sim_time"], env)
        return value is not None and value.strip() == "true"
    wait_until(sim_time_set, launch, timeout_s, "/use_sim_time set")


def sim_time_s(env, timeout_s=TOOL_TIMEOUT_S):
    """The simulator's time [s] (one /clock message), or None before it has started."""
    text = ros_tool(["rostopic", "echo", "-n", "1", "/clock"], env, timeout_s)
    if not text:
        return None
    try:
        clock = yaml.safe_load(text.split("---")[0])["clock"]
        return clock["secs"] + clock["nsecs"] * 1e-9
    except (yaml.YAMLError, KeyError, TypeError):
        return None


def recorder_connected(env, topic):
    """Whether the recorder (RECORDER_NODE) has an inbound connection on `topic` (`rosnode
    info`): from then on it receives the topic's messages; a subscription alone is only a
    registration with the master."""
    text = ros_tool(["rosnode", "info", RECORDER_NODE], env)
    if not text or "Connections:" not in text:
        return False
    for block in text.split("Connections:", 1)[1].split(" * topic: ")[1:]:
        lines = block.splitlines()
        if lines[0].strip() == topic and any("direction: inbound" in line for line in lines):
            return True
    return False


def wait_for_recording(env, recorder, topic, timeout_s=120.0):
    """Wait until the recorder receives `topic` (a recorder starting on a loaded machine can
    take seconds); RecordError when it ends or the (hang-guard) time runs out."""
    wait_until(lambda: recorder_connected(env, topic), recorder, timeout_s,
               f"recorder connection to {topic}")


def wait_for_sim_seconds(env, seconds, launch, timeout_s=300.0):
    """Wait until the simulator's clock has advanced `seconds` from now: a recording of a
    given length in simulated time, however slowly a loaded machine runs the simulator."""
    start = []

    def advanced():
        now = sim_time_s(env)
        if now is None:
            return False
        start[:] = start or [now]
        return now - start[0] >= seconds
    wait_until(advanced, launch, timeout_s, f"{seconds:g} s of simulated time")


def description_path(bag):
    """Where the robot model (URDF) of a run sits next to its bag: run.bag -> run.urdf."""
    bag = Path(bag)
    return bag.with_name(bag.name.removesuffix(".bag") + ".urdf")


def save_robot_description(bag, env):
    """Keep the run's /robot_description (the URDF rviz's RobotModel draws) next to `bag`, for
    replay.launch; the path, or None when the run sets none."""
    text = ros_tool(["rosparam", "get", "/robot_description"], env)
    try:
        urdf = yaml.safe_load(text) if text else None
    except yaml.YAMLError:
        urdf = None
    if not isinstance(urdf, str) or not urdf.strip():
        return None
    path = description_path(bag)
    path.write_text(urdf)
    return path


def robot_description(bag):
    """The URDF kept next to `bag` (save_robot_description), or "" when there is none."""
    path = description_path(bag)
    return path.read_text() if path.is_file() else ""


def replay_command(bag, view="social_household"):
    """The command that replays `bag` in rviz with the given view (VIEWS). A bag inside the
    workspace is named from $TAMP_WS (set by scripts/env.sh), so the command works in any
    checkout."""
    if view not in VIEWS:
        raise ValueError(f"unknown view {view!r}; one of {', '.join(VIEWS)}")
    where = shlex.quote(str(bag))
    workspace = os.environ.get("TAMP_WS")
    if workspace and Path(bag).is_relative_to(workspace):
        where = "$TAMP_WS/" + shlex.quote(str(Path(bag).relative_to(workspace)))
    command = f"roslaunch tamp_bringup replay.launch bag:={where}"
    return command if view == "social_household" else f"{command} view:={view}"
